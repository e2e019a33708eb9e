// Goldman's Kajiya-Kay hair shading (method.md §7.3), shared by billboards and
// strands: the diffuse Kd sin(T, L) and specular Ks max(0, sin(T,L) sin(T,E)
// - (T.L)(T.E))^p factors, each times the directionality f_dir (reflection
// towards the lit side, transmission through to the other).
uniform float u_kd, u_ks, u_shine, u_reflect, u_transmit;
vec2 kajiyaKay(vec3 T, vec3 L, vec3 E) {
  float tl = dot(T, L), te = dot(T, E);
  float sin_tl = sqrt(max(0.0, 1.0 - tl * tl)), sin_te = sqrt(max(0.0, 1.0 - te * te));
  float diffuse = u_kd * sin_tl;
  float specular = u_ks * pow(max(0.0, sin_tl * sin_te - tl * te), u_shine);
  vec3 txl = cross(T, L), txe = cross(T, E);
  float denom = length(txl) * length(txe);
  float kd = denom > 1e-6 ? dot(txl, txe) / denom : 1.0;
  float f_dir = u_reflect * (1.0 + kd) * 0.5 + u_transmit * (1.0 - kd) * 0.5;
  return f_dir * vec2(diffuse, specular);
}
