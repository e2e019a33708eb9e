// Billboard geometry (method.md §7.1), shared by both passes: the vertical axis is
// the hair direction made perpendicular to the projection direction d, whose
// length is foreshortened by sin(phi); opacity is boosted by 1/sin(phi).
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_dir;
layout(location = 2) in float a_value;
uniform mat4 u_view_proj;
uniform vec3 u_proj_dir;   // (u_eye, the perspective eye, is declared before)   // orthographic: projection direction
uniform int u_ortho;
uniform float u_width, u_length, u_max_boost, u_opacity;
uniform mat4 u_light_coords;  // world -> (s, t, slice) of the opacity maps
// pixels per metre at unit depth (perspective) or per metre (orthographic)
uniform float u_pixel_scale;
uniform float u_strand_width;  // texels across the strand texture
uniform float u_strand_max_level;
out vec2 v_uv;
flat out int v_level;
out vec3 v_T;
out vec3 v_light;
out float v_alpha;
out float v_value;
#ifdef SHADE
out vec3 v_color;
#endif
void main() {
  vec2 corner = vec2((gl_VertexID & 1) == 0 ? -1.0 : 1.0, (gl_VertexID & 2) == 0 ? -1.0 : 1.0);
  vec3 d = u_ortho == 1 ? u_proj_dir : normalize(a_pos - u_eye);
  vec3 T = normalize(a_dir);
  float c = clamp(abs(dot(T, d)), 0.0, 1.0);
  float s = sqrt(max(0.0, 1.0 - c * c));
  vec3 axis = T - dot(T, d) * d;
  float al = length(axis);
  vec3 helper = abs(d.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
  axis = al > 1e-5 ? axis / al : normalize(cross(d, helper));
  vec3 side = normalize(cross(d, axis));
  float len = max(u_length * s, u_width);
  vec3 p = a_pos + (0.5 * u_width * corner.x) * side + (0.5 * len * corner.y) * axis;
  v_uv = 0.5 * corner + 0.5;
  // the strand texture's mip level, once per billboard: its texels across
  // the billboard's width on screen
  float depth = u_ortho == 1 ? 1.0 : max(1e-4, length(a_pos - u_eye));
  float width_px = u_width * u_pixel_scale / depth;
  float level = floor(log2(u_strand_width / max(width_px, 1e-3)) + 0.5);
  v_level = int(clamp(level, 0.0, u_strand_max_level));
  v_T = T;
  v_light = (u_light_coords * vec4(p, 1.0)).xyz;  // affine (orthographic light): exact to interpolate
  v_alpha = u_opacity * min(1.0 / max(s, 1e-4), u_max_boost);
  v_value = a_value;
#ifdef SHADE
  v_color = shade(T, a_pos);
#endif
  gl_Position = u_view_proj * vec4(p, 1.0);
}
