// Strand shading (method.md §7.3 and issue "strands"): Kajiya-Kay with Goldman's
// directionality, or Marschner's R, TT and TRT lobes from lookup textures
// (the Nalu chapter's M(theta_i, theta_r) and N(phi, theta_d) tables),
// times the light that reaches the fragment; a small per-strand variation
// of the colour.
uniform vec3 u_light, u_color, u_spec_color;
uniform float u_ambient;
uniform float u_variation;   // relative colour variation between strands
uniform int u_marschner;
uniform sampler2D u_lut_m;   // (sin_i, sin_r) -> M_R, M_TT, M_TRT, cos(theta_d)
uniform sampler2D u_lut_n1;  // (cos_phi, cos_theta_d) -> N_R, N_TT rgb
uniform sampler2D u_lut_n2;  // (cos_phi, cos_theta_d) -> N_TRT rgb
uniform float u_marschner_gain;
vec3 shadeStrand(vec3 T, vec3 world, float strand, float light) {
  vec3 L = normalize(u_light);
  vec3 E = normalize(u_eye - world);
  float vary = 1.0 + u_variation * (2.0 * strand - 1.0);
  vec3 base = u_color * vary;
  vec3 ambient = base * u_ambient;
  if (u_marschner == 0) {
    vec2 k = kajiyaKay(T, L, E);
    return ambient + (base * k.x + u_spec_color * k.y) * light;
  }
  // angles to the normal plane of the strand
  float sin_i = clamp(dot(L, T), -1.0, 1.0), sin_r = clamp(dot(E, T), -1.0, 1.0);
  vec4 m = texture(u_lut_m, vec2(0.5 * sin_i + 0.5, 0.5 * sin_r + 0.5));
  vec3 lp = L - sin_i * T, ep = E - sin_r * T;
  float lpl = length(lp), epl = length(ep);
  float cos_phi = (lpl > 1e-6 && epl > 1e-6) ? dot(lp, ep) / (lpl * epl) : 1.0;
  vec2 nuv = vec2(0.5 * cos_phi + 0.5, m.a);
  vec4 n1 = texture(u_lut_n1, nuv);
  vec3 n2 = texture(u_lut_n2, nuv).rgb;
  vec3 s = m.r * n1.r * u_spec_color + m.g * n1.gba * vary + m.b * n2 * vary;
  // divided by cos^2(theta_d) as in Marschner's model; the cosine of the
  // incident light to the strand's normal plane is the irradiance factor.
  // Marschner's lobes are single scattering: the light scattered many
  // times in a head of hair is added as a soft diffuse term.
  float cd = max(m.a, 0.2);
  float cos_i = sqrt(max(0.0, 1.0 - sin_i * sin_i));
  vec3 multiple = base * (u_kd * cos_i);
  return ambient + (multiple + u_marschner_gain * s * (cos_i / (cd * cd))) * light;
}
