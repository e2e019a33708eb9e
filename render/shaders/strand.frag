// Strands in the camera pass, into weighted blended order-independent
// transparency (McGuire and Bavoil 2013): target 0 sums colour x alpha x
// weight and alpha x weight, target 1 sums -ln(1 - alpha), so that the
// composite knows the total coverage 1 - prod(1 - alpha) exactly and the
// colour as a weighted mean that favours the strands in front. The weight
// falls off over the hair's own depth range (u_depth_range), not the whole
// view's, so front strands win among strands millimetres apart.
// The weight and -ln(1 - alpha) are the vertex shader's (strand.vert,
// SHADE): they vary slowly along a strand, and a software rasteriser spends
// a strand frame on its fragments.
in vec4 v_weighted;  // colour x weight, weight
in float v_reveal;
layout(location = 0) out vec4 o_accum;
layout(location = 1) out vec4 o_reveal;
void main() {
  o_accum = v_weighted;
  o_reveal = vec4(v_reveal, 0.0, 0.0, 0.0);
}
