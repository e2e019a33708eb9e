uniform vec3 u_light, u_color, u_spec_color;
uniform float u_kd, u_ks, u_shine, u_reflect, u_transmit, u_ambient;
out vec3 v_lit;
vec3 shade(vec3 T, vec3 world) {
  vec3 L = normalize(u_light);
  vec3 E = normalize(u_eye - world);
  float tl = dot(T, L), te = dot(T, E);
  float sin_tl = sqrt(max(0.0, 1.0 - tl * tl)), sin_te = sqrt(max(0.0, 1.0 - te * te));
  float diffuse = u_kd * sin_tl;
  float specular = u_ks * pow(max(0.0, sin_tl * sin_te - tl * te), u_shine);
  vec3 txl = cross(T, L), txe = cross(T, E);
  float denom = length(txl) * length(txe);
  float kd = denom > 1e-6 ? dot(txl, txe) / denom : 1.0;
  float f_dir = u_reflect * (1.0 + kd) * 0.5 + u_transmit * (1.0 - kd) * 0.5;
  v_lit = u_color * (f_dir * diffuse) + u_spec_color * (f_dir * specular);
  return u_color * u_ambient;
}
