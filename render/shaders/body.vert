#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_model, u_view_proj, u_light_coords;
out vec3 v_world;
out vec3 v_normal;
out vec3 v_light;
void main() {
  vec4 w = u_model * vec4(a_pos, 1.0);
  v_world = w.xyz;
  v_normal = mat3(u_model) * a_normal;
  // looked up a little off the surface, so the skin does not shadow itself
  v_light = (u_light_coords * vec4(w.xyz + 0.002 * normalize(v_normal), 1.0)).xyz;
  gl_Position = u_view_proj * w;
}
