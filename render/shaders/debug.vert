// Debug views: points coloured by a value, and lines.
#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in float a_value;
uniform mat4 u_view_proj;
uniform float u_point_size;
out float v_value;
void main() {
  v_value = a_value;
  gl_PointSize = u_point_size;
  gl_Position = u_view_proj * vec4(a_pos, 1.0);
}
