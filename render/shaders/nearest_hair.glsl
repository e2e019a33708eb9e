// Deep opacity maps (Yuksel and Keyser 2008, with the slices of method.md §7.2):
// the slices start at the hair nearest the light in each texel of the
// light's view rather than at one plane across the whole head of hair, so
// they follow the hair's lit surface. With one plane, the first slices cut
// across the curved crown and their linear steps showed as dark bands.
// u_nearest holds that depth in slices (1e6 where no hair is); a point's
// depth into the hair is its depth less that depth interpolated between
// the 2x2 texels around it that have hair (a texel without hair does not
// count: a point at the hair's edge is lit as the hair beside it is).
uniform sampler2D u_nearest;
// The slices deepen with the square root of the depth d into the hair (d
// in units of a 15th of the hair's extent along the light): thin at the lit
// surface, where the light fades fastest (slice 1 at 1.3 mm into a 30 cm
// head of hair, slice 4 at 2 cm), and reaching through all of it.
float sliceOfDepth(float d) { return sqrt(15.0 * max(d, 0.0)); }
float nearestHair(vec2 st) {
  ivec2 size = textureSize(u_nearest, 0);
  vec2 p = st * vec2(size) - 0.5;
  ivec2 c = ivec2(floor(p));
  vec2 f = p - vec2(c);
  ivec2 hi = size - 1;
  vec4 z = vec4(texelFetch(u_nearest, clamp(c, ivec2(0), hi), 0).r,
                texelFetch(u_nearest, clamp(c + ivec2(1, 0), ivec2(0), hi), 0).r,
                texelFetch(u_nearest, clamp(c + ivec2(0, 1), ivec2(0), hi), 0).r,
                texelFetch(u_nearest, clamp(c + ivec2(1, 1), ivec2(0), hi), 0).r);
  vec4 w = vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
  w *= vec4(lessThan(z, vec4(1e5)));
  float sum = w.x + w.y + w.z + w.w;
  return sum > 1e-6 ? dot(w, z) / sum : 1e6;
}
