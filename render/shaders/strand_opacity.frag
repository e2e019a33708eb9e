// Pass 1 for strands: each strand fragment's coverage, into the slices.
in vec3 v_light;
in float v_alpha;
void main() { writeSlices(v_alpha, v_light); }
