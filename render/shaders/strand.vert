// Strands as thin ribbons facing the viewer (issue "strands"), shared by the
// light pass and the camera pass: strand k is a triangle strip of 2P
// vertices addressed by gl_VertexID (drawn with glMultiDrawArrays, no
// instancing: llvmpipe runs the vertex stage per instance), vertices 2i and
// 2i + 1 on either side of point i, fetched from a buffer texture. Each
// point is widened along cross(tangent, view) with the tangent from its
// neighbours, so segments join without gaps. A strand narrower than a pixel
// is drawn one pixel wide with its alpha scaled by the part of the pixel it
// covers. Where every strand is that thin (u_lines), strand k is a line
// strip of P vertices instead, one a point: half the vertices and
// primitives, which is what a software rasteriser spends its time on. A
// line covers max(|dx|, |dy|) pixels per pixel of its length; its alpha is
// raised by the inverse.
uniform samplerBuffer u_points;  // xyz: world position, w: unused
uniform int u_points_per_strand;
uniform mat4 u_view_proj;
uniform vec3 u_proj_dir;  // orthographic projection direction (light pass)
uniform int u_ortho;
uniform float u_radius;       // strand half-width, world (m)
uniform float u_pixel_scale;  // pixels per metre at unit depth (perspective) or per metre (ortho)
uniform float u_opacity;
uniform mat4 u_light_coords;
uniform int u_lines;
uniform vec2 u_viewport;  // pixels (lines only)
out vec3 v_world;
out vec3 v_light;
out float v_alpha;
#ifdef SHADE
// shaded per vertex (a strand is a pixel or two wide), with its weight in
// the transparency sums (strand.frag)
uniform vec2 u_depth_range;  // eye distance of the hair's nearest and farthest point
uniform float u_depth_falloff;
out vec4 v_weighted;
out float v_reveal;
#endif
vec3 fetch(int q) { return texelFetch(u_points, q).xyz; }
float hash(int k) {
  uint h = uint(k) * 747796405u + 2891336453u;
  h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
  return float((h >> 22u) ^ h) * (1.0 / 4294967296.0);
}
void main() {
  int per = u_points_per_strand - 1;
  int vertices = u_lines == 1 ? u_points_per_strand : 2 * u_points_per_strand;
  int strand = gl_VertexID / vertices;
  int local = gl_VertexID - strand * vertices;
  int base = strand * u_points_per_strand;
  int i = u_lines == 1 ? local : local / 2;  // the point this vertex sits at
  float side = u_lines == 1 ? 0.0 : ((local & 1) == 0 ? -1.0 : 1.0);
  vec3 p = fetch(base + i);
  vec3 prev = fetch(base + max(i - 1, 0));
  vec3 next = fetch(base + min(i + 1, per));
  vec3 T = next - prev;
  float tl = length(T);
  T = tl > 1e-9 ? T / tl : vec3(0.0, -1.0, 0.0);
  vec3 d = u_ortho == 1 ? u_proj_dir : normalize(p - u_eye);
  vec3 across = cross(T, d);
  float al = length(across);
  vec3 helper = abs(d.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
  across = al > 1e-6 ? across / al : normalize(cross(d, helper));
  float depth = u_ortho == 1 ? 1.0 : max(1e-4, length(p - u_eye));
  float half_pixel = 0.5 * depth / u_pixel_scale;  // half a pixel, world
  float r = max(u_radius, half_pixel);
  vec3 w = p + (side * r) * across;
  // fades over the last tenth of the strand (tips are thin)
  float s = float(i) / float(per);
  float tip = clamp((1.0 - s) * 10.0, 0.0, 1.0);
  // at most opaque (a strand drawn for several, by the level of detail, or
  // for many in the light pass, may stand for more than full coverage there)
  float coverage = u_radius / r;
  if (u_lines == 1) {
    vec4 a = u_view_proj * vec4(prev, 1.0), b = u_view_proj * vec4(next, 1.0);
    vec2 screen = (b.xy / b.w - a.xy / a.w) * u_viewport;
    float sl = length(screen);
    coverage /= sl > 1e-6 ? max(abs(screen.x), abs(screen.y)) / sl : 1.0;
  }
  v_alpha = u_ortho == 1 ? u_opacity * coverage * (0.35 + 0.65 * tip)
                         : min(1.0, u_opacity * coverage * (0.35 + 0.65 * tip));
  v_world = w;
  v_light = (u_light_coords * vec4(w, 1.0)).xyz;
#ifdef SHADE
  vec3 color = shadeStrand(T, p, hash(strand), transmittance(v_light));
  float a = clamp(v_alpha, 0.0, 0.98);
  float t = clamp((length(w - u_eye) - u_depth_range.x) / max(1e-4, u_depth_range.y - u_depth_range.x), 0.0, 1.0);
  float weight = a * exp(-u_depth_falloff * t);
  v_weighted = vec4(color * weight, weight);
  v_reveal = -log(1.0 - a);
#endif
  gl_Position = u_view_proj * vec4(w, 1.0);
}
