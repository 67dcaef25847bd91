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
    r.lo[k] = ir::max_num(a.lo[k], b.lo[k]), r.hi[k] = ir::min_num(a.hi[k], b.hi[k]);
  return r;
}
Box3 unite(const Box3& a, const Box3& b) {
  Box3 r;
  for (int k = 0; k < 3; ++k)
    r.lo[k] = ir::min_num(a.lo[k], b.lo[k]), r.hi[k] = ir::max_num(a.hi[k], b.hi[k]);
  return r;
}
Box3 infinite_box() {
  Box3 b;
  for (int k = 0; k < 3; ++k) b.lo[k] = -INFINITY, b.hi[k] = INFINITY;
  return b;
}

// A leaf's box is padded by this fraction of the slab's |t0| + |t1| (a little slack:
// the box is only a filter, and its faces may be a leaf's); a BVH node's by
// kNodePad. A node's box holds its leaves' boxes and IEEE rounding is monotone, so
// its slabs hold theirs; a leaf's |t0| + |t1| is at most twice the node's, so the
// node's pad covers the leaf's: a leaf that passes its own test passes its nodes'.
constexpr double kLeafPad = 1e-9, kNodePad = 4e-9;

// [lo, hi] of the ray inside `box` (slab test; false when it misses).
bool ray_box(const Box3& box, Vec3 o, Vec3 d, double lo, double hi, double pad_factor = kLeafPad) {
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0) {
      if (o[k] < box.lo[k] || o[k] > box.hi[k]) return false;
      continue;
    }
    double inv = 1 / d[k];
    double t0 = (box.lo[k] - o[k]) * inv, t1 = (box.hi[k] - o[k]) * inv;
    if (t0 > t1) std::swap(t0, t1);
    double pad = pad_factor * (std::fabs(t0) + std::fabs(t1)) + 1e-300;
    lo = ir::max_num(lo, t0 - pad), hi = ir::min_num(hi, t1 + pad);
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

}  // namespace

Spans CsgProgram::leaf_spans(const Leaf& l, Vec3 o, Vec3 d, double lo, double hi) {
  if (const auto* c = std::get_if<TruncatedCone>(&l.surface)) return cone_spans(*c, o, d, lo, hi);
  if (const auto* t = std::get_if<TorusSurface>(&l.surface)) return walk_surface(*t, o, d, lo, hi);
  return geom::leaf_spans(l.geom, o, d, lo, hi);
}

namespace {

struct Event {
  double t;
  std::uint32_t leaf, seq;  // seq: the order pushed (a leaf's events in its order)
  bool enter;
  Vec3 n;
};

// A ray's view of a CsgProgram's tree: each node's inside flag and its count of
// operands inside, valid where stamped with the ray's number and otherwise the
// node's all-outside state, so a ray starts in O(1) whatever the tree's size. One
// per thread, shared by every program: a stamp left by another program's ray is an
// older number.
struct RayState {
  std::vector<std::uint32_t> stamp, ntrue;
  std::vector<std::uint8_t> in;
  std::uint32_t ray = 0;
};
thread_local RayState t_ray_state;

}  // namespace

CsgProgram::CsgProgram(const ir::Scene& scene, std::uint32_t root, bool motion) {
  compile(scene, root, motion, box_);
  for (std::uint32_t i = 0; i < leaves_.size(); ++i)
    (leaves_[i].bounded ? bounded_ : unbounded_).push_back(i);
  if (!bounded_.empty()) build_bvh(0, std::uint32_t(bounded_.size()));
}

std::uint32_t CsgProgram::build_bvh(std::uint32_t begin, std::uint32_t end) {
  const std::uint32_t id = std::uint32_t(bvh_.size());
  bvh_.emplace_back();
  Box3 box = leaves_[bounded_[begin]].box, centres;
  auto centre = [&](std::uint32_t leaf, int k) {
    const Box3& b = leaves_[leaf].box;
    return 0.5 * b.lo[k] + 0.5 * b.hi[k];
  };
  for (std::uint32_t i = begin; i < end; ++i) {
    box = unite(box, leaves_[bounded_[i]].box);
    centres.grow(Vec3(centre(bounded_[i], 0), centre(bounded_[i], 1), centre(bounded_[i], 2)));
  }
  bvh_[id].box = box;
  if (end - begin <= 4) {
    bvh_[id].first = begin, bvh_[id].count = end - begin;
    return id;
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (centres.hi[k] - centres.lo[k] > centres.hi[axis] - centres.lo[axis]) axis = k;
  // Median split; ties by leaf index, so the tree is the same on every run.
  const std::uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(bounded_.begin() + begin, bounded_.begin() + mid, bounded_.begin() + end,
                   [&](std::uint32_t a, std::uint32_t b) {
                     double ca = centre(a, axis), cb = centre(b, axis);
                     return ca < cb || (ca == cb && a < b);
                   });
  build_bvh(begin, mid);
  const std::uint32_t right = build_bvh(mid, end);
  bvh_[id].right = right;
  return id;
}

template <class F>
void CsgProgram::for_each_leaf(Vec3 o, Vec3 d, double lo, double hi, F&& f) const {
  for (std::uint32_t leaf : unbounded_) f(leaf);
  if (bvh_.empty()) return;
  // Median splits of at most 2^32 leaves: fewer than 32 levels, so at most 33
  // nodes wait at once.
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::uint32_t id = stack[--top];
    const BvhNode& n = bvh_[id];
    if (!ray_box(n.box, o, d, lo, hi, kNodePad)) continue;
    if (n.count > 0) {
      for (std::uint32_t k = 0; k < n.count; ++k) f(bounded_[n.first + k]);
      continue;
    }
    stack[top++] = n.right;
    stack[top++] = id + 1;
  }
}

std::uint32_t CsgProgram::compile(const ir::Scene& scene, std::uint32_t index, bool motion,
                                  Box3& box_out) {
  const ir::CsgNode& node = scene.csg_nodes[index];
  if (node.leaf()) {
    const ir::Shape& part = scene.parts[node.part];
    Leaf l;
    l.geom = part.geom;
    if (const ir::Cylinder* c = part.as<ir::Cylinder>(); c && !c->open)
      l.surface.emplace<TruncatedCone>(*c);
    else if (const ir::Cone* k = part.as<ir::Cone>(); k && !k->open)
      l.surface.emplace<TruncatedCone>(*k);
    else if (const ir::Torus* t = part.as<ir::Torus>())
      l.surface.emplace<TorusSurface>(*t);
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
    box_out = l.box;
    leaf_node_.push_back(std::uint32_t(nodes_.size()));
    leaves_.push_back(l);
    nodes_.push_back({Node::Leaf});
    return leaf_node_.back();
  }
  std::vector<std::uint32_t> kids;
  for (std::size_t i = 0; i < node.children.size(); ++i) {
    Box3 c;
    kids.push_back(compile(scene, node.children[i], motion, c));
    if (i == 0)
      box_out = c;
    else if (node.op == ir::CsgOp::Intersection)
      box_out = overlap(box_out, c);
    else if (node.op != ir::CsgOp::Difference)
      box_out = unite(box_out, c);
  }
  Node n;
  n.kind = node.op == ir::CsgOp::Intersection ? Node::All
           : node.op == ir::CsgOp::Difference ? Node::FirstNotRest
                                              : Node::Any;
  n.count = std::uint32_t(kids.size());
  const std::uint32_t id = std::uint32_t(nodes_.size());
  for (std::size_t i = 0; i < kids.size(); ++i) {
    Node& k = nodes_[kids[i]];
    k.parent = id, k.first = i == 0;
    if (k.inside0 && !(n.kind == Node::FirstNotRest && i == 0)) ++n.true0;
  }
  if (n.kind == Node::FirstNotRest && !kids.empty()) n.first_child = kids[0];
  n.inside0 = n.kind == Node::Any   ? n.true0 > 0
              : n.kind == Node::All ? n.true0 == n.count
                                    : !kids.empty() && nodes_[kids[0]].inside0 && n.true0 == 0;
  nodes_.push_back(n);
  return id;
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
  RayState& st = t_ray_state;
  if (st.stamp.size() < nodes_.size()) {
    st.stamp.resize(nodes_.size(), 0);
    st.ntrue.resize(nodes_.size());
    st.in.resize(nodes_.size());
  }
  if (++st.ray == 0) {  // the numbers wrapped: no old stamp may pass for this ray's
    std::fill(st.stamp.begin(), st.stamp.end(), 0);
    st.ray = 1;
  }
  auto touch = [&](std::uint32_t id) {
    if (st.stamp[id] == st.ray) return;
    st.stamp[id] = st.ray, st.in[id] = nodes_[id].inside0, st.ntrue[id] = nodes_[id].true0;
  };
  // A leaf's flag, and the operations above it as far as their answers change.
  auto set_leaf = [&](std::uint32_t leaf, bool v) {
    std::uint32_t id = leaf_node_[leaf];
    touch(id);
    if (bool(st.in[id]) == v) return;
    st.in[id] = v;
    for (;;) {
      const Node& c = nodes_[id];
      const std::uint32_t p = c.parent;
      if (p == kNone) return;
      touch(p);
      const Node& pn = nodes_[p];
      if (!(pn.kind == Node::FirstNotRest && c.first)) st.ntrue[p] += v ? 1 : ~0u;
      bool now;
      if (pn.kind == Node::Any) {
        now = st.ntrue[p] > 0;
      } else if (pn.kind == Node::All) {
        now = st.ntrue[p] == pn.count;
      } else {
        touch(pn.first_child);
        now = st.in[pn.first_child] && st.ntrue[p] == 0;
      }
      if (now == bool(st.in[p])) return;
      st.in[p] = now, id = p, v = now;
    }
  };
  auto inside = [&] {
    const std::uint32_t root = std::uint32_t(nodes_.size() - 1);
    return st.stamp[root] == st.ray ? st.in[root] != 0 : nodes_[root].inside0;
  };
  thread_local std::vector<Event> events;
  events.clear();
  ir::Mat4 scratch;  // a moving leaf's placement at u
  for_each_leaf(o, d, tnear, tfar, [&](std::uint32_t i) {
    const Leaf& l = leaves_[i];
    if (l.bounded && !ray_box(l.box, o, d, tnear, tfar)) return;
    const ir::Mat4& leaf_from_csg = leaf_at(l, u, scratch);
    Vec3 ol = xform_point(leaf_from_csg, o), dl = xform_vector(leaf_from_csg, d);
    auto push = [&](double t, bool enter, Vec3 n) {
      events.push_back({t, i, std::uint32_t(events.size()), enter, n});
    };
    if (l.mesh) {
      thread_local std::vector<MeshSolid::Crossing> cross;
      bool in = false;
      l.mesh->crossings(ol, dl, tnear, cross, in);
      if (in) set_leaf(i, true);
      for (const MeshSolid::Crossing& c : cross) {
        if (!(c.t < tfar)) break;
        if (c.t > tnear)
          push(c.t, c.enter, xform_normal_by_inverse(leaf_from_csg, c.n));
        else
          set_leaf(i, c.enter);
      }
      return;
    }
    Spans sp = leaf_spans(l, ol, dl, tnear, tfar);
    for (int k = 0; k < sp.count; ++k) {
      const Span& s = sp.span[k];
      // Normals to CSG space (inverse transpose of csg_from_leaf).
      if (s.t_in > tnear)
        push(s.t_in, true, xform_normal_by_inverse(leaf_from_csg, s.n_in));
      else
        set_leaf(i, true);  // the ray starts inside this leaf
      if (s.t_out < tfar) push(s.t_out, false, xform_normal_by_inverse(leaf_from_csg, s.n_out));
    }
  });
  if (events.empty()) return false;
  // A total order (a leaf's own events in the order its test gave them), so the
  // answer does not depend on the order the BVH visited the leaves.
  std::sort(events.begin(), events.end(), [](const Event& a, const Event& b) {
    return a.t < b.t || (a.t == b.t && (a.leaf < b.leaf || (a.leaf == b.leaf && a.seq < b.seq)));
  });
  double dmax = ir::max_num(std::fabs(d.x), ir::max_num(std::fabs(d.y), std::fabs(d.z)));
  double omax = ir::max_num(std::fabs(o.x), ir::max_num(std::fabs(o.y), std::fabs(o.z)));
  bool state = inside();
  for (std::size_t k = 0; k < events.size();) {
    double tol = kCoincident * (std::fabs(events[k].t) + omax / dmax);
    std::size_t j = k, owner = k;
    for (; j < events.size() && events[j].t - events[k].t <= tol; ++j) {
      set_leaf(events[j].leaf, events[j].enter);
      if (events[j].leaf < events[owner].leaf) owner = j;
    }
    bool now = inside();
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
  Spans sp = leaf_spans(l, ol, dl, -INFINITY, INFINITY);
  for (int k = 0; k < sp.count; ++k)
    for (double c : {sp.span[k].t_in, sp.span[k].t_out})
      if (std::isfinite(c) && std::fabs(c - t) < dist) best = c, dist = std::fabs(c - t);
  return best;
}

std::string CsgProgram::to_string() const {
  return fmt::format("csg_program {{ leaves {} nodes {} bvh_nodes {} unbounded {} }}",
                     leaves_.size(), nodes_.size(), bvh_.size(), unbounded_.size());
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
    box.lo[k] = ir::max_num(box.lo[k], -kClamp), box.hi[k] = ir::min_num(box.hi[k], kClamp);
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
    hit.p = r.org + r.dir * t, hit.offset = unbounded_offset(r, hit.p);
  } else {
    // The leaf's own crossing in double, near the float t: the point is then on
    // the leaf's surface to the rounding of p to float (LocalSet::refine's bound).
    Vec3 o = xform_point(p.csg_from_rel, Vec3(r.org.x, r.org.y, r.org.z));
    Vec3 d = xform_vector(p.csg_from_rel, Vec3(r.dir.x, r.dir.y, r.dir.z));
    double tc = p.program.leaf_crossing(sub, o, d, double(t), &hit.prim);
    Vec3 q = xform_point(p.rel_from_csg, o + d * tc);
    if (!ir::is_finite(q) || std::fabs(tc - double(t)) > 1e-3 * std::fabs(double(t)) + 1e-30) {
      hit.p = r.org + r.dir * t, hit.offset = unbounded_offset(r, hit.p);
      return;
    }
    hit.p = to_float(q.x, q.y, q.z);
    hit.offset = float(kSurfaceOffsetUlps * 0x1p-24 * double(max_abs(hit.p)));
  }
}

template class CsgSetT<false>;
template class CsgSetT<true>;

}  // namespace snell::rt::geom
