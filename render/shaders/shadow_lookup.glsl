// The opacity lookup shared by the hair and the bodies (method.md §7.2), per
// fragment, at light coordinates (s, t, z) interpolated from the vertices:
// z is the depth in slices, less the offset against self-shadowing.
// Omega(z) = sum_k Omega_k max(0, 1 - |z - k|): only the slices k and k+1
// around z weigh, and both are in layer l = k / 3 (one bilinear fetch).
// The slices are 8-bit (Omega clamped at 1, where exp(-kappa) leaves 0.4%
// of the light): llvmpipe reads and blends them much faster than floats.
// Written without branches or dynamic indexing (llvmpipe runs every path of
// a branch in its SIMD lanes).
uniform sampler2DArray u_slices;  // 5 layers x RGBA: slices 3l .. 3l+3 in layer l
uniform float u_kappa;
uniform int u_shadows;
float transmittance(vec3 lc) {
  if (u_shadows == 0) return 1.0;
  float depth = lc.z - nearestHair(lc.xy);  // into the hair (deep opacity maps)
  float z = clamp(sliceOfDepth(depth), 0.0, 15.0);
  int l = min(int(z) / 3, 4);
  vec4 a = texture(u_slices, vec3(lc.xy, float(l)));
  vec4 w = max(vec4(0.0), 1.0 - abs(z - (float(3 * l) + vec4(0.0, 1.0, 2.0, 3.0))));
  float omega = dot(a, w);
  // outside the maps (and in front of the first slice) nothing shadows
  bool inside = all(greaterThanEqual(lc.xy, vec2(0.0))) && all(lessThanEqual(lc.xy, vec2(1.0))) && depth > 0.0;
  return inside ? exp(-u_kappa * omega) : 1.0;
}
