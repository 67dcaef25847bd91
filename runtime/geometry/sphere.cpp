#include "runtime/geometry/sphere.hpp"

#include "runtime/geometry/motion.hpp"

namespace snell::rt::geom {

void SphereSet::add(const ir::Shape& s, const ir::Sphere& g, std::uint32_t index, Vec3 origin) {
  const ir::Transform& xf = s.world_from_object();
  origin_ = origin;
  Static d;
  d.ir = &s;
  d.shape = index;
  // Similarity test: the columns of the linear part are orthogonal and of equal
  // length (to 1e-12 relative).
  Vec3 c0(xf.m(0, 0), xf.m(1, 0), xf.m(2, 0)), c1(xf.m(0, 1), xf.m(1, 1), xf.m(2, 1)),
      c2(xf.m(0, 2), xf.m(1, 2), xf.m(2, 2));
  double l0 = ir::dot(c0, c0), tol = 1e-12 * l0;
  bool similarity = std::fabs(ir::dot(c1, c1) - l0) <= tol &&
                    std::fabs(ir::dot(c2, c2) - l0) <= tol && std::fabs(ir::dot(c0, c1)) <= tol &&
                    std::fabs(ir::dot(c0, c2)) <= tol && std::fabs(ir::dot(c1, c2)) <= tol;
  d.rel_center = xf.point(g.center) - origin;
  d.rel_radius = g.radius * std::sqrt(l0);
  if (!similarity) {
    d.general = static_cast<std::uint32_t>(general_.size());
    general_.push_back({xf.inv * ir::Transform::translate(origin).m,
                        (ir::Transform::translate(-origin) * xf).m, g.center, g.radius});
  }
  spheres_.push_back(d);
}

void SphereSet::bounds(unsigned prim, Box3& box) const {
  const Static& s = spheres_[prim];
  const ir::Sphere& g = *s.ir->as<ir::Sphere>();
  sphere_box(ir::Transform::translate(-origin_).m * s.ir->world_from_object().m, g.center, g.radius,
             box.lo, box.hi);
}

// The hit point of a static sphere, projected onto the sphere in double (object
// space unless the transform is a similarity): o + t·d from the float t is off the
// surface by ulps of t, radially at normal incidence; the projection leaves only
// the rounding of p to float, ≤ 0.87 ulp of its largest coordinate along the
// normal. The sphere is re-tested in double from the spawned float origin, so a
// few ulps clear it: hc01's sphere test (2000 spheres at 1e-6..1e6, 1e6 rays) sees
// no re-entry even with the one-ulp rounding of spawn_origin alone, and 2502 without
// the projection; kSurfaceOffsetUlps = 8 matches the triangles' margin. Small
// spheres far away keep their shape: 256 ulps (Wächter–Binder) of 100 units are
// 2e-3, a tenth of a bead of radius 0.02 (hc23's bead: errors 0.134 -> 0.009).
void SphereSet::refine(unsigned prim, const Ray& r, float t, Hit& hit) const {
  const Static& s = spheres_[prim];
  Vec3 p0(double(r.org.x) + double(r.dir.x) * t, double(r.org.y) + double(r.dir.y) * t,
          double(r.org.z) + double(r.dir.z) * t);
  Vec3 p;
  if (s.general == kSimilar) {
    // A normalisation, not a Newton step along the normal: p0 is off by ulps of t,
    // which for a tiny sphere far away can be many radii. One division (r / |v|),
    // not normalize's three: the point is rounded to float after.
    const Vec3 v = p0 - s.rel_center;
    p = s.rel_center + v * (s.rel_radius / ir::length(v));
  } else {
    const General& g = general_[s.general];
    const Vec3 v = xform_point(g.object_from_rel, p0) - g.center;
    const Vec3 q = g.center + v * (g.radius / ir::length(v));
    p = xform_point(g.rel_from_object, q);
  }
  if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) {  // p0 at the centre
    hit.p = r.org + r.dir * t, hit.offset = unbounded_offset(r, hit.p);
    return;
  }
  hit.p = to_float(p.x, p.y, p.z);
  hit.offset = float(kSurfaceOffsetUlps * 0x1p-24 * double(max_abs(hit.p)));
}

void MovingSphereSet::add(const ir::Shape& s, const ir::Sphere& g, std::uint32_t index,
                          Vec3 origin) {
  Moving m{&s, g, origin, index, {}};
  // Each part's box: the sphere's boxes at kSub + 1 times over it, grown by the
  // most any face moves between two of them (as bounds() grows the sweep) and by
  // 1e-6 of the box's reach, so the double slab test never turns away a ray
  // that grazes the sphere.
  constexpr unsigned kSub = 8;
  for (unsigned p = 0; p < kSegments; ++p) {
    Box3& part = m.part[p];
    Box3 prev;
    double grow = 0;
    for (unsigned j = 0; j <= kSub; ++j) {
      Box3 b;
      double u = (double(p) + double(j) / kSub) / kSegments;
      sphere_box(rel_at(s, origin, u).m, g.center, g.radius, b.lo, b.hi);
      for (int k = 0; k < 3; ++k) {
        part.lo[k] = ir::min_num(part.lo[k], b.lo[k]),
        part.hi[k] = ir::max_num(part.hi[k], b.hi[k]);
        if (j > 0)
          grow = ir::max_num(
              grow, ir::max_num(std::fabs(b.lo[k] - prev.lo[k]), std::fabs(b.hi[k] - prev.hi[k])));
      }
      prev = b;
    }
    double reach = 0;
    for (int k = 0; k < 3; ++k)
      reach = ir::max_num(reach, ir::max_num(std::fabs(part.lo[k]), std::fabs(part.hi[k])));
    grow += 1e-6 * reach;
    for (int k = 0; k < 3; ++k) part.lo[k] -= grow, part.hi[k] += grow;
  }
  spheres_.push_back(m);
}

SphereData MovingSphereSet::at(const Moving& m, float time) {
  SphereData d;
  d.object_from_rel = rel_from_object_inverse_at(*m.shape, m.origin, shutter_fraction(time));
  d.center = m.sphere.center;
  d.radius = m.sphere.radius;
  return d;
}

// Bounds of the sweep: the union of the sphere's boxes at kSweepSteps + 1 times,
// grown by the largest distance a box corner moves between two neighbouring times
// (a point's path between two samples stays within its chord length of either end,
// as long as the path is no longer than twice the chord; true for these steps).
constexpr int kSweepSteps = 64;
void MovingSphereSet::bounds(unsigned prim, Box3& box) const {
  const Moving& m = spheres_[prim];
  const ir::Sphere& s = m.sphere;
  double pad = 0;
  Vec3 prev[8];
  for (int i = 0; i <= kSweepSteps; ++i) {
    ir::Transform t = rel_at(*m.shape, m.origin, double(i) / kSweepSteps);
    sphere_box(t.m, s.center, s.radius, box.lo, box.hi);
    for (int c = 0; c < 8; ++c) {
      Vec3 q = s.center + Vec3(c & 1 ? s.radius : -s.radius, c & 2 ? s.radius : -s.radius,
                               c & 4 ? s.radius : -s.radius);
      Vec3 w = xform_point(t.m, q);
      if (i > 0) pad = ir::max_num(pad, ir::length(w - prev[c]));
      prev[c] = w;
    }
  }
  for (int k = 0; k < 3; ++k) box.lo[k] -= pad, box.hi[k] += pad;
}

}  // namespace snell::rt::geom
