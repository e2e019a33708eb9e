in vec2 v_uv;
flat in int v_level;
in vec3 v_light;
in float v_alpha;
in vec3 v_color;  // ambient
in vec3 v_lit;    // diffuse and specular before attenuation
uniform sampler2D u_hair;
out vec4 o_color;
void main() {
  ivec2 size = textureSize(u_hair, v_level);
  float a = texelFetch(u_hair, min(ivec2(v_uv * vec2(size)), size - 1), v_level).a * v_alpha;
  if (a < 2e-3) discard;
  o_color = vec4(v_color + v_lit * transmittance(v_light), min(a, 1.0));
}
