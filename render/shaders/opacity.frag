// Pass 1 for billboards: the strand texture's alpha, into the slices.
in vec2 v_uv;
flat in int v_level;
in vec3 v_light;  // z: position in slices
in float v_alpha;
uniform sampler2D u_hair;
void main() {
  ivec2 size = textureSize(u_hair, v_level);
  float a = texelFetch(u_hair, min(ivec2(v_uv * vec2(size)), size - 1), v_level).a * v_alpha;
  if (a < 1e-4) discard;
  writeSlices(a, v_light);
}
