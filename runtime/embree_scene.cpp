// The only translation unit that includes Embree (architecture: one TU per library).
#include "runtime/embree_scene.hpp"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace snell::rt {

namespace {

using ir::Vec3;

// A sphere prepared for object-space intersection from camera-relative rays.
struct SphereData {
  ir::Mat4 object_from_rel;  // camera-relative world -> object space
  Vec3 center;
  double radius = 1;
  // A similarity transform (rotation, uniform scale, translation) keeps a sphere a
  // sphere: then it is intersected directly in camera-relative space, skipping the
  // per-ray matrix products (most scenes' spheres).
  bool similarity = false;
  Vec3 rel_center;
  double rel_radius = 1;
  std::uint32_t shape = 0;
};

struct PlaneData {
  Vec3 n;       // unit world normal
  double d = 0; // dot(n, x) = d for camera-relative x
  std::uint32_t shape = 0;
};

Vec3 xform_point(const ir::Mat4& m, Vec3 p) {
  return {m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2) * p.z + m(0, 3),
          m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2) * p.z + m(1, 3),
          m(2, 0) * p.x + m(2, 1) * p.y + m(2, 2) * p.z + m(2, 3)};
}
Vec3 xform_vector(const ir::Mat4& m, Vec3 v) {
  return {m(0, 0) * v.x + m(0, 1) * v.y + m(0, 2) * v.z,
          m(1, 0) * v.x + m(1, 1) * v.y + m(1, 2) * v.z,
          m(2, 0) * v.x + m(2, 1) * v.y + m(2, 2) * v.z};
}
// Normal to world: inverse transpose of world_from_object = transpose of object_from_world.
Vec3 xform_normal_by_inverse(const ir::Mat4& inv, Vec3 n) {
  return {inv(0, 0) * n.x + inv(1, 0) * n.y + inv(2, 0) * n.z,
          inv(0, 1) * n.x + inv(1, 1) * n.y + inv(2, 1) * n.z,
          inv(0, 2) * n.x + inv(1, 2) * n.y + inv(2, 2) * n.z};
}
double det3(const ir::Mat4& m) {
  return m(0, 0) * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1)) -
         m(0, 1) * (m(1, 0) * m(2, 2) - m(1, 2) * m(2, 0)) +
         m(0, 2) * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0));
}

// Smallest and largest roots of |o + t d - c|² = r² in double, with the
// discriminant in the cancellation-free form of Haines et al. (RTG ch. 7).
bool sphere_roots(Vec3 o, Vec3 d, Vec3 c, double r, double& t0, double& t1) {
  Vec3 f = o - c;
  double a = ir::dot(d, d);
  double b = ir::dot(f, d);  // half of the usual b
  Vec3 v = f - d * (b / a);
  double lv = ir::length(v);
  double disc = (r + lv) * (r - lv);  // r² - |v|², i.e. the discriminant / (4a)
  if (!(disc >= 0)) return false;
  double cc = ir::dot(f, f) - r * r;
  double q = -b - std::copysign(std::sqrt(a * disc), b);
  if (q == 0) {  // ray through the centre aimed... degenerate only for a = 0 or o = c
    double s = std::sqrt(disc / a);
    t0 = -s, t1 = s;
    return a > 0;
  }
  t0 = cc / q;
  t1 = q / a;
  if (t0 > t1) std::swap(t0, t1);
  return true;
}

struct SphereSet {
  std::vector<SphereData> spheres;
};

// Intersects sphere `s` with a camera-relative float ray; returns the nearest t in
// (tnear, tfar) and the outward unit world normal.
bool hit_sphere(const SphereData& s, float ox, float oy, float oz, float dx, float dy, float dz,
                float tnear, float tfar, float& t_out, Vec3f& n_out) {
  double t0, t1;
  if (s.similarity) {
    Vec3 o(ox, oy, oz), d(dx, dy, dz);
    if (!sphere_roots(o, d, s.rel_center, s.rel_radius, t0, t1)) return false;
    double t = t0 > tnear ? t0 : t1;
    if (!(t > tnear) || !(t < tfar)) return false;
    t_out = static_cast<float>(t);
    if (!(t_out > tnear && t_out < tfar)) return false;
    Vec3 n = (o + d * t - s.rel_center) / s.rel_radius;
    n = ir::normalize(n);
    n_out = to_float(n.x, n.y, n.z);
    return true;
  }
  Vec3 o = xform_point(s.object_from_rel, Vec3(ox, oy, oz));
  Vec3 d = xform_vector(s.object_from_rel, Vec3(dx, dy, dz));
  if (!sphere_roots(o, d, s.center, s.radius, t0, t1)) return false;
  double t = t0 > tnear ? t0 : t1;
  if (!(t > tnear) || !(t < tfar)) return false;
  Vec3 no = (o + d * t - s.center) / s.radius;
  Vec3 nw = ir::normalize(xform_normal_by_inverse(s.object_from_rel, no));
  t_out = static_cast<float>(t);
  if (!(t_out > tnear && t_out < tfar)) return false;
  n_out = to_float(nw.x, nw.y, nw.z);
  return true;
}

void sphere_bounds(const RTCBoundsFunctionArguments* args) {
  auto* set = static_cast<const SphereSet*>(args->geometryUserPtr);
  const SphereData& s = set->spheres[args->primID];
  // World-relative bounds of the transformed object-space box around the sphere.
  ir::Mat4 rel_from_object;
  {
    // Invert the affine object_from_rel through its 3x3 adjugate.
    const ir::Mat4& m = s.object_from_rel;
    double det = det3(m);
    ir::Mat4 inv;
    inv(0, 0) = (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1)) / det;
    inv(0, 1) = (m(0, 2) * m(2, 1) - m(0, 1) * m(2, 2)) / det;
    inv(0, 2) = (m(0, 1) * m(1, 2) - m(0, 2) * m(1, 1)) / det;
    inv(1, 0) = (m(1, 2) * m(2, 0) - m(1, 0) * m(2, 2)) / det;
    inv(1, 1) = (m(0, 0) * m(2, 2) - m(0, 2) * m(2, 0)) / det;
    inv(1, 2) = (m(0, 2) * m(1, 0) - m(0, 0) * m(1, 2)) / det;
    inv(2, 0) = (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0)) / det;
    inv(2, 1) = (m(0, 1) * m(2, 0) - m(0, 0) * m(2, 1)) / det;
    inv(2, 2) = (m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0)) / det;
    for (int r = 0; r < 3; ++r)
      inv(r, 3) = -(inv(r, 0) * m(0, 3) + inv(r, 1) * m(1, 3) + inv(r, 2) * m(2, 3));
    rel_from_object = inv;
  }
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int i = 0; i < 8; ++i) {
    Vec3 c = s.center + Vec3(i & 1 ? s.radius : -s.radius, i & 2 ? s.radius : -s.radius,
                             i & 4 ? s.radius : -s.radius);
    Vec3 w = xform_point(rel_from_object, c);
    for (int k = 0; k < 3; ++k) lo[k] = std::fmin(lo[k], w[k]), hi[k] = std::fmax(hi[k], w[k]);
  }
  // Round outward so float bounds never cut the double surface.
  auto down = [](double v) { return std::nextafter(float(v), -INFINITY); };
  auto up = [](double v) { return std::nextafter(float(v), INFINITY); };
  RTCBounds* b = args->bounds_o;
  b->lower_x = down(lo[0]), b->lower_y = down(lo[1]), b->lower_z = down(lo[2]);
  b->upper_x = up(hi[0]), b->upper_y = up(hi[1]), b->upper_z = up(hi[2]);
}

void sphere_intersect(const RTCIntersectFunctionNArguments* args) {
  auto* set = static_cast<const SphereSet*>(args->geometryUserPtr);
  const SphereData& s = set->spheres[args->primID];
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
  for (unsigned i = 0; i < args->N; ++i) {
    if (!args->valid[i]) continue;
    float t;
    Vec3f n;
    if (!hit_sphere(s, RTCRayN_org_x(ray, args->N, i), RTCRayN_org_y(ray, args->N, i),
                    RTCRayN_org_z(ray, args->N, i), RTCRayN_dir_x(ray, args->N, i),
                    RTCRayN_dir_y(ray, args->N, i), RTCRayN_dir_z(ray, args->N, i),
                    RTCRayN_tnear(ray, args->N, i), RTCRayN_tfar(ray, args->N, i), t, n))
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

void sphere_occluded(const RTCOccludedFunctionNArguments* args) {
  auto* set = static_cast<const SphereSet*>(args->geometryUserPtr);
  const SphereData& s = set->spheres[args->primID];
  for (unsigned i = 0; i < args->N; ++i) {
    if (!args->valid[i]) continue;
    float t;
    Vec3f n;
    RTCRayN* ray = args->ray;
    if (hit_sphere(s, RTCRayN_org_x(ray, args->N, i), RTCRayN_org_y(ray, args->N, i),
                   RTCRayN_org_z(ray, args->N, i), RTCRayN_dir_x(ray, args->N, i),
                   RTCRayN_dir_y(ray, args->N, i), RTCRayN_dir_z(ray, args->N, i),
                   RTCRayN_tnear(ray, args->N, i), RTCRayN_tfar(ray, args->N, i), t, n))
      RTCRayN_tfar(ray, args->N, i) = -INFINITY;
  }
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
  std::vector<PlaneData> planes;
  // Triangle geometry: per-primitive owner (shape index); area lights: prim / 2.
  unsigned tri_geom = RTC_INVALID_GEOMETRY_ID, sphere_geom = RTC_INVALID_GEOMETRY_ID,
           light_geom = RTC_INVALID_GEOMETRY_ID;
  std::vector<std::uint32_t> tri_owner;
  std::size_t triangle_count = 0;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  void add_triangles(const std::vector<Vec3>& verts, const std::vector<std::uint32_t>& idx,
                     const std::vector<std::uint32_t>& owner, unsigned& geom_id) {
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
    rtcCommitGeometry(g);
    geom_id = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    (void)owner;
  }
};

EmbreeScene::EmbreeScene(const ir::Scene& sc, ir::Vec3 origin)
    : origin_(origin), impl_(std::make_unique<Impl>()) {
  Impl& im = *impl_;
  im.device = rtcNewDevice(nullptr);
  if (!im.device) throw std::runtime_error("cannot create the Embree device");
  rtcSetDeviceErrorFunction(im.device, embree_error, &im.error);
  im.scene = rtcNewScene(im.device);
  rtcSetSceneBuildQuality(im.scene, RTC_BUILD_QUALITY_HIGH);

  std::vector<Vec3> tv;  // camera-relative vertices (double until the float store)
  std::vector<std::uint32_t> ti;
  auto add_tri = [&](const ir::Transform& xf, bool flip, Vec3 a, Vec3 b, Vec3 c,
                     std::uint32_t shape) {
    auto base = static_cast<std::uint32_t>(tv.size());
    tv.push_back(xf.point(a) - origin);
    tv.push_back(xf.point(b) - origin);
    tv.push_back(xf.point(c) - origin);
    ti.push_back(base);
    ti.push_back(flip ? base + 2 : base + 1);
    ti.push_back(flip ? base + 1 : base + 2);
    im.tri_owner.push_back(shape);
  };

  for (std::uint32_t si = 0; si < sc.shapes.size(); ++si) {
    const ir::Shape& s = sc.shapes[si];
    const ir::Transform& xf = s.world_from_object;
    bool flip = det3(xf.m) < 0;  // mirroring transforms reverse the winding
    switch (s.kind) {
      case ir::ShapeKind::Sphere: {
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
        break;
      }
      case ir::ShapeKind::Plane: {
        Vec3 p0 = xf.point(s.normal * s.distance) - origin;
        Vec3 n = ir::normalize(xf.normal(s.normal));
        im.planes.push_back({n, ir::dot(n, p0), si});
        break;
      }
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
            add_tri(xf, flip != wrong, q[0], q[1], q[2], si);
            add_tri(xf, flip != wrong, q[0], q[2], q[3], si);
          }
        break;
      }
      case ir::ShapeKind::Triangle:
        add_tri(xf, flip, s.a, s.b, s.c, si);
        break;
      case ir::ShapeKind::Mesh: {
        if (s.mesh >= sc.meshes.size()) break;
        const ir::Mesh& m = sc.meshes[s.mesh];
        for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {
          if (m.indices[i] >= m.positions.size() || m.indices[i + 1] >= m.positions.size() ||
              m.indices[i + 2] >= m.positions.size())
            continue;
          add_tri(xf, flip, m.positions[m.indices[i]], m.positions[m.indices[i + 1]],
                  m.positions[m.indices[i + 2]], si);
        }
        break;
      }
    }
  }
  im.triangle_count = ti.size() / 3;
  im.add_triangles(tv, ti, im.tri_owner, im.tri_geom);

  if (!im.spheres.spheres.empty()) {
    RTCGeometry g = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(im.spheres.spheres.size()));
    rtcSetGeometryUserData(g, &im.spheres);
    rtcSetGeometryBoundsFunction(g, sphere_bounds, nullptr);
    rtcSetGeometryIntersectFunction(g, sphere_intersect);
    rtcSetGeometryOccludedFunction(g, sphere_occluded);
    rtcCommitGeometry(g);
    im.sphere_geom = rtcAttachGeometry(im.scene, g);
    rtcReleaseGeometry(g);
  }

  if (!sc.area_lights.empty()) {
    std::vector<Vec3> lv;
    std::vector<std::uint32_t> li, lo;
    for (std::uint32_t k = 0; k < sc.area_lights.size(); ++k) {
      const ir::AreaLight& l = sc.area_lights[k];
      auto base = static_cast<std::uint32_t>(lv.size());
      Vec3 c = l.corner - origin;
      lv.push_back(c);
      lv.push_back(c + l.edge1);
      lv.push_back(c + l.edge1 + l.edge2);
      lv.push_back(c + l.edge2);
      for (std::uint32_t j : {0u, 1u, 2u, 0u, 2u, 3u}) li.push_back(base + j);
      lo.push_back(k);
      lo.push_back(k);
    }
    im.add_triangles(lv, li, lo, im.light_geom);
  }
  rtcCommitScene(im.scene);
  if (!im.error.empty()) throw std::runtime_error(im.error);
}

EmbreeScene::~EmbreeScene() = default;

namespace {
// Planes in double from the float ray; the float origin was already offset by the
// caller, so the sign of (d - n·o) is reliable.
bool hit_plane(const PlaneData& p, const Ray& r, double tmax, double& t) {
  Vec3 o(r.org.x, r.org.y, r.org.z), d(r.dir.x, r.dir.y, r.dir.z);
  double denom = ir::dot(p.n, d);
  if (denom == 0) return false;
  t = (p.d - ir::dot(p.n, o)) / denom;
  return t > 0 && t < tmax && static_cast<float>(t) > 0;
}

RTCRayHit make_rayhit(const Ray& r) {
  RTCRayHit rh;
  rh.ray.org_x = r.org.x, rh.ray.org_y = r.org.y, rh.ray.org_z = r.org.z;
  rh.ray.dir_x = r.dir.x, rh.ray.dir_y = r.dir.y, rh.ray.dir_z = r.dir.z;
  rh.ray.tnear = 0;
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
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
    found = true;
    hit.t = rh.ray.tfar;
    hit.ng = normalize(Vec3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
    if (rh.hit.geomID == im.sphere_geom) {
      hit.kind = Hit::Kind::Shape;
      hit.index = im.spheres.spheres[rh.hit.primID].shape;
    } else if (rh.hit.geomID == im.light_geom) {
      hit.kind = Hit::Kind::AreaLight;
      hit.index = rh.hit.primID / 2;
    } else {
      hit.kind = Hit::Kind::Shape;
      hit.index = im.tri_owner[rh.hit.primID];
    }
  }
  double tmax = found ? double(hit.t) : double(r.tmax);
  for (const PlaneData& p : im.planes) {
    double t;
    if (hit_plane(p, r, tmax, t)) {
      tmax = t;
      found = true;
      hit.t = static_cast<float>(t);
      hit.ng = to_float(p.n.x, p.n.y, p.n.z);
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
    if (hit_plane(p, r, r.tmax, t)) return true;
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
  return fmt::format("hit {{ t {} ng {} {} {} }}", h.t, rt::to_string(h.ng),
                     h.kind == Hit::Kind::Shape ? "shape" : "area_light", h.index);
}

std::string EmbreeScene::to_string() const {
  return fmt::format(
      "embree_scene {{ origin {} spheres {} planes {} triangles {} area_light_tris {} }}",
      ir::to_string(origin_), impl_->spheres.spheres.size(), impl_->planes.size(),
      impl_->triangle_count, impl_->light_geom == RTC_INVALID_GEOMETRY_ID ? 0 : 2);
}

}  // namespace snell::rt
