// Strands in the camera pass, into weighted blended order-independent
// transparency (McGuire and Bavoil 2013): target 0 sums colour x alpha x
// weight and alpha x weight, target 1 sums -ln(1 - alpha), so that the
// composite knows the total coverage 1 - prod(1 - alpha) exactly and the
// colour as a weighted mean that favours the strands in front. The weight
// falls off over the hair's own depth range (u_depth_range), not the whole
// view's, so front strands win among strands millimetres apart.
in vec3 v_world;
in float v_alpha;
in vec3 v_color;
uniform vec3 u_eye;
uniform vec2 u_depth_range;  // eye distance of the hair's nearest and farthest point
uniform float u_depth_falloff;
layout(location = 0) out vec4 o_accum;
layout(location = 1) out vec4 o_reveal;
void main() {
  float a = clamp(v_alpha, 0.0, 0.98);
  if (a < 1e-4) discard;
  vec3 c = v_color;
  float t = clamp((length(v_world - u_eye) - u_depth_range.x) / max(1e-4, u_depth_range.y - u_depth_range.x), 0.0, 1.0);
  float w = a * exp(-u_depth_falloff * t);
  o_accum = vec4(c * w, w);
  o_reveal = vec4(-log(1.0 - a), 0.0, 0.0, 0.0);
}
