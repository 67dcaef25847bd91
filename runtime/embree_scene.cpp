// The only translation unit that includes Embree (architecture: one TU per library).
#include "runtime/embree_scene.hpp"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "runtime/shapes.hpp"

namespace snell::rt {

namespace {

using ir::Vec3;
using namespace shapes;

// Outward rounding so float bounds never cut the double surface.
void store_bounds(const double lo[3], const double hi[3], RTCBounds* b) {
  auto down = [](double v) { return std::nextafter(float(v), -INFINITY); };
  auto up = [](double v) { return std::nextafter(float(v), INFINITY); };
  b->lower_x = down(lo[0]), b->lower_y = down(lo[1]), b->lower_z = down(lo[2]);
  b->upper_x = up(hi[0]), b->upper_y = up(hi[1]), b->upper_z = up(hi[2]);
}

struct SphereSet {
  std::vector<SphereData> spheres;
  std::vector<ir::Mat4> rel_from_object;  // for the bounds
};

// A sphere that moves during the open shutter: user geometry whose static bounds
// hold the whole sweep; the intersector places the sphere at the ray's time
// (Motion::at, exact rotation) and intersects it in object space in double.
struct MovingSphere {
  const ir::Shape* shape = nullptr;
  Vec3 origin;
  std::uint32_t index = 0;
};
struct MovingSphereSet {
  std::vector<MovingSphere> spheres;
};

// The object's transform at shutter fraction u, camera-relative.
ir::Transform rel_at(const ir::Shape& s, Vec3 origin, double u) {
  return ir::Transform::translate(-origin) * (s.motion.at(u) * s.world_from_object);
}

SphereData sphere_at(const MovingSphere& m, float time) {
  double u = std::fmin(1.0, std::fmax(0.0, double(time)));  // robustness #32: clamp
  ir::Transform t = rel_at(*m.shape, m.origin, u);
  SphereData d;
  d.object_from_rel = t.inv;
  d.center = m.shape->center;
  d.radius = m.shape->radius;
  d.shape = m.index;
  return d;
}

// Bounds of the sweep: the union of the sphere's boxes at kSweepSteps + 1 times,
// grown by the largest distance a box corner moves between two neighbouring times
// (a point's path between two samples stays within its chord length of either end,
// as long as the path is no longer than twice the chord; true for these steps).
constexpr int kSweepSteps = 64;
void moving_sphere_bounds(const RTCBoundsFunctionArguments* args) {
  auto* set = static_cast<const MovingSphereSet*>(args->geometryUserPtr);
  const MovingSphere& m = set->spheres[args->primID];
  const ir::Shape& s = *m.shape;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  double pad = 0;
  Vec3 prev[8];
  for (int i = 0; i <= kSweepSteps; ++i) {
    ir::Transform t = rel_at(s, m.origin, double(i) / kSweepSteps);
    sphere_box(t.m, s.center, s.radius, lo, hi);
    for (int c = 0; c < 8; ++c) {
      Vec3 q = s.center + Vec3(c & 1 ? s.radius : -s.radius, c & 2 ? s.radius : -s.radius,
                               c & 4 ? s.radius : -s.radius);
      Vec3 w = xform_point(t.m, q);
      if (i > 0) pad = std::fmax(pad, ir::length(w - prev[c]));
      prev[c] = w;
    }
  }
  for (int k = 0; k < 3; ++k) lo[k] -= pad, hi[k] += pad;
  store_bounds(lo, hi, args->bounds_o);
}

// The packet loops of the sphere callbacks, shared by static and moving spheres:
// `sphere_for(time)` gives the sphere a ray sees (moving ones are placed at the
// ray's time). Each valid ray is tested in double (hit_sphere).
template <class SphereFor>
void report_sphere_hits(const RTCIntersectFunctionNArguments* args, SphereFor sphere_for) {
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
  for (unsigned i = 0; i < args->N; ++i) {
    if (!args->valid[i]) continue;
    float t;
    Vec3f n;
    if (!hit_sphere(sphere_for(RTCRayN_time(ray, args->N, i)), RTCRayN_org_x(ray, args->N, i),
                    RTCRayN_org_y(ray, args->N, i), RTCRayN_org_z(ray, args->N, i),
                    RTCRayN_dir_x(ray, args->N, i), RTCRayN_dir_y(ray, args->N, i),
                    RTCRayN_dir_z(ray, args->N, i), RTCRayN_tnear(ray, args->N, i),
                    RTCRayN_tfar(ray, args->N, i), t, n))
      continue;
    RTCRayN_tfar(ray, args->N, i) = t;
    RTCHitN_Ng_x(hit, args->N, i) = n.x;
    RTCHitN_Ng_y(hit, args->N, i) = n.y;
    RTCHitN_Ng_z(hit, args->N, i) = n.z;
    RTCHitN_u(hit, args->N, i) = 0;
    RTCHitN_v(hit, args->N, i) = 0;
    RTCHitN_primID(hit, args->N, i) = args->primID;
    RTCHitN_geomID(hit, args->N, i) = args->geomID;
    RTCHitN_instID(hit, args->N, i, 0) = args->context->instID[0];
  }
}

template <class SphereFor>
void report_sphere_occlusion(const RTCOccludedFunctionNArguments* args, SphereFor sphere_for) {
  RTCRayN* ray = args->ray;
  for (unsigned i = 0; i < args->N; ++i) {
    if (!args->valid[i]) continue;
    float t;
    Vec3f n;
    if (hit_sphere(sphere_for(RTCRayN_time(ray, args->N, i)), RTCRayN_org_x(ray, args->N, i),
                   RTCRayN_org_y(ray, args->N, i), RTCRayN_org_z(ray, args->N, i),
                   RTCRayN_dir_x(ray, args->N, i), RTCRayN_dir_y(ray, args->N, i),
                   RTCRayN_dir_z(ray, args->N, i), RTCRayN_tnear(ray, args->N, i),
                   RTCRayN_tfar(ray, args->N, i), t, n))
      RTCRayN_tfar(ray, args->N, i) = -INFINITY;
  }
}

void moving_sphere_intersect(const RTCIntersectFunctionNArguments* args) {
  const MovingSphere& m =
      static_cast<const MovingSphereSet*>(args->geometryUserPtr)->spheres[args->primID];
  report_sphere_hits(args, [&m](float time) { return sphere_at(m, time); });
}

void moving_sphere_occluded(const RTCOccludedFunctionNArguments* args) {
  const MovingSphere& m =
      static_cast<const MovingSphereSet*>(args->geometryUserPtr)->spheres[args->primID];
  report_sphere_occlusion(args, [&m](float time) { return sphere_at(m, time); });
}

// Triangle soup of one shape in object space, with its winding already outward.
struct Soup {
  std::vector<Vec3> verts;  // three per triangle
};

// Time steps for a moving triangle shape: Embree interpolates vertices linearly
// between steps, exact for pure translation (2 steps). Rotation and scale bend the
// paths, so segments are doubled until every checked vertex's mid-segment position
// is within 1e-4 of the shape's size of the linear interpolation, at most 128
// segments (129 steps, Embree's limit): a 90° turn takes 64 segments; a turn beyond
// ~230° keeps a chord error above 1e-4 (documented limit).
unsigned motion_segments(const ir::Shape& s, const Soup& soup, Vec3 origin) {
  if (soup.verts.empty()) return 1;
  std::vector<Vec3> probe;
  std::size_t stride = std::max<std::size_t>(1, soup.verts.size() / 64);
  for (std::size_t i = 0; i < soup.verts.size(); i += stride) probe.push_back(soup.verts[i]);
  ir::Transform t0 = rel_at(s, origin, 0);
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const Vec3& v : soup.verts) {
    Vec3 w = t0.point(v);
    for (int k = 0; k < 3; ++k) lo[k] = std::fmin(lo[k], w[k]), hi[k] = std::fmax(hi[k], w[k]);
  }
  double size = ir::length(Vec3(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]));
  double tol = 1e-4 * (size > 0 ? size : 1);
  unsigned segs = 1;
  for (; segs < 128; segs *= 2) {
    double err = 0;
    for (unsigned i = 0; i < segs; ++i) {
      ir::Transform a = rel_at(s, origin, double(i) / segs);
      ir::Transform b = rel_at(s, origin, double(i + 1) / segs);
      ir::Transform m = rel_at(s, origin, (i + 0.5) / segs);
      for (const Vec3& v : probe)
        err = std::fmax(err, ir::length(m.point(v) - (a.point(v) + b.point(v)) * 0.5));
    }
    if (err <= tol) break;
  }
  return segs;
}

void sphere_bounds(const RTCBoundsFunctionArguments* args) {
  auto* set = static_cast<const SphereSet*>(args->geometryUserPtr);
  const SphereData& s = set->spheres[args->primID];
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  sphere_box(set->rel_from_object[args->primID], s.center, s.radius, lo, hi);
  store_bounds(lo, hi, args->bounds_o);
}

void sphere_intersect(const RTCIntersectFunctionNArguments* args) {
  const SphereData& s = static_cast<const SphereSet*>(args->geometryUserPtr)->spheres[args->primID];
  report_sphere_hits(args, [&s](float) -> const SphereData& { return s; });
}

void sphere_occluded(const RTCOccludedFunctionNArguments* args) {
  const SphereData& s = static_cast<const SphereSet*>(args->geometryUserPtr)->spheres[args->primID];
  report_sphere_occlusion(args, [&s](float) -> const SphereData& { return s; });
}

// The hit point of a static triangle from Embree's barycentrics, p = v0 + u·e1 + v·e2:
// an error in (u, v) moves p within the plane, never off it (as pbrt-v4's
// Triangle::InteractionFromIntersection rebuilds its hit points). Where the three
// vertices share a coordinate (an axis-aligned face) the edges' component is
// exactly 0 and p keeps that coordinate exactly; b0·v0 + u·v1 + v·v2 would be off
// by an ulp of it, since b0 + u + v rounds (2.4 % of the path through a 1e-5 slab
// 3 units away).
void triangle_point(const float* vb, const unsigned* ib, unsigned prim, float u, float v,
                    Vec3f& p) {
  const float* a = vb + 3 * ib[3 * prim];
  const float* b = vb + 3 * ib[3 * prim + 1];
  const float* c = vb + 3 * ib[3 * prim + 2];
  p = {a[0] + u * (b[0] - a[0]) + v * (c[0] - a[0]), a[1] + u * (b[1] - a[1]) + v * (c[1] - a[1]),
       a[2] + u * (b[2] - a[2]) + v * (c[2] - a[2])};
}

// How far a ray leaving a point of triangle abc must start (Hit::offset), in ulps
// (2^-24) of two sources; a constant of the triangle, computed once:
// - the point's own error off the plane, and Embree's rounding of the vertices when
//   it translates them to the new ray's origin: a few ulps of each coordinate,
//   weighted by how much that coordinate moves along the normal: Σ_i |n_i|·M_i
//   (M_i: largest |v_j,i|). An axis-aligned face needs ulps of its plane coordinate
//   only, however large it is.
// - Embree's normal, rebuilt from rounded edges: its direction is off by the
//   rounding of each component's cross products, seen from the origin over the
//   triangle's extent: Σ_i R_i·(|e1_j e2_k| + |e1_k e2_j|) / |e1 × e2| (R_i: the
//   extent along i). Zero for an axis-aligned face (every product it rounds is
//   along n); large for slivers, whose normal is ill-conditioned.
// kOffsetUlps: hc01's 6e4 random triangles at 1e-8..1e8 see self-hits at 0.5 and
// none from 1 (docs/hardcases.md); 8 leaves a factor 8. A result of 0 (a face in a
// coordinate plane through the camera) falls back to offset_ray_origin.
constexpr float kOffsetUlps = 8;
float triangle_offset(const float* a, const float* b, const float* c) {
  // In double: the cross products of edges 1e10 long overflow float.
  double e1[3], e2[3], big[3], extent[3], n[3];
  for (int i = 0; i < 3; ++i) {
    e1[i] = double(b[i]) - a[i], e2[i] = double(c[i]) - a[i];
    double lo = std::fmin(a[i], std::fmin(b[i], c[i])), hi = std::fmax(a[i], std::fmax(b[i], c[i]));
    big[i] = std::fmax(std::fabs(lo), std::fabs(hi));
    extent[i] = hi - lo;
  }
  double cross_abs = 0, cross_sq = 0;
  for (int i = 0; i < 3; ++i) {
    int j = (i + 1) % 3, k = (i + 2) % 3;
    n[i] = e1[j] * e2[k] - e1[k] * e2[j];
    cross_sq += n[i] * n[i];
    cross_abs += extent[i] * (std::fabs(e1[j] * e2[k]) + std::fabs(e1[k] * e2[j]));
  }
  if (!(cross_sq > 0)) return 0;  // degenerate: never hit
  double len = std::sqrt(cross_sq), w = cross_abs / len;
  for (int i = 0; i < 3; ++i) w += std::fabs(n[i]) / len * big[i];
  double offset = kOffsetUlps * 0x1p-24 * w;
  // Finite and at most a float's range, or 0 (Wächter–Binder) when not.
  return offset < 1e30 ? float(offset) : 0.0f;
}

// The hit point of a static sphere, projected onto the sphere in double (object
// space unless the transform is a similarity): o + t·d from the float t is off the
// surface by ulps of t, radially at normal incidence; the projection leaves only
// the rounding of p to float, ≤ 0.87 ulp of its largest coordinate along the
// normal. The sphere is re-tested in double from the spawned float origin, so a
// few ulps clear it: hc01's sphere test (2000 spheres at 1e-6..1e6, 1e6 rays) sees
// no re-entry even with the one-ulp rounding of spawn_origin alone, and 2502 without
// the projection; kSphereOffsetUlps = 8 matches the triangles' margin. Small
// spheres far away keep their shape: 256 ulps (Wächter–Binder) of 100 units are
// 2e-3, a tenth of a bead of radius 0.02 (hc23's bead: errors 0.134 -> 0.009).
constexpr double kSphereOffsetUlps = 8;  // planes use it too
void sphere_point(const SphereSet& set, unsigned prim, const Ray& r, float t, Hit& hit) {
  const SphereData& s = set.spheres[prim];
  Vec3 p0(double(r.org.x) + double(r.dir.x) * t, double(r.org.y) + double(r.dir.y) * t,
          double(r.org.z) + double(r.dir.z) * t);
  Vec3 p;
  if (s.similarity) {
    // A normalisation, not a Newton step along the normal: p0 is off by ulps of t,
    // which for a tiny sphere far away can be many radii.
    p = s.rel_center + ir::normalize(p0 - s.rel_center) * s.rel_radius;
  } else {
    Vec3 q = xform_point(s.object_from_rel, p0);
    q = s.center + ir::normalize(q - s.center) * s.radius;
    p = xform_point(set.rel_from_object[prim], q);
  }
  if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) {  // p0 at the centre
    hit.p = r.org + r.dir * t, hit.offset = 0;
    return;
  }
  hit.p = to_float(p.x, p.y, p.z);
  hit.offset = float(kSphereOffsetUlps * 0x1p-24 * double(max_abs(hit.p)));
}

void embree_error(void* user, RTCError code, const char* str) {
  auto* msg = static_cast<std::string*>(user);
  if (msg->empty()) *msg = fmt::format("embree error {}: {}", int(code), str ? str : "");
}

}  // namespace

struct EmbreeScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::string error;
  SphereSet spheres;
  MovingSphereSet moving_spheres;
  std::vector<PlaneData> planes;
  // Triangle geometry: per-primitive owner (shape index); area lights: prim / 2;
  // a moving triangle shape has a geometry of its own (geom_shape[geomID]).
  unsigned tri_geom = RTC_INVALID_GEOMETRY_ID, sphere_geom = RTC_INVALID_GEOMETRY_ID,
           moving_sphere_geom = RTC_INVALID_GEOMETRY_ID, light_geom = RTC_INVALID_GEOMETRY_ID;
  std::vector<std::uint32_t> tri_owner;
  // The static triangles' buffers as Embree holds them (camera-relative float), to
  // rebuild hit points from barycentrics.
  const float* tri_vb = nullptr;
  const unsigned* tri_ib = nullptr;
  std::vector<float> tri_offset;         // by primID: triangle_offset
  std::vector<std::int64_t> geom_shape;  // by geomID: the moving shape, or -1
  std::size_t triangle_count = 0, moving_shapes = 0, motion_steps = 0;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  void add_triangles(const std::vector<Vec3>& verts, const std::vector<std::uint32_t>& idx,
                     unsigned& geom_id, const float** vb_out = nullptr,
                     const unsigned** ib_out = nullptr) {
    if (idx.empty()) return;
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), verts.size()));
    for (std::size_t i = 0; i < verts.size(); ++i) {
      vb[3 * i] = float(verts[i].x), vb[3 * i + 1] = float(verts[i].y),
             vb[3 * i + 2] = float(verts[i].z);
    }
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), idx.size() / 3));
    for (std::size_t i = 0; i < idx.size(); ++i) ib[i] = idx[i];
    if (vb_out) *vb_out = vb, *ib_out = ib;
    rtcCommitGeometry(g);
    geom_id = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
  }

  // A moving box/triangle/mesh: Embree motion blur, one vertex buffer per time step,
  // the vertices placed exactly (Motion::at) at each step.
  void add_moving_triangles(const ir::Shape& s, std::uint32_t shape, const Soup& soup,
                            Vec3 origin) {
    if (soup.verts.empty()) return;
    unsigned segs = motion_segments(s, soup, origin);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryTimeStepCount(g, segs + 1);
    for (unsigned step = 0; step <= segs; ++step) {
      ir::Transform t = rel_at(s, origin, double(step) / segs);
      auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, step,
                                                             RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                             soup.verts.size()));
      for (std::size_t i = 0; i < soup.verts.size(); ++i) {
        Vec3 w = t.point(soup.verts[i]);
        vb[3 * i] = float(w.x), vb[3 * i + 1] = float(w.y), vb[3 * i + 2] = float(w.z);
      }
    }
    auto* ib = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                soup.verts.size() / 3));
    for (std::size_t i = 0; i < soup.verts.size(); ++i) ib[i] = unsigned(i);
    rtcCommitGeometry(g);
    unsigned id = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    if (geom_shape.size() <= id) geom_shape.resize(id + 1, -1);
    geom_shape[id] = shape;
    ++moving_shapes;
    motion_steps += segs + 1;
  }
};

namespace {
// The triangles of a box, triangle or mesh in object space, three vertices each,
// wound so that Ng points outward after a transform whose determinant has the sign
// of `flip` (mirroring transforms reverse the winding).
Soup object_triangles(const ir::Scene& sc, const ir::Shape& s, bool flip) {
  Soup out;
  auto tri = [&](Vec3 a, Vec3 b, Vec3 c, bool f) {
    out.verts.push_back(a);
    out.verts.push_back(f ? c : b);
    out.verts.push_back(f ? b : c);
  };
  switch (s.kind) {
    case ir::ShapeKind::Box: {
      Vec3 lo = s.min, hi = s.max;
      auto corner = [&](int i) {
        return Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
      };
      for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
          // The face's four corners in cyclic order, then wound outward.
          int bit = 1 << axis, b1 = 1 << ((axis + 1) % 3), b2 = 1 << ((axis + 2) % 3);
          int f = side ? bit : 0;
          Vec3 q[4] = {corner(f), corner(f | b1), corner(f | b1 | b2), corner(f | b2)};
          Vec3 outward;
          outward[axis] = side ? 1 : -1;
          bool wrong = ir::dot(ir::cross(q[1] - q[0], q[2] - q[0]), outward) < 0;
          tri(q[0], q[1], q[2], flip != wrong);
          tri(q[0], q[2], q[3], flip != wrong);
        }
      break;
    }
    case ir::ShapeKind::Triangle:
      tri(s.a, s.b, s.c, flip);
      break;
    case ir::ShapeKind::Mesh: {
      if (s.mesh >= sc.meshes.size()) break;
      const ir::Mesh& m = sc.meshes[s.mesh];
      for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {
        if (m.indices[i] >= m.positions.size() || m.indices[i + 1] >= m.positions.size() ||
            m.indices[i + 2] >= m.positions.size())
          continue;
        tri(m.positions[m.indices[i]], m.positions[m.indices[i + 1]], m.positions[m.indices[i + 2]],
            flip);
      }
      break;
    }
    default:
      break;
  }
  return out;
}
}  // namespace

EmbreeScene::EmbreeScene(const ir::Scene& sc, ir::Vec3 origin)
    : origin_(origin), impl_(std::make_unique<Impl>()) {
  Impl& im = *impl_;
  im.device = rtcNewDevice(nullptr);
  if (!im.device) throw std::runtime_error("cannot create the Embree device");
  rtcSetDeviceErrorFunction(im.device, embree_error, &im.error);
  im.scene = rtcNewScene(im.device);
  rtcSetSceneBuildQuality(im.scene, RTC_BUILD_QUALITY_HIGH);
  // Robust mode: watertight triangle tests and conservative traversal. Without
  // it, rays aimed exactly at the shared vertices of a closed mesh missed 12.9 %
  // of the time (tests/hardcases, #6); see embree_scene.hpp for the cost.
  rtcSetSceneFlags(im.scene, RTC_SCENE_FLAG_ROBUST);
  // §6/§8: objects move only while the shutter is open; with a closed shutter they
  // stand where their transforms place them (the shutter-open placement).
  bool shutter_open = sc.camera.shutter_close > sc.camera.shutter_open;

  std::vector<Vec3> tv;  // camera-relative vertices (double until the float store)
  std::vector<std::uint32_t> ti;
  for (std::uint32_t si = 0; si < sc.shapes.size(); ++si) {
    const ir::Shape& s = sc.shapes[si];
    const ir::Transform& xf = s.world_from_object;
    bool moving = shutter_open && s.motion.moves();
    bool flip = det3(xf.m) < 0;  // mirroring transforms reverse the winding
    switch (s.kind) {
      case ir::ShapeKind::Sphere: {
        if (moving) {
          im.moving_spheres.spheres.push_back({&s, origin, si});
          ++im.moving_shapes;
          break;
        }
        SphereData d;
        d.object_from_rel = xf.inv * ir::Transform::translate(origin).m;
        d.center = s.center;
        d.radius = s.radius;
        d.shape = si;
        {
          // Similarity test: the columns of the linear part are orthogonal and of
          // equal length (to 1e-12 relative).
          Vec3 c0(xf.m(0, 0), xf.m(1, 0), xf.m(2, 0)), c1(xf.m(0, 1), xf.m(1, 1), xf.m(2, 1)),
              c2(xf.m(0, 2), xf.m(1, 2), xf.m(2, 2));
          double l0 = ir::dot(c0, c0), tol = 1e-12 * l0;
          d.similarity = std::fabs(ir::dot(c1, c1) - l0) <= tol &&
                         std::fabs(ir::dot(c2, c2) - l0) <= tol &&
                         std::fabs(ir::dot(c0, c1)) <= tol && std::fabs(ir::dot(c0, c2)) <= tol &&
                         std::fabs(ir::dot(c1, c2)) <= tol;
          d.rel_center = xf.point(s.center) - origin;
          d.rel_radius = s.radius * std::sqrt(l0);
        }
        im.spheres.spheres.push_back(d);
        im.spheres.rel_from_object.push_back((ir::Transform::translate(-origin) * xf).m);
        break;
      }
      case ir::ShapeKind::Plane: {
        Vec3 p0 = xf.point(s.normal * s.distance) - origin;
        Vec3 n = ir::normalize(xf.normal(s.normal));
        im.planes.push_back({n, ir::dot(n, p0), si, moving ? &s : nullptr});
        if (moving) ++im.moving_shapes;
        break;
      }
      case ir::ShapeKind::Box:
      case ir::ShapeKind::Triangle:
      case ir::ShapeKind::Mesh: {
        Soup soup = object_triangles(sc, s, flip);
        if (moving) {
          im.add_moving_triangles(s, si, soup, origin);
          break;
        }
        for (std::size_t i = 0; i < soup.verts.size(); ++i) {
          tv.push_back(xf.point(soup.verts[i]) - origin);
          ti.push_back(std::uint32_t(tv.size() - 1));
          if (i % 3 == 0) im.tri_owner.push_back(si);
        }
        break;
      }
    }
  }
  im.triangle_count = ti.size() / 3;
  im.add_triangles(tv, ti, im.tri_geom, &im.tri_vb, &im.tri_ib);
  im.tri_offset.resize(ti.size() / 3);
  for (std::size_t t = 0; t < im.tri_offset.size(); ++t)
    im.tri_offset[t] = triangle_offset(im.tri_vb + 3 * ti[3 * t], im.tri_vb + 3 * ti[3 * t + 1],
                                       im.tri_vb + 3 * ti[3 * t + 2]);

  auto add_user = [&](void* data, std::size_t n, RTCBoundsFunction bounds,
                      RTCIntersectFunctionN isect, RTCOccludedFunctionN occl, unsigned& id) {
    if (n == 0) return;
    RTCGeometry g = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(n));
    rtcSetGeometryUserData(g, data);
    rtcSetGeometryBoundsFunction(g, bounds, nullptr);
    rtcSetGeometryIntersectFunction(g, isect);
    rtcSetGeometryOccludedFunction(g, occl);
    rtcCommitGeometry(g);
    id = rtcAttachGeometry(im.scene, g);
    rtcReleaseGeometry(g);
  };
  add_user(&im.spheres, im.spheres.spheres.size(), sphere_bounds, sphere_intersect, sphere_occluded,
           im.sphere_geom);
  add_user(&im.moving_spheres, im.moving_spheres.spheres.size(), moving_sphere_bounds,
           moving_sphere_intersect, moving_sphere_occluded, im.moving_sphere_geom);

  if (!sc.area_lights.empty()) {
    std::vector<Vec3> lv;
    std::vector<std::uint32_t> li;
    for (std::uint32_t k = 0; k < sc.area_lights.size(); ++k) {
      const ir::AreaLight& l = sc.area_lights[k];
      auto base = static_cast<std::uint32_t>(lv.size());
      Vec3 c = l.corner - origin;
      lv.push_back(c);
      lv.push_back(c + l.edge1);
      lv.push_back(c + l.edge1 + l.edge2);
      lv.push_back(c + l.edge2);
      for (std::uint32_t j : {0u, 1u, 2u, 0u, 2u, 3u}) li.push_back(base + j);
    }
    im.add_triangles(lv, li, im.light_geom);
  }
  rtcCommitScene(im.scene);
  if (!im.error.empty()) throw std::runtime_error(im.error);
}

bool EmbreeScene::has_motion() const {
  return impl_->moving_shapes > 0;
}

EmbreeScene::~EmbreeScene() = default;

namespace {
// Planes in double from the float ray; the float origin was already offset by the
// caller, so the sign of (d - n·o) is reliable.
// A moving plane is placed at the ray's time first.
constexpr double kMaxPlaneHit = 1e17;  // camera-relative; scenes lie within 1e12 (ir.hpp)
// `tie`: a distance along the plane's normal within which the plane beats a hit at
// tmax (see EmbreeScene::intersect).
bool hit_plane(const PlaneData& p, const Ray& r, double tmax, double tie, Vec3 origin, double& t,
               Vec3& n_out, Vec3* point = nullptr) {
  Vec3 o(r.org.x, r.org.y, r.org.z), d(r.dir.x, r.dir.y, r.dir.z);
  Vec3 n = p.n;
  double pd = p.d;
  if (p.moving) {
    double u = std::fmin(1.0, std::fmax(0.0, double(r.time)));
    ir::Transform xf = rel_at(*p.moving, origin, u);
    Vec3 p0 = xf.point(p.moving->normal * p.moving->distance);
    n = ir::normalize(xf.normal(p.moving->normal));
    pd = ir::dot(n, p0);
  }
  n_out = n;
  double denom = ir::dot(n, d);
  if (denom == 0) return false;
  t = (pd - ir::dot(n, o)) / denom;
  double tnear = r.tnear;
  if (!((t > tnear) && (t < tmax + tie / std::fabs(denom)) && (static_cast<float>(t) > 0)))
    return false;
  // A grazing hit can land arbitrarily far away; past kMaxPlaneHit the ray is taken
  // to escape, so no ray Embree is given starts beyond its range (FLT_LARGE, 1.8e18).
  Vec3 q = o + d * t;
  if (!(std::fmax(std::fabs(q.x), std::fmax(std::fabs(q.y), std::fabs(q.z))) <= kMaxPlaneHit))
    return false;
  // The hit point, projected onto the plane in double (o + t·d is off it by ulps of t).
  if (point) *point = q - n * (ir::dot(n, q) - pd);
  return true;
}

RTCRayHit make_rayhit(const Ray& r) {
  RTCRayHit rh;
  rh.ray.org_x = r.org.x, rh.ray.org_y = r.org.y, rh.ray.org_z = r.org.z;
  rh.ray.dir_x = r.dir.x, rh.ray.dir_y = r.dir.y, rh.ray.dir_z = r.dir.z;
  rh.ray.tnear = r.tnear;
  rh.ray.tfar = r.tmax;
  rh.ray.time = r.time;
  rh.ray.mask = ~0u;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}
}  // namespace

bool EmbreeScene::intersect(const Ray& r, Hit& hit) const {
  const Impl& im = *impl_;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = make_rayhit(r);
  rtcIntersect1(im.scene, &ctx, &rh);
  bool found = false;
  // Embree's float test overflows on triangles ~1e13 across (t = inf, Ng = 0); the
  // compiler keeps scenes within 1e12 of the camera, and such a hit is a miss here.
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID && rh.ray.tfar < INFINITY &&
      (rh.hit.Ng_x != 0 || rh.hit.Ng_y != 0 || rh.hit.Ng_z != 0)) {
    found = true;
    hit.t = rh.ray.tfar;
    hit.ng = normalize(Vec3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
    if (rh.hit.geomID == im.sphere_geom) {
      hit.kind = Hit::Kind::Shape;
      hit.index = im.spheres.spheres[rh.hit.primID].shape;
    } else if (rh.hit.geomID == im.moving_sphere_geom) {
      hit.kind = Hit::Kind::Shape;
      hit.index = im.moving_spheres.spheres[rh.hit.primID].index;
    } else if (rh.hit.geomID < im.geom_shape.size() && im.geom_shape[rh.hit.geomID] >= 0) {
      hit.kind = Hit::Kind::Shape;
      hit.index = std::uint32_t(im.geom_shape[rh.hit.geomID]);
    } else if (rh.hit.geomID == im.light_geom) {
      hit.kind = Hit::Kind::AreaLight;
      hit.index = rh.hit.primID / 2;
    } else {
      hit.kind = Hit::Kind::Shape;
      hit.index = im.tri_owner[rh.hit.primID];
    }
    if (rh.hit.geomID == im.tri_geom) {
      triangle_point(im.tri_vb, im.tri_ib, rh.hit.primID, rh.hit.u, rh.hit.v, hit.p);
      hit.offset = im.tri_offset[rh.hit.primID];
    } else if (rh.hit.geomID == im.sphere_geom) {
      sphere_point(im.spheres, rh.hit.primID, r, hit.t, hit);
    } else {
      hit.p = r.org + r.dir * hit.t, hit.offset = 0;
    }
  }
  double tmax = found ? double(hit.t) : double(r.tmax);
  // Coincident surfaces (a box resting on a plane: its bottom face and the floor):
  // the face is a float triangle, the plane exact, so their hits differ by rounding
  // and the nearer one flipped from ray to ray (a speckled band at the foot of the
  // glass block in examples/glass). Within the face's error bound (its offset, at
  // least 32 ulps of the point) the plane wins: the floor under a block resting on it.
  double tie = found && !im.planes.empty()
                   ? std::fmax(double(hit.offset), 0x1p-19 * double(max_abs(hit.p)))
                   : 0;
  for (const PlaneData& p : im.planes) {
    double t;
    Vec3 n;
    Vec3 q;
    if (hit_plane(p, r, tmax, tie, origin_, t, n, &q)) {
      tmax = t;
      tie = 0;  // between planes, the nearer t
      found = true;
      hit.t = static_cast<float>(t);
      hit.ng = to_float(n.x, n.y, n.z);
      // Off the plane only by its rounding to float; the plane is re-tested in
      // double from the float origin, so a few ulps clear it (as for spheres).
      hit.p = to_float(q.x, q.y, q.z);
      hit.offset = float(kSphereOffsetUlps * 0x1p-24 * double(max_abs(hit.p)));
      hit.kind = Hit::Kind::Shape;
      hit.index = p.shape;
    }
  }
  return found;
}

bool EmbreeScene::occluded(const Ray& r) const {
  const Impl& im = *impl_;
  for (const PlaneData& p : im.planes) {
    double t;
    Vec3 n;
    if (hit_plane(p, r, r.tmax, 0, origin_, t, n)) return true;
  }
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay ray = make_rayhit(r).ray;
  rtcOccluded1(im.scene, &ctx, &ray);
  return ray.tfar < 0;
}

std::string to_string(const Ray& r) {
  return fmt::format("ray {{ org {} dir {} tmax {} time {} }}", rt::to_string(r.org),
                     rt::to_string(r.dir), r.tmax, r.time);
}

std::string to_string(const Hit& h) {
  return fmt::format("hit {{ t {} ng {} p {} offset {} {} {} }}", h.t, rt::to_string(h.ng),
                     rt::to_string(h.p), h.offset,
                     h.kind == Hit::Kind::Shape ? "shape" : "area_light", h.index);
}

std::string EmbreeScene::to_string() const {
  return fmt::format(
      "embree_scene {{ origin {} spheres {} planes {} triangles {} area_light_tris {} "
      "moving_shapes {} motion_steps {} }}",
      ir::to_string(origin_), impl_->spheres.spheres.size(), impl_->planes.size(),
      impl_->triangle_count, impl_->light_geom == RTC_INVALID_GEOMETRY_ID ? 0 : 2,
      impl_->moving_shapes, impl_->motion_steps);
}

}  // namespace snell::rt
