// Generates the bundled styles of data/styles/ on the bundled head, through
// the same editing API the viewer uses (run by `loosehair_make_styles DIR`,
// DIR holding meshes/; writes DIR/styles/*.json):
//
//   long-straight.json  long straight hair with a centre parting
//   bob.json            a chin-length bob
//   side-swept.json     a side parting, the hair swept over
//   swept-back.json     hair swept back from the forehead
//   wavy.json           long wavy hair (a curl in the strands' frame)
//   ponytail.json       a ponytail gathered by a tie at the back of the head
//
// Each style covers the scalp square with a grid of rectangular (u, v)
// wisps, so it loads onto any head by (u, v). A key strand is "draped": it
// leaves the root in a direction the style chooses, bends towards gravity
// step by step, and is pushed off the head and torso by a clearance that
// grows along the strand (hair from the crown lies over hair rooted lower).
#include "loosehair/head_landmarks.hpp"
#include "loosehair/head_model.hpp"
#include "loosehair/style.hpp"
#include "loosehair/style_editor.hpp"
#include "loosehair/style_settle.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>

namespace {

using namespace loosehair;

// Member settings of a style's wisps: density (strands per cm^2), largest
// tip offset (m), length variation; wisps blend into their neighbours at
// their borders and the hairline is thinned over 6 mm.
WispParams memberParams(float density, float offset_radius, float length_variation) {
  WispParams p;
  p.density = density;
  p.offset_radius = offset_radius;
  p.length_variation = length_variation;
  p.blend = 1.0f;
  p.edge_ramp = 0.006f;
  return p;
}

struct Drape {
  float length = 0.3f;                         // m
  float step = 0.01f;                          // m between marched points
  float bend = 0.2f;                           // how fast the direction turns towards gravity per step
  float clearance = 0.003f, layering = 0.03f;  // off the head: clearance + layering * s
  float cut = -INFINITY;                       // the strand ends where it first falls below this height (m)
  int every = 4;                               // a control point every this many steps
};

// Pushes p off the head and torso to at least `gap`.
glm::vec3 pushOff(const HeadModel& head, glm::vec3 p, float gap) {
  for (int it = 0; it < 4; ++it) {
    bool moved = false;
    for (const Body* b : {head.head().get(), head.torso().get()}) {
      if (!b) continue;
      float phi;
      glm::vec3 n;
      b->signedDistance(&p, 1, &phi, &n);
      if (phi < gap) {
        p += (gap - phi) * n;
        moved = true;
      }
    }
    if (!moved) break;
  }
  return p;
}

// A key strand from `root`, leaving along `dir0`, combed by `steer` (a
// direction the hair is pulled towards at a point and arc length) and
// falling under gravity, lying on the head where the head holds it up.
std::vector<glm::vec3> drape(const HeadModel& head, glm::vec3 root, glm::vec3 dir0, const Drape& d,
                             const std::function<glm::vec3(glm::vec3, float)>& steer = nullptr) {
  std::vector<glm::vec3> control{root};
  glm::vec3 p = root, dir = glm::normalize(dir0);
  const int steps = static_cast<int>(std::ceil(d.length / d.step));
  for (int k = 1; k <= steps; ++k) {
    const float s = static_cast<float>(k) * d.step;
    dir = glm::normalize(dir + d.bend * glm::vec3(0, -1, 0));
    if (steer) dir = glm::normalize(steer(p, s) + dir);
    const glm::vec3 next = pushOff(head, p + d.step * dir, d.clearance + d.layering * s);
    dir = glm::normalize(next - p);
    p = next;
    const bool cut = p.y < d.cut && k >= 2;
    if (k % d.every == 0 || k == steps || cut) control.push_back(p);
    if (cut) break;
  }
  if (control.size() < 3) control.insert(control.begin() + 1, 0.5f * (control[0] + control[1]));
  return control;  // the editor adds points where the spline would cut into the head
}

WispRegion cell(int i, int j, int nu, int nv) {
  const float fu = static_cast<float>(nu), fv = static_cast<float>(nv);
  const float u0 = static_cast<float>(i) / fu, u1 = static_cast<float>(i + 1) / fu;
  const float v0 = static_cast<float>(j) / fv, v1 = static_cast<float>(j + 1) / fv;
  WispRegion r;
  r.polygons.push_back({{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}});
  return r;
}

// The scalp tangent along v (towards the nape).
glm::vec3 towardsNape(const HeadModel& head, glm::vec2 uv) {
  const glm::vec3 n = head.scalpNormal(uv), e = head.scalpTangentU(uv);
  return glm::normalize(glm::cross(n, e));
}

// Away from the head's vertical axis, level.
glm::vec3 outwards(glm::vec3 p) {
  const glm::vec3 o(p.x, 0.0f, p.z);
  return glm::length(o) > 1e-6f ? glm::normalize(o) : glm::vec3(0, 0, -1);
}

// A grid of wisps; `direction(uv, root, normal)` gives each key strand's
// first direction, `drape_at(uv)` its fall and `steer_at(uv)` its combing.
using Direction = std::function<glm::vec3(glm::vec2, glm::vec3, glm::vec3)>;
using Steer = std::function<glm::vec3(glm::vec3, float)>;
Style gridStyle(const HeadModel& head, const std::string& name, int nu, int nv, const WispParams& params,
                const std::function<Drape(glm::vec2)>& drape_at, const Direction& direction,
                const std::function<Steer(glm::vec2)>& steer_at = nullptr) {
  Style base;
  base.name = name;
  base.head = head.desc();
  StyleEditor ed(base, head);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const WispRegion r = cell(i, j, nu, nv);
      const glm::vec2 uv = regionRoot(r, head);
      const glm::vec3 root = head.scalpPoint(uv), n = head.scalpNormal(uv);
      WispParams p = params;
      p.seed = params.seed + static_cast<std::uint64_t>(j * nu + i);
      ed.createWisp(r, p, drape(head, root, direction(uv, root, n), drape_at(uv), steer_at ? steer_at(uv) : nullptr),
                    name + " " + std::to_string(j) + "," + std::to_string(i));
    }
  return ed.style();
}

// The style's key strands as the physics leaves them after a second on a
// still head (settledKeyStrands): the hair lies where gravity puts it.
// Wisps rooted along the front hairline (v < 0.2) keep their combed shape:
// without the stiffness of real hair, plain LCP lets them fall over the face.
Style settled(Style style, const HeadModel& head) {
  checkStyle(style, head);
  StyleEditor ed(std::move(style), head);
  SettleOptions o;
  o.seconds = 1.0;
  std::vector<std::vector<glm::vec3>> keys = settledKeyStrands(ed.style(), o);
  for (std::size_t w = 0; w < keys.size(); ++w)
    if (regionRoot(ed.style().wisps[w].region, head).y < 0.2f) keys[w] = ed.style().wisps[w].key_strand;
  ed.setKeyStrands(keys);
  return ed.style();
}

Style ponytail(const HeadModel& head) {
  const glm::vec2 back_uv(0.5f, 0.72f);
  const glm::vec3 back = head.scalpPoint(back_uv), bn = head.scalpNormal(back_uv);
  HairTie tie;
  tie.name = "ponytail tie";
  tie.center = back + 0.022f * bn;
  tie.axis = glm::normalize(glm::vec3(0, -1, -0.35f));
  tie.radius = 0.016f;
  tie.width = 0.014f;
  Style base;
  base.name = "ponytail";
  base.head = head.desc();
  // The style's default hold (1 Hz) for the tail; the hair between scalp
  // and tie is held at the tie's own, stronger hold (HairTie::hold).
  StyleEditor ed(base, head);
  const int nu = 7, nv = 6;
  WispParams params = memberParams(36.0f, 0.016f, 0.12f);
  const glm::vec3 before = tie.center - 0.03f * tie.axis;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const WispRegion r = cell(i, j, nu, nv);
      const glm::vec2 uv = regionRoot(r, head);
      const glm::vec3 root = head.scalpPoint(uv);
      // combed flat over the head from the root to just before the tie
      // (each step towards it, kept 3 mm off the surface), through the
      // ring along its axis, then the tail falling away from the head
      std::vector<glm::vec3> key{root};
      glm::vec3 p = root;
      float walked = 0;
      for (int k = 0; k < 60 && glm::distance(p, before) > 0.025f; ++k) {
        const glm::vec3 next = head.scalpPoint(head.nearestScalpUv(p + 0.01f * glm::normalize(before - p)));
        float phi;
        glm::vec3 nn;
        head.head()->signedDistance(&next, 1, &phi, &nn);
        const glm::vec3 q = pushOff(head, next - phi * nn, 0.003f);
        walked += glm::distance(p, q);
        p = q;
        if (walked > 0.03f) {
          key.push_back(p);
          walked = 0;
        }
      }
      if (glm::distance(key.back(), before) < 0.012f) key.pop_back();
      key.push_back(before);
      key.push_back(tie.center);
      // below the ring the tail fans out a little: each wisp towards the
      // side of the head it comes from
      const float side = std::clamp((root.x - tie.center.x) / 0.06f, -1.0f, 1.0f);
      p = tie.center;
      glm::vec3 dir = glm::normalize(tie.axis + glm::vec3(0.25f * side, 0, 0));
      for (int k = 1; k <= 5; ++k) {
        dir = glm::normalize(dir + 0.25f * glm::vec3(0, -1, 0));
        p = pushOff(head, p + 0.05f * dir, 0.01f);
        key.push_back(p);
      }
      WispParams pi = params;
      pi.seed = static_cast<std::uint64_t>(100 + j * nu + i);
      ed.createWisp(r, pi, key, "ponytail " + std::to_string(j) + "," + std::to_string(i));
    }
  ed.addTie(tie);
  return ed.style();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DATA_DIR   (writes DATA_DIR/styles/*.json)\n", argv[0]);
    return 2;
  }
  try {
    const std::filesystem::path dir(argv[1]);
    HeadDesc desc;
    desc.head_kind = HeadKind::Mesh;
    desc.head_mesh.path = (dir / "meshes" / "head.ply").string();
    desc.has_torso = true;
    desc.torso_mesh.path = (dir / "meshes" / "torso.ply").string();
    desc.scalp_kind = ScalpKind::Auto;
    const HeadModel head = HeadModel::build(desc, "bundled head");
    std::filesystem::create_directories(dir / "styles");

    const HeadHeights at = measureHeadHeights(head.headMesh());
    std::printf("bundled head: top %.3f, brows %.3f, ears %.3f..%.3f, chin %.3f m\n", at.top, at.brows, at.ear_top,
                at.ear_bottom, at.chin);
    const float jaw = at.chin + 0.35f * (at.ear_bottom - at.chin);
    // sideways away from the parting at u = parting, then down
    // A parting runs from the front hairline to the crown: behind it
    // (v from 0.45 to 0.75) the sideways comb fades and the hair falls
    // towards the nape, so the back of the head shows no parting line.
    auto behindCrown = [](glm::vec2 uv) { return glm::smoothstep(0.45f, 0.75f, uv.y); };
    auto parted = [&](float parting, float lift) -> Direction {
      return [&head, parting, lift, behindCrown](glm::vec2 uv, glm::vec3, glm::vec3 n) {
        const glm::vec3 e = head.scalpTangentU(uv);
        const float side = uv.x < parting ? -1.0f : 1.0f, back = behindCrown(uv);
        return lift * n + (1.0f - back) * side * e + (0.3f + back) * towardsNape(head, uv);
      };
    };
    auto fixed = [](Drape d) { return [d](glm::vec2) { return d; }; };
    // hair that would fall in front of the face below the brows is combed
    // aside and back, behind the face's sides, as one frames a face
    const float brow = at.brows;
    auto clearOfFace = [brow](glm::vec2) -> Steer {
      return [brow](glm::vec3 p, float) {
        if (p.y > brow || p.z < 0.0f) return glm::vec3(0.0f);
        return glm::vec3(p.x < 0.0f ? -0.5f : 0.5f, 0.0f, -0.5f);
      };
    };
    std::vector<std::pair<std::string, Style>> styles;
    {
      // to the middle of the back, over the shoulders
      WispParams p = memberParams(26.0f, 0.008f, 0.06f);
      Drape d;
      d.length = 0.42f;
      styles.emplace_back("long-straight",
                          gridStyle(head, "long-straight", 7, 6, p, fixed(d), parted(0.5f, 0.5f), clearOfFace));
    }
    {
      // a fringe cut at the brows; everything else falls outwards from the
      // crown and is cut level at the jaw, all round
      WispParams p = memberParams(28.0f, 0.006f, 0.04f);
      auto drape_at = [&](glm::vec2 uv) {
        Drape e;
        e.length = 0.25f;
        e.cut = uv.y < 0.2f ? at.brows + 0.01f : jaw;
        return e;
      };
      auto leave = [&](glm::vec2 uv, glm::vec3 root, glm::vec3 n) {
        if (uv.y < 0.2f) return glm::normalize(0.3f * n - towardsNape(head, uv));
        return glm::normalize(0.4f * n + outwards(root));
      };
      styles.emplace_back("bob", settled(gridStyle(head, "bob", 7, 6, p, drape_at, leave), head));
    }
    {
      // everything right of the parting at u = 0.3 combed over to the right
      WispParams p = memberParams(26.0f, 0.01f, 0.08f);
      Drape d;
      d.length = 0.3f;
      auto over = [&head, behindCrown](glm::vec2 uv, glm::vec3, glm::vec3 n) {
        const glm::vec3 e = head.scalpTangentU(uv);
        const float side = uv.x < 0.3f ? -1.0f : 1.0f, back = behindCrown(uv);
        return 0.3f * n + (1.0f - back) * side * e + (1.2f * back - 0.2f) * towardsNape(head, uv);
      };
      styles.emplace_back("side-swept", gridStyle(head, "side-swept", 7, 6, p, fixed(d), over, clearOfFace));
    }
    {
      // combed back flat over the crown, falling from the back of the head
      WispParams p = memberParams(34.0f, 0.012f, 0.08f);
      Drape d;
      d.length = 0.26f;
      d.bend = 0.14f;
      auto back = [&head](glm::vec2 uv, glm::vec3, glm::vec3 n) { return 0.2f * n + towardsNape(head, uv); };
      auto comb = [](glm::vec2) -> Steer {
        return [](glm::vec3, float s) { return s < 0.08f ? glm::vec3(0, 0, -0.2f) : glm::vec3(0.0f); };
      };
      styles.emplace_back("swept-back", gridStyle(head, "swept-back", 7, 6, p, fixed(d), back, comb));
    }
    {
      WispParams p = memberParams(24.0f, 0.01f, 0.08f);
      p.curl_radius = 0.012f;
      p.curl_period = 0.045f;
      Drape d;
      d.length = 0.38f;
      styles.emplace_back("wavy", gridStyle(head, "wavy", 7, 6, p, fixed(d), parted(0.5f, 0.5f), clearOfFace));
    }
    styles.emplace_back("ponytail", ponytail(head));
    for (auto& [file, style] : styles) {
      checkStyle(style, head);
      const std::string path = (dir / "styles" / (file + ".json")).string();
      saveStyle(style, path);
      const StrandSet strands = buildMemberStrands(style, head);
      std::printf("%s: %zu wisps, %zu strands, %zu points\n", path.c_str(), style.wisps.size(), strands.size(),
                  strands.points.size());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "loosehair_make_styles: %s\n", e.what());
    return 1;
  }
  return 0;
}
