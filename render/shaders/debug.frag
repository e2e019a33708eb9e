#version 330 core
in float v_value;
uniform vec2 u_range;
uniform vec3 u_flat;
uniform int u_use_flat;
out vec4 o_color;
void main() {
  if (u_use_flat == 1) { o_color = vec4(u_flat, 1.0); return; }
  float t = clamp((v_value - u_range.x) / max(u_range.y - u_range.x, 1e-9), 0.0, 1.0);
  // blue -> cyan -> yellow -> red
  vec3 c = t < 0.5 ? mix(vec3(0.1, 0.2, 0.9), vec3(0.1, 0.9, 0.9), t * 2.0)
                   : mix(vec3(0.95, 0.9, 0.1), vec3(0.9, 0.1, 0.1), t * 2.0 - 1.0);
  o_color = vec4(c, 1.0);
}
