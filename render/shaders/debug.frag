#version 330 core
in float v_value;
uniform vec2 u_range;
uniform vec3 u_flat;
uniform int u_use_flat;
uniform vec3 u_ramp[4];  // blue, cyan | yellow, red (render::debugRamp)
out vec4 o_color;
void main() {
  if (u_use_flat == 1) { o_color = vec4(u_flat, 1.0); return; }
  float t = clamp((v_value - u_range.x) / max(u_range.y - u_range.x, 1e-9), 0.0, 1.0);
  vec3 c = t < 0.5 ? mix(u_ramp[0], u_ramp[1], t * 2.0) : mix(u_ramp[2], u_ramp[3], t * 2.0 - 1.0);
  o_color = vec4(c, 1.0);
}
