#include "runtime/geometry/csg.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <variant>

#include "runtime/geometry/intervals.hpp"
#include "runtime/ir/bounds.hpp"
#include "runtime/ir/dump.hpp"

namespace snell::rt::geom {

namespace {

// Events closer than this fraction of the ray's scale are simultaneous (see
// csg.hpp). Truly coincident faces differ by the rounding of their transforms,
// ~1e-16 relative; the offsets of spawned rays are ~1e-6 relative, so a group
// never swallows the surface a ray just left.
constexpr double kCoincident = 1e-9;

Box3 overlap(const Box3& a, const Box3& b) {
  Box3 r;
  for (int k = 0; k < 3; ++k)
    r.lo[k] = std::fmax(a.lo[k], b.lo[k]), r.hi[k] = std::fmin(a.hi[k], b.hi[k]);
  return r;
}
Box3 unite(const Box3& a, const Box3& b) {
  Box3 r;
  for (int k = 0; k < 3; ++k)
    r.lo[k] = std::fmin(a.lo[k], b.lo[k]), r.hi[k] = std::fmax(a.hi[k], b.hi[k]);
  return r;
}
Box3 infinite_box() {
  Box3 b;
  for (int k = 0; k < 3; ++k) b.lo[k] = -INFINITY, b.hi[k] = INFINITY;
  return b;
}

// [lo, hi] of the ray inside `box` (slab test; false when it misses).
bool ray_box(const Box3& box, Vec3 o, Vec3 d, double lo, double hi) {
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0) {
      if (o[k] < box.lo[k] || o[k] > box.hi[k]) return false;
      continue;
    }
    double inv = 1 / d[k];
    double t0 = (box.lo[k] - o[k]) * inv, t1 = (box.hi[k] - o[k]) * inv;
    if (t0 > t1) std::swap(t0, t1);
    // A little slack: the box is only a filter, and its faces may be a leaf's.
    double pad = 1e-9 * (std::fabs(t0) + std::fabs(t1)) + 1e-300;
    lo = std::fmax(lo, t0 - pad), hi = std::fmin(hi, t1 + pad);
    if (lo > hi) return false;
  }
  return true;
}

Spans leaf_spans(const ir::ShapeGeom& g, Vec3 o, Vec3 d, double lo, double hi) {
  return std::visit(
      [&](const auto& k) -> Spans {
        if constexpr (kSolid<std::decay_t<decltype(k)>>)
          return solid_intervals(k, o, d, lo, hi);
        else
          return {};
      },
      g);
}

struct Event {
  double t;
  std::uint32_t leaf;
  bool enter;
  Vec3 n;
};

}  // namespace

CsgProgram::CsgProgram(const ir::Scene& scene, std::uint32_t root, bool motion) {
  box_ = compile(scene, root, motion);
}

Box3 CsgProgram::compile(const ir::Scene& scene, std::uint32_t index, bool motion) {
  const ir::CsgNode& node = scene.csg_nodes[index];
  if (node.leaf()) {
    const ir::Shape& part = scene.parts[node.part];
    Leaf l;
    l.geom = part.geom;
    l.leaf_from_csg = part.world_from_object().inv;
    if (motion && part.motion().moves()) l.moves = &part;
    l.material = part.material;
    l.part = node.part;
    l.bounded = !ir::unbounded(part);
    if (const ir::Mesh* m = part.as<ir::Mesh>(); m && m->mesh < scene.meshes.size())
      l.mesh = MeshSolid::of(scene.meshes[m->mesh]);
    if (!l.bounded)
      l.box = infinite_box();
    else if (l.moves)
      swept_bounds([&](double u) { return (part.motion().at(u) * part.world_from_object()).m; },
                   [&](auto&& f) {
                     std::visit([&](const auto& g) { ir::hull_points(g, scene, f); }, part.geom);
                   },
                   l.box);
    else
      ir::world_hull_points(part, scene, [&](Vec3 p) { l.box.grow(p); });
    code_.push_back({Op::Leaf, static_cast<std::uint32_t>(leaves_.size())});
    leaves_.push_back(l);
    return l.box;
  }
  Box3 box;
  for (std::size_t i = 0; i < node.children.size(); ++i) {
    Box3 c = compile(scene, node.children[i], motion);
    if (i == 0)
      box = c;
    else if (node.op == ir::CsgOp::Intersection)
      box = overlap(box, c);
    else if (node.op != ir::CsgOp::Difference)
      box = unite(box, c);
  }
  Op::Kind k = node.op == ir::CsgOp::Intersection ? Op::All
               : node.op == ir::CsgOp::Difference ? Op::FirstNotRest
                                                  : Op::Any;
  code_.push_back({k, static_cast<std::uint32_t>(node.children.size())});
  return box;
}

bool CsgProgram::inside(const std::uint8_t* flags) const {
  // The stack holds at most one flag per leaf.
  thread_local std::vector<std::uint8_t> stack;
  stack.clear();
  for (const Op& op : code_) {
    if (op.kind == Op::Leaf) {
      stack.push_back(flags[op.arg]);
      continue;
    }
    std::size_t base = stack.size() - op.arg;
    bool r;
    if (op.kind == Op::Any) {
      r = false;
      for (std::size_t i = base; i < stack.size(); ++i) r = r || stack[i];
    } else if (op.kind == Op::All) {
      r = true;
      for (std::size_t i = base; i < stack.size(); ++i) r = r && stack[i];
    } else {
      r = stack[base];
      for (std::size_t i = base + 1; i < stack.size(); ++i) r = r && !stack[i];
    }
    stack.resize(base);
    stack.push_back(r);
  }
  return !stack.empty() && stack.back();
}

const ir::Mat4& CsgProgram::leaf_at(const Leaf& l, double u, ir::Mat4& scratch) const {
  if (!l.moves) return l.leaf_from_csg;
  scratch =
      (l.moves->motion().inverse_at(u) * ir::InverseTransform::of(l.moves->world_from_object()))
          .inv;
  return scratch;
}

bool CsgProgram::intersect(Vec3 o, Vec3 d, double tnear, double tfar, double& t_hit, Vec3& n_hit,
                           std::uint32_t& leaf_hit, double u) const {
  if (!ray_box(box_, o, d, tnear, tfar)) return false;
  thread_local std::vector<Event> events;
  thread_local std::vector<std::uint8_t> flags;
  events.clear();
  flags.assign(leaves_.size(), 0);
  ir::Mat4 scratch;  // a moving leaf's placement at u
  for (std::uint32_t i = 0; i < leaves_.size(); ++i) {
    const Leaf& l = leaves_[i];
    if (l.bounded && !ray_box(l.box, o, d, tnear, tfar)) continue;
    const ir::Mat4& leaf_from_csg = leaf_at(l, u, scratch);
    Vec3 ol = xform_point(leaf_from_csg, o), dl = xform_vector(leaf_from_csg, d);
    if (l.mesh) {
      thread_local std::vector<MeshSolid::Crossing> cross;
      bool in = false;
      l.mesh->crossings(ol, dl, tnear, cross, in);
      if (in) flags[i] = 1;
      for (const MeshSolid::Crossing& c : cross) {
        if (!(c.t < tfar)) break;
        if (c.t > tnear)
          events.push_back({c.t, i, c.enter, xform_normal_by_inverse(leaf_from_csg, c.n)});
        else
          flags[i] = c.enter;
      }
      continue;
    }
    Spans sp = leaf_spans(l.geom, ol, dl, tnear, tfar);
    for (int k = 0; k < sp.count; ++k) {
      const Span& s = sp.span[k];
      // Normals to CSG space (inverse transpose of csg_from_leaf).
      if (s.t_in > tnear)
        events.push_back({s.t_in, i, true, xform_normal_by_inverse(leaf_from_csg, s.n_in)});
      else
        flags[i] = 1;  // the ray starts inside this leaf
      if (s.t_out < tfar)
        events.push_back({s.t_out, i, false, xform_normal_by_inverse(leaf_from_csg, s.n_out)});
    }
  }
  if (events.empty()) return false;
  std::sort(events.begin(), events.end(), [](const Event& a, const Event& b) {
    return a.t < b.t || (a.t == b.t && a.leaf < b.leaf);
  });
  double dmax = std::fmax(std::fabs(d.x), std::fmax(std::fabs(d.y), std::fabs(d.z)));
  double omax = std::fmax(std::fabs(o.x), std::fmax(std::fabs(o.y), std::fabs(o.z)));
  bool state = inside(flags.data());
  for (std::size_t k = 0; k < events.size();) {
    double tol = kCoincident * (std::fabs(events[k].t) + omax / dmax);
    std::size_t j = k, owner = k;
    for (; j < events.size() && events[j].t - events[k].t <= tol; ++j) {
      flags[events[j].leaf] = events[j].enter;
      if (events[j].leaf < events[owner].leaf) owner = j;
    }
    bool now = inside(flags.data());
    if (now != state) {
      const Event& e = events[owner];
      t_hit = e.t;
      // Out of the result: against the ray where it enters, along it where it leaves.
      n_hit = (ir::dot(e.n, d) < 0) == now ? e.n : -e.n;
      leaf_hit = e.leaf;
      return true;
    }
    k = j;
  }
  return false;
}

double CsgProgram::leaf_crossing(std::uint32_t leaf, Vec3 o, Vec3 d, double t, std::uint32_t* tri,
                                 double u) const {
  const Leaf& l = leaves_[leaf];
  ir::Mat4 scratch;
  const ir::Mat4& leaf_from_csg = leaf_at(l, u, scratch);
  Vec3 ol = xform_point(leaf_from_csg, o), dl = xform_vector(leaf_from_csg, d);
  double best = t, dist = INFINITY;
  if (l.mesh) {
    thread_local std::vector<MeshSolid::Crossing> cross;
    bool in = false;
    l.mesh->crossings(ol, dl, 0, cross, in);
    for (const MeshSolid::Crossing& c : cross)
      if (std::fabs(c.t - t) < dist) {
        best = c.t, dist = std::fabs(c.t - t);
        if (tri) *tri = c.tri;
      }
    return best;
  }
  Spans sp = leaf_spans(l.geom, ol, dl, -INFINITY, INFINITY);
  for (int k = 0; k < sp.count; ++k)
    for (double c : {sp.span[k].t_in, sp.span[k].t_out})
      if (std::isfinite(c) && std::fabs(c - t) < dist) best = c, dist = std::fabs(c - t);
  return best;
}

std::string CsgProgram::to_string() const {
  return fmt::format("csg_program {{ leaves {} ops {} }}", leaves_.size(), code_.size());
}

// ---------------------------------------------------------------------------
// The primitive sets

namespace {
// A CSG object's box is finite unless a plane's half-space is left unbounded:
// then it is clamped here (camera-relative), as far as the compiler lets scenes
// reach (ir::kMaxCameraDistance).
constexpr double kClamp = 1e12;
}  // namespace

template <bool kMoving>
void CsgSetT<kMoving>::add(const ir::Shape& s, const ir::Csg& g, std::uint32_t index, Vec3 origin,
                           const ir::Scene& scene) {
  ir::Transform rel = ir::Transform::translate(-origin) * s.world_from_object();
  prims_.push_back({CsgProgram(scene, g.node, kMoving), &s, origin, rel.inv, rel.m, index});
}

template <bool kMoving>
void CsgSetT<kMoving>::bounds(unsigned prim, Box3& box) const {
  const Prim& p = prims_[prim];
  if constexpr (!kMoving) {
    // Clamped in CSG space first, then again camera-relative (a far clamp corner
    // transformed may overflow the float box otherwise).
    p.program.corners(kClamp, [&](Vec3 c) { box.grow(xform_point(p.rel_from_csg, c)); });
  } else {
    swept_bounds([&](double u) { return rel_at(*p.shape_ir, p.origin, u).m; },
                 [&](auto&& f) { p.program.corners(kClamp, f); }, box);
  }
  for (int k = 0; k < 3; ++k)
    box.lo[k] = std::fmax(box.lo[k], -kClamp), box.hi[k] = std::fmin(box.hi[k], kClamp);
}

template <bool kMoving>
bool CsgSetT<kMoving>::hit(unsigned prim, float time, Vec3f of, Vec3f df, float tnear, float tfar,
                           float& t_out, Vec3f& n_out, unsigned& sub) const {
  const Prim& p = prims_[prim];
  ir::Mat4 csg_from_rel = p.csg_from_rel;
  double u = 0;
  if constexpr (kMoving) {
    // The inverse alone: rel_at(...).inv to the bit, at half the matrix products.
    u = shutter_fraction(time);
    csg_from_rel = rel_from_object_inverse_at(*p.shape_ir, p.origin, u);
  }
  Vec3 o = xform_point(csg_from_rel, Vec3(of.x, of.y, of.z));
  Vec3 d = xform_vector(csg_from_rel, Vec3(df.x, df.y, df.z));
  double t;
  Vec3 n;
  std::uint32_t leaf;
  if (!p.program.intersect(o, d, tnear, tfar, t, n, leaf, u)) return false;
  t_out = static_cast<float>(t);
  if (!(t_out > tnear && t_out < tfar)) return false;
  Vec3 nw = ir::normalize(xform_normal_by_inverse(csg_from_rel, n));
  if (!ir::is_finite(nw)) return false;
  n_out = to_float(nw.x, nw.y, nw.z);
  sub = leaf;
  return true;
}

template <bool kMoving>
void CsgSetT<kMoving>::refine(unsigned prim, const Ray& r, float t, Hit& hit, unsigned sub) const {
  const Prim& p = prims_[prim];
  hit.material = p.program.material(sub);
  hit.part = p.program.part(sub);
  hit.prim = 0, hit.tri_layer = nullptr;  // a mesh leaf's triangle, when refined below
  if constexpr (kMoving) {
    hit.p = r.org + r.dir * t, hit.offset = 0;
  } else {
    // The leaf's own crossing in double, near the float t: the point is then on
    // the leaf's surface to the rounding of p to float (LocalSet::refine's bound).
    Vec3 o = xform_point(p.csg_from_rel, Vec3(r.org.x, r.org.y, r.org.z));
    Vec3 d = xform_vector(p.csg_from_rel, Vec3(r.dir.x, r.dir.y, r.dir.z));
    double tc = p.program.leaf_crossing(sub, o, d, double(t), &hit.prim);
    Vec3 q = xform_point(p.rel_from_csg, o + d * tc);
    if (!ir::is_finite(q) || std::fabs(tc - double(t)) > 1e-3 * std::fabs(double(t)) + 1e-30) {
      hit.p = r.org + r.dir * t, hit.offset = 0;
      return;
    }
    hit.p = to_float(q.x, q.y, q.z);
    hit.offset = float(kSurfaceOffsetUlps * 0x1p-24 * double(max_abs(hit.p)));
  }
}

template class CsgSetT<false>;
template class CsgSetT<true>;

}  // namespace snell::rt::geom
