// Solids' ray intervals (§12's seam): the spans [t_in, t_out] of t where o + t·d
// lies inside a solid, in the kind's object space and in double, sorted and
// disjoint; what CSG composes. A kind is a solid when `solid_intervals` has an
// overload for it (kSolid<Kind>); triangles, discs and open shapes have no inside.
//   sphere      the two roots of its quadric
//   box         the slab test
//   plane       the half-space dot(p, normal) < distance (an unbounded span)
//   cylinder, cone (closed)
//               the side's quadric cut by the slab of the caps, in one solve
//   torus       walked from its surface: every crossing of the surface in
//               order, entering where the outward normal faces the ray, exiting
//               otherwise (up to two spans)
// Spans are clipped to [tmin, tmax]; a ray that starts inside has t_in = tmin.
// No Embree types.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "runtime/geometry/cone.hpp"
#include "runtime/geometry/sphere.hpp"
#include "runtime/geometry/torus.hpp"
#include "runtime/geometry/xform.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::rt::geom {

// The outward normals (any length, the solid's object space) where the ray enters
// and leaves; a bound clipped to [tmin, tmax] has no surface there and a
// meaningless normal.
struct Span {
  double t_in, t_out;
  Vec3 n_in, n_out;
};

// Up to four spans per primitive (a torus seen edge on has two; room to spare).
struct Spans {
  static constexpr int kMax = 4;
  Span span[kMax];
  int count = 0;
  // Adds [a, b] ∩ [lo, hi] when not empty.
  void add(double a, double b, double lo, double hi, Vec3 na = {}, Vec3 nb = {}) {
    a = ir::max_num(a, lo), b = ir::min_num(b, hi);
    if (a < b && count < kMax) span[count++] = {a, b, na, nb};
  }
};

inline Spans solid_intervals(const ir::Sphere& s, Vec3 o, Vec3 d, double lo, double hi) {
  Spans out;
  double t0, t1;
  if (sphere_roots(o, d, s.center, s.radius, t0, t1))
    out.add(t0, t1, lo, hi, o + d * t0 - s.center, o + d * t1 - s.center);
  return out;
}

inline Spans solid_intervals(const ir::Box& b, Vec3 o, Vec3 d, double lo, double hi) {
  Spans out;
  double a = -INFINITY, z = INFINITY;
  int ka = 0, kz = 0;  // the slabs entered last and left first
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0) {
      if (!(o[k] >= b.min[k] && o[k] <= b.max[k])) return out;
      continue;
    }
    double t0 = (b.min[k] - o[k]) / d[k], t1 = (b.max[k] - o[k]) / d[k];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > a) a = t0, ka = k;
    if (t1 < z) z = t1, kz = k;
  }
  // Entering through a face the ray runs against: its outward normal faces -d.
  Vec3 na, nz;
  na[ka] = d[ka] > 0 ? -1 : 1;
  nz[kz] = d[kz] > 0 ? 1 : -1;
  out.add(a, z, lo, hi, na, nz);
  return out;
}

inline Spans solid_intervals(const ir::Plane& p, Vec3 o, Vec3 d, double lo, double hi) {
  Spans out;
  double s = ir::dot(p.normal, o) - p.distance, dn = ir::dot(p.normal, d);
  if (dn == 0) {
    if (s < 0) out.add(-INFINITY, INFINITY, lo, hi, p.normal, p.normal);
    return out;
  }
  double t = -s / dn;
  if (dn > 0)
    out.add(-INFINITY, t, lo, hi, p.normal, p.normal);  // leaving the half-space
  else
    out.add(t, INFINITY, lo, hi, p.normal, p.normal);
  return out;
}

// A closed surface's crossings along the ray, taken in order into the spans they
// bound. A root found again just past itself (the solvers are good to ulps, not
// exactly) would enter a span twice: a crossing is taken only 64 ulps past the
// last, and one that does not alternate with the last is taken for that same root.
// Spans thinner than that are lost (64 ulps of t, ~1e-14 relative).
class Crossings {
 public:
  Crossings(double lo, double hi) : lo_(lo), hi_(hi), next_(lo), start_(lo) {}
  // Where the next crossing may be, past the last taken.
  double next() const { return next_; }
  bool any() const { return !first_; }
  // A crossing at t (< hi, > next()), entering or leaving, with its outward normal.
  void take(double t, bool entering, Vec3 n) {
    if (first_ && !entering) inside_ = true, start_ = lo_;  // the ray starts inside
    first_ = false;
    if (entering && !inside_) {
      start_ = t, n_start_ = n;
      inside_ = true;
    } else if (!entering && inside_) {
      out_.add(start_, t, lo_, hi_, n_start_, n);
      inside_ = false;
    }
    const double ulp = std::nextafter(std::fabs(t), INFINITY) - std::fabs(t);
    next_ = t + 64 * ulp;
  }
  // The spans. `inside_all`: with no crossing taken, whether the ray is inside the
  // whole way (the first crossing past hi leaves: a closed bounded surface is left
  // before infinity).
  Spans finish(bool inside_all) {
    if (first_) inside_ = inside_all;
    if (inside_) out_.add(start_, hi_, lo_, hi_, n_start_);
    return out_;
  }

 private:
  double lo_, hi_, next_, start_;
  Vec3 n_start_;
  bool inside_ = false, first_ = true;
  Spans out_;
};

// Every crossing of a closed local surface along the ray, in order, each found by
// a solve of its own from just past the last.
template <class L>
Spans walk_surface(const L& l, Vec3 o, Vec3 d, double lo, double hi) {
  ir::Mat4 local_from_object = l.object_from_local.inv;
  Vec3 ol = xform_point(local_from_object, o), dl = xform_vector(local_from_object, d);
  // Normals to the kind's object space: the inverse transpose of object_from_local.
  auto to_object = [&](Vec3 n) { return xform_normal_by_inverse(local_from_object, n); };
  Crossings c(lo, hi);
  for (int i = 0; i < 4 * Spans::kMax; ++i) {
    double th;
    Vec3 n;
    if (!l.intersect(ol, dl, c.next(), hi, th, n)) break;
    c.take(th, ir::dot(n, dl) < 0, to_object(n));
  }
  bool inside_all = false;
  if (!c.any()) {
    double th;
    Vec3 n;
    inside_all = l.intersect(ol, dl, hi, INFINITY, th, n) && !(ir::dot(n, dl) < 0);
  }
  return c.finish(inside_all);
}

// A closed cone's spans from one solve of its quadric and slab (solid_spans), where
// walking its surface solved once per crossing and once more past the last: three
// solves for a ray through it, two fifths of a glass of water's render. Its
// crossings are taken as walk_surface's are (Crossings), so a piece thinner than
// 64 ulps merges with its neighbour, as the two nappes do at a pointed cone's tip:
// the span enters there through the cap's normal, not through the side's, which
// vanishes at the tip.
inline Spans cone_spans(const TruncatedCone& l, Vec3 o, Vec3 d, double lo, double hi) {
  const ir::Mat4 local_from_object = l.object_from_local.inv;
  const Vec3 ol = xform_point(local_from_object, o), dl = xform_vector(local_from_object, d);
  TruncatedCone::Piece p[2];
  const int n = l.solid_spans(ol, dl, lo, hi, p);
  Crossings c(lo, hi);
  for (int k = 0; k < 2 * n; ++k) {
    const bool entering = k % 2 == 0;
    const double t = entering ? p[k / 2].e : p[k / 2].x;
    if (t > c.next() && t < hi)
      c.take(t, entering,
             xform_normal_by_inverse(local_from_object, entering ? p[k / 2].n_e : p[k / 2].n_x));
  }
  bool inside_all = false;
  if (!c.any())  // the first crossing past hi leaves
    for (int k = 0; k < 2 * n; ++k)
      if ((k % 2 == 0 ? p[k / 2].e : p[k / 2].x) > hi) {
        inside_all = k % 2 == 1;
        break;
      }
  return c.finish(inside_all);
}
inline Spans solid_intervals(const ir::Cylinder& c, Vec3 o, Vec3 d, double lo, double hi) {
  if (c.open) return {};
  return cone_spans(TruncatedCone(c), o, d, lo, hi);
}
inline Spans solid_intervals(const ir::Cone& c, Vec3 o, Vec3 d, double lo, double hi) {
  if (c.open) return {};
  return cone_spans(TruncatedCone(c), o, d, lo, hi);
}
inline Spans solid_intervals(const ir::Torus& t, Vec3 o, Vec3 d, double lo, double hi) {
  return walk_surface(TorusSurface(t), o, d, lo, hi);
}

// True for the kinds that have an inside (an open cylinder or cone has none: ask
// has_inside for the value).
template <class K>
concept SolidKind = requires(const K& k, Vec3 v) {
  solid_intervals(k, v, v, 0.0, 1.0);
};
template <class K>
inline constexpr bool kSolid = SolidKind<K>;
inline bool has_inside(const ir::Shape& s) {
  return std::visit(
      [](const auto& g) {
        using K = std::decay_t<decltype(g)>;
        if constexpr (std::is_same_v<K, ir::Cylinder> || std::is_same_v<K, ir::Cone>)
          return !g.open;
        else
          return kSolid<K>;
      },
      s.geom);
}
// The same for every kind, meshes included: a mesh has an inside when its file's
// triangles are closed (MeshData::closed: watertight, consistently wound, outward;
// ir/mesh_topology.hpp). Its intervals are not in this file yet.
inline bool has_inside(const ir::Shape& s, const ir::Scene& scene) {
  if (const ir::Mesh* m = s.as<ir::Mesh>())
    return m->mesh < scene.meshes.size() && scene.meshes[m->mesh].closed;
  return has_inside(s);
}
// Why a shape has no inside, in words an error can quote after "needs a solid:"
// ("mesh 'cup.obj' is not closed: it has 14 boundary edges, e.g. (v3, v7) ...");
// empty when has_inside(s, scene).
inline std::string no_inside_reason(const ir::Shape& s, const ir::Scene& scene) {
  if (has_inside(s, scene)) return "";
  if (const ir::Mesh* m = s.as<ir::Mesh>()) {
    if (m->mesh >= scene.meshes.size()) return "the mesh has no data";
    const ir::MeshData& d = scene.meshes[m->mesh];
    return "mesh '" + d.path + "' is not closed" +
           (d.open_reason.empty() ? std::string() : ": it " + d.open_reason);
  }
  const char* open = s.as<ir::Cylinder>() || s.as<ir::Cone>() ? "an open " : "a ";
  return open + ir::to_string(s.kind()) + " has no inside";
}

}  // namespace snell::rt::geom
