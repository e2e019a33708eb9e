// The strands carried by the particles on the GPU (issue 45; the CPU twin
// is StrandField::deform in sim/src/strands/strand_field.cpp, whose steps
// this follows): one invocation a strand, from its root to its tip,
//   1. each point carried by its particles' rigid motions, p = sum w (R r + y),
//   2. smoothed along the strand with the rest strand's detail put back in
//      the carried frame,
//   3. segment lengths held within the tolerance of their rest lengths,
//   4. pushed out of the bodies by their sampled distances (trilinear) and
//      the lengths held again, in rounds,
//   5. a strand pushed longer or shorter than the tolerance mended at its
//      tip and pushed out again, in up to 6 rounds,
// then placed in the world by the head's pose. Prepended by the program:
// #version 430 core, and #define MAX_BODIES.
layout(local_size_x = 64) in;

struct Motion { vec4 c0, c1, c2; };  // rotation columns; w: the shift
layout(std430, binding = 0) readonly buffer Motions { Motion motion[]; };
layout(std430, binding = 1) readonly buffer BindIndex { uint bind_index[]; };
layout(std430, binding = 2) readonly buffer BindWeight { float bind_weight[]; };
layout(std430, binding = 3) readonly buffer RestPoints { vec4 rest_point[]; };  // w: rest length to the next
layout(std430, binding = 4) readonly buffer Detail { vec4 detail[]; };
layout(std430, binding = 5) readonly buffer StrandFirst { uint strand_first[]; };
layout(std430, binding = 6) buffer OutPoints { vec4 out_point[]; };
// 2 a point: the carried point (later: the last distance asked, and where),
// the rest direction turned
layout(std430, binding = 7) buffer Scratch { vec4 scratch[]; };

uniform uint u_strands;
uniform uint u_stride;  // every u_stride-th strand (RenderSettings::strand_budget)
uniform int u_carriers;
uniform float u_clearance;
uniform float u_tolerance;
uniform mat4 u_head;  // head frame -> world
uniform int u_smooth_half;
uniform float u_smooth_taps[8];
uniform int u_rounds;
uniform int u_bodies;
// the bodies' distance volumes, one after another in `volume` (x fastest):
// body i's from u_volume_first[i], u_volume_dims[i] values a side
layout(std430, binding = 8) readonly buffer Volumes { float volume[]; };
uniform int u_volume_first[MAX_BODIES];
uniform ivec3 u_volume_dims[MAX_BODIES];
uniform mat4 u_to_grid[MAX_BODIES];           // head frame -> grid coordinates (voxels)
uniform mat3 u_gradient_to_head[MAX_BODIES];  // grid gradient -> head frame

mat3 rotationOf(uint k) { return mat3(motion[k].c0.xyz, motion[k].c1.xyz, motion[k].c2.xyz); }
vec3 shiftOf(uint k) { return vec3(motion[k].c0.w, motion[k].c1.w, motion[k].c2.w); }

// body b's trilinear interpolant at p (clamped to its grid) and its
// gradient (per voxel), from the 8 values around p: read from a buffer
// rather than a texture, as one buffer holds every body's volume
float volumeAt(int b, vec3 p, out vec3 gradient) {
  ivec3 dims = u_volume_dims[b];
  vec3 g = clamp((u_to_grid[b] * vec4(p, 1.0)).xyz, vec3(0.0), vec3(dims - 1));
  ivec3 c = min(ivec3(floor(g)), max(dims - 2, ivec3(0)));
  vec3 f = g - vec3(c);
  int sx = 1, sy = dims.x, sz = dims.x * dims.y;
  int i = u_volume_first[b] + c.x + c.y * sy + c.z * sz;
  float v000 = volume[i], v100 = volume[i + sx], v010 = volume[i + sy], v110 = volume[i + sx + sy];
  float v001 = volume[i + sz], v101 = volume[i + sx + sz], v011 = volume[i + sy + sz],
        v111 = volume[i + sx + sy + sz];
  float x00 = mix(v000, v100, f.x), x10 = mix(v010, v110, f.x);
  float x01 = mix(v001, v101, f.x), x11 = mix(v011, v111, f.x);
  float y0 = mix(x00, x10, f.y), y1 = mix(x01, x11, f.y);
  float dx0 = mix(v100 - v000, v110 - v010, f.y), dx1 = mix(v101 - v001, v111 - v011, f.y);
  gradient = vec3(mix(dx0, dx1, f.z), mix(x10 - x00, x11 - x01, f.z), y1 - y0);
  return mix(y0, y1, f.z);
}

// the signed distance to the nearest body (head frame) and its outward
// normal
float bodyDistance(vec3 p, out vec3 n) {
  float best = 1e30;
  n = vec3(0.0, 1.0, 0.0);
  for (int b = 0; b < u_bodies; ++b) {
    vec3 grad;
    float phi = volumeAt(b, p, grad);
    if (phi < best) {
      best = phi;
      vec3 gh = u_gradient_to_head[b] * grad;
      float l = length(gh);
      n = l > 0.0 ? gh / l : vec3(0.0, 1.0, 0.0);
    }
  }
  return best;
}

// strand points [b, e): every segment as it is now, held within the
// tolerance of its rest length (a squeezed one turned towards the carried
// rest direction the more it is squeezed), from the root on
void limitLengths(uint b, uint e) {
  vec3 prev_old = out_point[b].xyz;
  vec3 prev_new = prev_old;
  for (uint q = b + 1u; q < e; ++q) {
    vec3 cur_old = out_point[q].xyz;
    vec3 d = cur_old - prev_old;
    prev_old = cur_old;
    float len = length(d), l0 = rest_point[q - 1u].w;
    float hi = l0 * (1.0 + u_tolerance), lo = l0 * (1.0 - u_tolerance);
    vec3 carried = scratch[2u * (q - 1u) + 1u].xyz;
    if (len > hi) {
      d *= hi / len;
    } else if (len < lo) {
      vec3 dir = d + (lo - len) * carried;
      float dl = length(dir);
      d = (dl > 1e-7 * l0 ? dir / dl : carried) * lo;
    }
    prev_new += d;
    out_point[q] = vec4(prev_new, 0.0);
  }
}

// the points of [b, e) (the root excepted) nearer a body than the
// clearance, pushed out to it; true if any moved. Each point's last
// distance asked and where (scratch[2q], free once the strand is smoothed)
// spare asking again while the point has not moved near enough to a body
// to matter (the distance is 1-Lipschitz); `first`: nothing asked yet.
bool pushOut(uint b, uint e, bool first) {
  bool moved = false;
  for (uint q = b + 1u; q < e; ++q) {
    vec3 p = out_point[q].xyz, n;
    vec4 last = scratch[2u * q];
    if (!first && last.w - length(p - last.xyz) >= u_clearance) continue;
    float phi = bodyDistance(p, n);
    scratch[2u * q] = vec4(p, phi);
    if (phi < u_clearance) {
      out_point[q] = vec4(p + (u_clearance - phi) * n, 0.0);
      moved = true;
    }
  }
  return moved;
}

// a strand pushed longer or shorter than the tolerance, mended at its tip
bool trimTip(uint b, uint e) {
  float len = 0.0, rest = 0.0;
  for (uint q = b + 1u; q < e; ++q) {
    len += length(out_point[q].xyz - out_point[q - 1u].xyz);
    rest += rest_point[q - 1u].w;
  }
  if (len < rest * (1.0 - u_tolerance)) {
    vec3 d = out_point[e - 1u].xyz - out_point[e - 2u].xyz;
    float l = length(d);
    if (!(l > 0.0)) return false;
    out_point[e - 1u].xyz += d * ((rest * (1.0 - u_tolerance) - len) / l);
    return true;
  }
  float excess = len - rest * (1.0 + u_tolerance);
  if (!(excess > 0.0)) return false;
  for (uint q = e - 1u; q > b && excess > 0.0; --q) {
    vec3 d = out_point[q].xyz - out_point[q - 1u].xyz;
    float l = length(d);
    float cut = min(excess, 0.5 * l);
    if (!(l > 0.0) || cut <= 0.0) continue;
    vec3 move = -d * (cut / l);
    for (uint r = q; r < e; ++r) out_point[r].xyz += move;
    excess -= cut;
  }
  return true;
}

void main() {
  uint s = gl_GlobalInvocationID.x * u_stride;
  if (s >= u_strands) return;
  uint b = strand_first[s], e = strand_first[s + 1u];
  uint k = uint(u_carriers);
  // 1. carried: the raw point, and the rest detail and the rest segment's
  // direction turned by the blended frame
  for (uint q = b; q < e; ++q) {
    mat3 m = mat3(0.0);
    vec3 c = vec3(0.0);
    for (uint i = 0u; i < k; ++i) {
      uint j = bind_index[q * k + i];
      float w = bind_weight[q * k + i];
      m += w * rotationOf(j);
      c += w * shiftOf(j);
    }
    scratch[2u * q] = vec4(m * rest_point[q].xyz + c, 0.0);
    out_point[q] = vec4(m * detail[q].xyz, 0.0);
    vec3 seg = q + 1u < e ? m * (rest_point[q + 1u].xyz - rest_point[q].xyz) : vec3(0.0);
    float sl = length(seg);
    scratch[2u * q + 1u] = vec4(sl > 0.0 ? seg / sl : vec3(0.0, -1.0, 0.0), 0.0);
  }
  // 2. smoothed along the strand (a window cut at the ends, narrowing at
  // the root, which is not moved), plus the detail
  uint n = e - b;
  for (uint j = 0u; j < n; ++j) {
    vec3 smoothed;
    if (j == 0u) {
      smoothed = scratch[2u * b].xyz;
    } else {
      uint half_width = min(uint(u_smooth_half), j);
      vec3 sum = vec3(0.0);
      float wsum = 0.0;
      for (uint d = 0u; d <= half_width; ++d) {
        float w = u_smooth_taps[d];
        sum += w * scratch[2u * (b + j - d)].xyz;
        wsum += w;
        if (d > 0u && j + d < n) {
          sum += w * scratch[2u * (b + j + d)].xyz;
          wsum += w;
        }
      }
      smoothed = sum / wsum;
    }
    out_point[b + j] = vec4(smoothed + out_point[b + j].xyz, 0.0);
  }
  // 3. lengths (r = -1); 4. rounds of (push out, lengths) while a push
  // moves a point (r < u_rounds), one push more (r = u_rounds); 5. rounds of
  // (mend the tip, push out). One loop, so that each step is compiled once
  // (software OpenGL compiles a shader's every copy of a call anew).
  int last = u_bodies > 0 ? u_rounds + 6 : -1;
  for (int r = -1; r <= last; ++r) {
    if (r > u_rounds && !trimTip(b, e)) break;
    if (r >= 0 && !pushOut(b, e, r == 0) && r < u_rounds) r = u_rounds;  // nothing moved: on to the tip
    if (r < u_rounds) limitLengths(b, e);
  }
  for (uint q = b; q < e; ++q) out_point[q] = u_head * vec4(out_point[q].xyz, 1.0);
}
