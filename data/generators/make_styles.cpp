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
#include "loosehair/head_model.hpp"
#include "loosehair/style.hpp"
#include "loosehair/style_editor.hpp"

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
// tip offset (m), length variation.
WispParams memberParams(float density, float offset_radius, float length_variation) {
  WispParams p;
  p.density = density;
  p.offset_radius = offset_radius;
  p.length_variation = length_variation;
  // translated copies, as these styles grew before wisps could blend at
  // their borders (remaking them with blending, and the tools of the
  // styling mode, is issue 44's last part)
  p.blend = 0.0f;
  return p;
}


struct Drape {
  float length = 0.3f;   // m
  float step = 0.02f;    // m between marched points
  float bend = 0.35f;    // how fast the direction turns towards gravity per step
  float clearance = 0.006f, layering = 0.06f;  // off the head: clearance + layering * s
  int every = 3;         // a control point every this many steps
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

// A key strand from `root`, leaving along `dir0`, falling under gravity.
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
    if (k % d.every == 0 || k == steps) control.push_back(p);
  }
  return control;
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

// A grid of wisps; `direction(uv, root, normal)` gives each key strand's
// first direction and `drape` its fall.
Style gridStyle(const HeadModel& head, const std::string& name, int nu, int nv, const WispParams& params,
                const Drape& d, const std::function<glm::vec3(glm::vec2, glm::vec3)>& direction,
                const std::function<Drape(glm::vec2)>& drape_at = nullptr) {
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
      const Drape di = drape_at ? drape_at(uv) : d;
      ed.createWisp(r, p, drape(head, root, direction(uv, n), di),
                    name + " " + std::to_string(j) + "," + std::to_string(i));
    }
  return ed.style();
}

Style ponytail(const HeadModel& head) {
  const glm::vec2 back_uv(0.5f, 0.72f);
  const glm::vec3 back = head.scalpPoint(back_uv), bn = head.scalpNormal(back_uv);
  HairTie tie;
  tie.name = "ponytail tie";
  tie.center = back + 0.03f * bn;
  tie.axis = glm::normalize(glm::vec3(0, -1, -0.35f));
  tie.radius = 0.02f;
  tie.width = 0.014f;
  Style base;
  base.name = "ponytail";
  base.head = head.desc();
  // The style's default hold (1 Hz) for the tail; the hair between scalp
  // and tie is held at the tie's own, stronger hold (HairTie::hold).
  StyleEditor ed(base, head);
  const int nu = 5, nv = 4;
  WispParams params = memberParams(18.0f, 0.02f, 0.12f);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const WispRegion r = cell(i, j, nu, nv);
      const glm::vec2 uv = regionRoot(r, head);
      const glm::vec3 root = head.scalpPoint(uv), n = head.scalpNormal(uv);
      // from the root over the head to just before the tie, through the ring
      // along its axis, then the tail falling away from the head
      std::vector<glm::vec3> key{root};
      const glm::vec3 before = tie.center - 0.035f * tie.axis;
      const glm::vec3 lift = root + 0.012f * n;
      const int n_mid = 4;
      for (int k = 1; k <= n_mid; ++k) {
        const float t = static_cast<float>(k) / (n_mid + 1);
        const glm::vec3 q = (1.0f - t) * lift + t * before;
        key.push_back(pushOff(head, q, 0.008f + 0.01f * t));
      }
      key.push_back(before);
      key.push_back(tie.center);
      // below the ring the tail fans out a little: each wisp towards the
      // side of the head it comes from
      const float side = std::clamp((root.x - tie.center.x) / 0.06f, -1.0f, 1.0f);
      glm::vec3 p = tie.center, dir = glm::normalize(tie.axis + glm::vec3(0.35f * side, 0, 0));
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

    // sideways away from the parting at u = parting, then down
    auto parted = [&](float parting, float lift) {
      return [&head, parting, lift](glm::vec2 uv, glm::vec3 n) {
        const glm::vec3 e = head.scalpTangentU(uv);
        const float side = uv.x < parting ? -1.0f : 1.0f;
        return lift * n + side * e + 0.3f * towardsNape(head, uv);
      };
    };
    std::vector<std::pair<std::string, Style>> styles;
    {
      WispParams p = memberParams(20.0f, 0.008f, 0.08f);
      Drape d;
      d.length = 0.42f;
      styles.emplace_back("long-straight", gridStyle(head, "long-straight", 6, 5, p, d, parted(0.5f, 0.6f)));
    }
    {
      WispParams p = memberParams(22.0f, 0.006f, 0.05f);
      Drape d;
      d.length = 0.17f;
      d.bend = 0.3f;
      d.step = 0.015f;
      d.layering = 0.1f;
      Style s = gridStyle(head, "bob", 6, 5, p, d, parted(0.5f, 1.0f), [&](glm::vec2 uv) {
        Drape e = d;
        e.length = 0.1f + 0.12f * uv.y;  // short at the front, to the chin at the sides and back
        return e;
      });
      styles.emplace_back("bob", s);
    }
    {
      WispParams p = memberParams(20.0f, 0.01f, 0.1f);
      Drape d;
      d.length = 0.3f;
      // everything right of the parting at u = 0.3 is swept over to the right
      auto over = [&head](glm::vec2 uv, glm::vec3 n) {
        const glm::vec3 e = head.scalpTangentU(uv);
        const float side = uv.x < 0.3f ? -1.0f : 1.0f;
        return 0.5f * n + side * e - 0.2f * towardsNape(head, uv);
      };
      styles.emplace_back("side-swept", gridStyle(head, "side-swept", 6, 5, p, d, over));
    }
    {
      // fuller wisps than the others: swept back, neighbouring key strands
      // part over the sides of the head, and narrow wisps show as stripes
      WispParams p = memberParams(20.0f, 0.016f, 0.1f);
      Drape d;
      d.length = 0.28f;
      d.bend = 0.2f;
      auto back = [&head](glm::vec2 uv, glm::vec3 n) { return 0.4f * n + towardsNape(head, uv); };
      styles.emplace_back("swept-back", gridStyle(head, "swept-back", 6, 5, p, d, back));
    }
    {
      WispParams p = memberParams(18.0f, 0.01f, 0.1f);
      p.curl_radius = 0.012f;
      p.curl_period = 0.045f;
      Drape d;
      d.length = 0.38f;
      styles.emplace_back("wavy", gridStyle(head, "wavy", 6, 5, p, d, parted(0.5f, 0.8f)));
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
