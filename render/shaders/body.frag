in vec3 v_world;
in vec3 v_normal;
in vec3 v_light;
uniform vec3 u_eye, u_light, u_skin;
out vec4 o_color;
void main() {
  vec3 N = normalize(v_normal);
  vec3 L = normalize(u_light);
  vec3 E = normalize(u_eye - v_world);
  vec3 H = normalize(L + E);
  float light = transmittance(v_light);
  float lambert = max(0.0, dot(N, L));
  float spec = pow(max(0.0, dot(N, H)), 24.0) * 0.15;
  vec3 c = u_skin * (0.28 + 0.72 * lambert * light) + vec3(spec * light);
  o_color = vec4(c, 1.0);
}
