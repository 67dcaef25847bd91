#include "runtime/geometry/mesh_solid.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>

namespace snell::rt::geom {

namespace {

// The device of every mesh solid: made on first use, never released (a BVH can
// outlive any one render's device).
RTCDevice solid_device() {
  static RTCDevice device = rtcNewDevice(nullptr);
  return device;
}

// What the filter function collects: the context first, so Embree's pointer to it
// is a pointer to this.
struct Collect {
  RTCIntersectContext context;
  std::vector<std::uint32_t>* tris;
};

void collect_all(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<Collect*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    c->tris->push_back(RTCHitN_primID(args->hit, args->N, i));
    args->valid[i] = 0;  // rejected: traversal goes on to every other hit
  }
}

// t of o + t·d in the plane of triangle abc, with its (unnormalised) normal.
bool plane_t(Vec3 a, Vec3 b, Vec3 c, Vec3 o, Vec3 d, double& t, Vec3& n) {
  n = ir::cross(b - a, c - a);
  double dn = ir::dot(n, d);
  if (dn == 0) return false;
  t = ir::dot(n, a - o) / dn;
  return std::isfinite(t);
}

}  // namespace

struct MeshSolid::Impl {
  const ir::MeshData* mesh = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
  }
};

MeshSolid::MeshSolid(const ir::MeshData& mesh) : impl_(std::make_unique<Impl>()) {
  impl_->mesh = &mesh;
  RTCDevice dev = solid_device();
  if (!dev) throw std::runtime_error("Embree: cannot make a device for mesh solids");
  impl_->scene = rtcNewScene(dev);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);  // watertight: no ray slips through
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) vb[3 * i + k] = float(mesh.positions[i][k]);
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0,
                                                            RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                            mesh.indices.size() / 3));
  for (std::size_t i = 0; i < mesh.indices.size(); ++i) ib[i] = mesh.indices[i];
  rtcSetGeometryIntersectFilterFunction(g, &collect_all);
  rtcCommitGeometry(g);
  rtcAttachGeometry(impl_->scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(impl_->scene);
}

MeshSolid::~MeshSolid() = default;

std::shared_ptr<const MeshSolid> MeshSolid::of(const ir::MeshData& mesh) {
  static std::mutex m;
  static std::map<const ir::MeshData*, std::weak_ptr<const MeshSolid>> cache;
  std::lock_guard<std::mutex> lock(m);
  std::weak_ptr<const MeshSolid>& slot = cache[&mesh];
  if (auto s = slot.lock()) return s;
  std::shared_ptr<const MeshSolid> s(new MeshSolid(mesh));
  slot = s;
  return s;
}

void MeshSolid::crossings(Vec3 o, Vec3 d, double tnear, std::vector<Crossing>& out,
                          bool& inside) const {
  out.clear();
  inside = false;
  thread_local std::vector<std::uint32_t> tris;
  tris.clear();
  Collect c;
  rtcInitIntersectContext(&c.context);
  c.tris = &tris;
  RTCRayHit rh{};
  rh.ray.org_x = float(o.x), rh.ray.org_y = float(o.y), rh.ray.org_z = float(o.z);
  rh.ray.dir_x = float(d.x), rh.ray.dir_y = float(d.y), rh.ray.dir_z = float(d.z);
  // From a little before tnear: a crossing Embree's float t puts just short of it
  // is still seen, and the double t below decides.
  double span = std::fabs(tnear) * 1e-5;
  rh.ray.tnear = float(std::fmax(0.0, tnear - span));
  rh.ray.tfar = INFINITY;
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &c.context, &rh);
  if (tris.empty()) return;
  const ir::MeshData& m = *impl_->mesh;
  thread_local std::vector<Crossing> all;
  all.clear();
  for (std::uint32_t tri : tris) {
    std::size_t i = 3 * std::size_t(tri);
    double t;
    Vec3 n;
    if (!plane_t(m.positions[m.indices[i]], m.positions[m.indices[i + 1]],
                 m.positions[m.indices[i + 2]], o, d, t, n))
      continue;
    all.push_back({t, n, ir::dot(n, d) < 0, tri});
  }
  std::sort(all.begin(), all.end(), [](const Crossing& a, const Crossing& b) {
    return a.t < b.t || (a.t == b.t && a.tri < b.tri);
  });
  bool first = true, last_enter = false;
  for (const Crossing& x : all) {
    if (!first && x.enter == last_enter) continue;  // the same crossing again
    if (first) inside = !x.enter;
    first = false;
    last_enter = x.enter;
    if (x.t >= tnear)
      out.push_back(x);
    else
      inside = x.enter;  // crossed before tnear: the state after it
  }
}

}  // namespace snell::rt::geom
