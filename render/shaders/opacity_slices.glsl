// Pass 1 of the opacity shadow maps (method.md §7.2): a fragment of opacity a at
// depth z (in slices) adds a to every slice behind it, with a one-slice ramp
// (so the lookup interpolates). Layer l of the slice array holds slices
// 3l .. 3l+3 (neighbouring layers share one slice), so any two adjacent
// slices k, k+1 are in one layer and the lookup reads one texel.
layout(location = 0) out vec4 o0;
layout(location = 1) out vec4 o1;
layout(location = 2) out vec4 o2;
layout(location = 3) out vec4 o3;
layout(location = 4) out vec4 o4;
// 1: the pass before, which keeps the depth of the hair nearest the light
// (a MIN blend into one target); fragments nearly transparent do not count
uniform int u_nearest_pass;
// lc: the fragment's light coordinates (s, t, depth in slices)
void writeSlices(float a, vec3 lc) {
  if (u_nearest_pass == 1) {
    if (a < 0.05) discard;
    o0 = vec4(lc.z);
    o1 = o2 = o3 = o4 = vec4(0.0);
    return;
  }
  float zs = sliceOfDepth(lc.z - nearestHair(lc.xy));
  vec4 z = vec4(zs) - vec4(0.0, 1.0, 2.0, 3.0);
  o0 = a * clamp(0.0 - z, 0.0, 1.0);
  o1 = a * clamp(3.0 - z, 0.0, 1.0);
  o2 = a * clamp(6.0 - z, 0.0, 1.0);
  o3 = a * clamp(9.0 - z, 0.0, 1.0);
  o4 = a * clamp(12.0 - z, 0.0, 1.0);
}
