#version 330 core
// The strands' weighted blended transparency over the opaque picture: the
// weighted mean colour with coverage 1 - prod(1 - alpha) = 1 - exp(-sum).
in vec2 v_uv;
uniform sampler2D u_accum, u_reveal;
out vec4 o_color;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 acc = texelFetch(u_accum, p, 0);
  float coverage = 1.0 - exp(-texelFetch(u_reveal, p, 0).r);
  if (coverage < 1e-4) discard;
  o_color = vec4(acc.rgb / max(acc.a, 1e-8), coverage);
}
