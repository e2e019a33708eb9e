uniform vec3 u_light, u_color, u_spec_color;
uniform float u_ambient;
out vec3 v_lit;
vec3 shade(vec3 T, vec3 world) {
  vec2 k = kajiyaKay(T, normalize(u_light), normalize(u_eye - world));
  v_lit = u_color * k.x + u_spec_color * k.y;
  return u_color * u_ambient;
}
