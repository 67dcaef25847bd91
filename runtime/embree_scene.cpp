// The only translation unit that includes Embree (architecture: one TU per
// library). It builds the BVH per geometry class of runtime/geometry/traits.hpp,
// never per shape kind, and finds a hit's shape and hit-point refinement through
// one table indexed by Embree's geometry ID.
#include "runtime/embree_scene.hpp"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <new>
#include <stdexcept>
#include <tuple>
#include <type_traits>
#include <unordered_map>
#include <variant>

#include "runtime/geometry/motion.hpp"
#include "runtime/geometry/sphere_lanes.hpp"
#include "runtime/geometry/traits.hpp"
#include "runtime/ir/bounds.hpp"
#include "runtime/ray_packet.hpp"

namespace snell::rt {

namespace {

using ir::Vec3;
using namespace geom;

// Outward rounding so float bounds never cut the double surface.
void store_bounds(const double lo[3], const double hi[3], RTCBounds* b) {
  auto down = [](double v) { return std::nextafter(float(v), -INFINITY); };
  auto up = [](double v) { return std::nextafter(float(v), INFINITY); };
  b->lower_x = down(lo[0]), b->lower_y = down(lo[1]), b->lower_z = down(lo[2]);
  b->upper_x = up(hi[0]), b->upper_y = up(hi[1]), b->upper_z = up(hi[2]);
}

// The user-geometry callbacks, one instantiation per primitive set (traits.hpp).
template <class Set>
void user_bounds(const RTCBoundsFunctionArguments* args) {
  Box3 box;
  static_cast<const Set*>(args->geometryUserPtr)->bounds(args->primID, box);
  store_bounds(box.lo, box.hi, args->bounds_o);
}

// A set whose primitives have parts (CSG leaves) says which one a hit is on.
template <class Set>
concept HasParts = requires(const Set& s, unsigned p, float f, Vec3f v, float& t, Vec3f& n,
                            unsigned& sub, const Ray& r, Hit& h) {
  s.hit(p, f, v, v, f, f, t, n, sub);
  s.refine(p, r, f, h, sub);
};

// The float after a positive finite one; the rest as they are.
inline float float_up(float f) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(f);
  return bits < 0x7f800000u ? std::bit_cast<float>(bits + 1) : f;
}

// Lane i against primitive `prim`; `ties`: up to one float past the lane's tfar, so a
// hit at exactly tfar is found (user_intersect decides it).
template <class Set>
bool user_hit(const Set& set, unsigned prim, RTCRayN* ray, unsigned n, unsigned i, float& t,
              Vec3f& ng, unsigned& sub, bool ties = false) {
  float time = RTCRayN_time(ray, n, i);
  Vec3f o(RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i));
  Vec3f d(RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i));
  float tnear = RTCRayN_tnear(ray, n, i), tfar = RTCRayN_tfar(ray, n, i);
  if (ties) tfar = float_up(tfar);
  if constexpr (HasParts<Set>)
    return set.hit(prim, time, o, d, tnear, tfar, t, ng, sub);
  else
    return set.hit(prim, time, o, d, tnear, tfar, t, ng);
}

// A 16-ray packet's lanes against a static sphere at once, where the CPU has a
// SIMD path (sphere_lanes.hpp; the same bits as user_hit): `hits` the lanes that
// hit, with their t and normal in `out` (null for an occlusion query, which needs
// neither); false when the lanes go one by one (no path, another packet width, a
// non-similarity transform). Lanes in `undecided` still go one by one. `ties`: as
// user_hit's.
const SphereLanesFn g_sphere_lanes = sphere_lanes();
template <class Set>
bool packet_hits(const Set& set, unsigned prim, RTCRayN* ray, unsigned n, const int* valid,
                 HitLanes* out, std::uint32_t& hits, std::uint32_t& undecided, bool ties = false) {
  if constexpr (std::is_same_v<Set, SphereSet>) {
    Vec3 c;
    double r;
    // Embree hands the callback its own packet width: 16 rays on AVX-512, 8 on
    // AVX2 (both go through the lanes; 4 and single rays go one by one).
    if ((n != 16 && n != 8) || !g_sphere_lanes || !set.similar(prim, c, r)) return false;
    // The raised tfars in a copy of their own (one vector operation; the ray's are
    // not touched).
    using U16 = std::uint32_t __attribute__((vector_size(64)));
    U16 bits{};
    std::memcpy(&bits, &RTCRayN_tfar(ray, n, 0), n * sizeof(float));
    if (ties) bits += U16(bits < 0x7f800000u) & 1u;  // positive and finite; the rest kept
    alignas(64) float tfar[16];
    std::memcpy(tfar, &bits, sizeof tfar);
    RayLanes rays{&RTCRayN_org_x(ray, n, 0),
                  &RTCRayN_org_y(ray, n, 0),
                  &RTCRayN_org_z(ray, n, 0),
                  &RTCRayN_dir_x(ray, n, 0),
                  &RTCRayN_dir_y(ray, n, 0),
                  &RTCRayN_dir_z(ray, n, 0),
                  &RTCRayN_tnear(ray, n, 0),
                  tfar,
                  valid,
                  n};
    undecided = 0;
    hits = g_sphere_lanes(c, r, rays, out, undecided);
    return true;
  }
  (void)set, (void)prim, (void)ray, (void)n, (void)valid, (void)out, (void)hits, (void)undecided,
      (void)ties;
  return false;
}

// Lane i of a packet: from packet_hits when it decided the lane, else user_hit.
template <class Set>
bool lane_hit(const Set& set, unsigned prim, RTCRayN* ray, unsigned n, unsigned i, bool packet,
              const HitLanes& lanes, std::uint32_t hits, std::uint32_t undecided, float& t,
              Vec3f& ng, unsigned& sub, bool ties) {
  if (packet && !((undecided >> i) & 1)) {
    if (!((hits >> i) & 1)) return false;
    t = lanes.t[i], ng = Vec3f(lanes.nx[i], lanes.ny[i], lanes.nz[i]);
    return true;
  }
  return user_hit(set, prim, ray, n, i, t, ng, sub, ties);
}

template <class Set>
void user_intersect(const RTCIntersectFunctionNArguments* args) {
  const Set& set = *static_cast<const Set*>(args->geometryUserPtr);
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
  // Equal distances (coincident surfaces: a sphere written twice, a union's children
  // sharing a face) go to the lower (instance, geometry, primitive) ids, not to
  // whichever the traversal meets first: that order depends on the packet a ray
  // rides in, so a crop or a farm tile differed from the whole render there, and a
  // union's shared face was striped by packet rows. So the lanes are tested against
  // tfar one float up, and a hit at exactly tfar is a tie, taken only from a hit
  // with higher ids. (Ties among Embree's own triangles stay Embree's.)
  const unsigned n = args->N;  // at most 16
  float* const tfar = &RTCRayN_tfar(ray, n, 0);
  HitLanes lanes;
  std::uint32_t hits = 0, undecided = 0;
  const bool packet =
      packet_hits(set, args->primID, ray, n, args->valid, &lanes, hits, undecided, true);
  if (packet && hits == 0 && undecided == 0) return;
  float t[16];
  Vec3f ng[16];
  unsigned sub[16];
  // The lanes to look at: the packet test's hits and undecided ones (valid lanes
  // only), else every valid lane.
  std::uint32_t todo = hits | undecided, found = 0;
  if (!packet)
    for (unsigned i = 0; i < n; ++i) todo |= std::uint32_t(args->valid[i] != 0) << i;
  for (std::uint32_t b = todo; b; b &= b - 1) {
    const unsigned i = unsigned(std::countr_zero(b));
    sub[i] = 0;
    if (lane_hit(set, args->primID, ray, n, i, packet, lanes, hits, undecided, t[i], ng[i], sub[i],
                 true))
      found |= 1u << i;
  }
  const unsigned inst = args->context->instID[0];
  for (std::uint32_t b = found; b; b &= b - 1) {
    const unsigned i = unsigned(std::countr_zero(b));
    if (!(t[i] < tfar[i])) {  // a tie: only with a hit of higher ids
      const unsigned g = RTCHitN_geomID(hit, n, i);
      if (g == RTC_INVALID_GEOMETRY_ID ||
          !(std::tie(inst, args->geomID, args->primID) <
            std::tie(RTCHitN_instID(hit, n, i, 0), g, RTCHitN_primID(hit, n, i))))
        continue;
    }
    tfar[i] = t[i];
    RTCHitN_Ng_x(hit, n, i) = ng[i].x;
    RTCHitN_Ng_y(hit, n, i) = ng[i].y;
    RTCHitN_Ng_z(hit, n, i) = ng[i].z;
    // The part rides in u (exact in a float below 2^24; CsgProgram's leaves).
    RTCHitN_u(hit, n, i) = float(sub[i]);
    RTCHitN_v(hit, n, i) = 0;
    RTCHitN_primID(hit, n, i) = args->primID;
    RTCHitN_geomID(hit, n, i) = args->geomID;
    RTCHitN_instID(hit, n, i, 0) = inst;
  }
}

template <class Set>
void user_occluded(const RTCOccludedFunctionNArguments* args) {
  const Set& set = *static_cast<const Set*>(args->geometryUserPtr);
  RTCRayN* ray = args->ray;
  std::uint32_t hits = 0, undecided = 0;
  const bool packet =
      packet_hits(set, args->primID, ray, args->N, args->valid, nullptr, hits, undecided);
  if (packet && hits == 0 && undecided == 0) return;
  for (unsigned i = 0; i < args->N; ++i) {
    if (!args->valid[i]) continue;
    float t;
    Vec3f n;
    unsigned sub;
    if (packet && !((undecided >> i) & 1) ? (hits >> i) & 1
                                          : user_hit(set, args->primID, ray, args->N, i, t, n, sub))
      RTCRayN_tfar(ray, args->N, i) = -INFINITY;
  }
}

// Embree's first error; out of memory is kept apart, to be the same clean
// out-of-memory report as an allocation of Snell's own that fails (std::bad_alloc).
struct EmbreeError {
  std::string message;
  bool out_of_memory = false;
};
void embree_error(void* user, RTCError code, const char* str) {
  auto* e = static_cast<EmbreeError*>(user);
  if (code == RTC_ERROR_OUT_OF_MEMORY) e->out_of_memory = true;
  if (e->message.empty())
    e->message = fmt::format("embree error {}: {}", int(code), str ? str : "");
}

}  // namespace

// What a hit on one Embree geometry is: `resolve` fills the hit's kind, index,
// material, point and offset from the primitive and its barycentrics (u carries
// a CSG object's leaf).
struct Layer;
struct GeomEntry {
  void (*resolve)(const GeomEntry&, unsigned prim, float u, float v, const Ray& r, float t,
                  Hit& hit) = nullptr;
  // A prototype's geometry only: the ray's crossing of `prim` found again from a
  // ray of Snell's own (t, normal, u and v as Embree gives them; false: keep
  // Embree's). resolve_instance asks it for a moving instance.
  bool (*retrace)(const GeomEntry&, unsigned prim, const Ray& r, float& t, Vec3f& ng, float& u,
                  float& v) = nullptr;
  const void* data = nullptr;
  const Layer* layer = nullptr;
  std::uint32_t shape = 0;  // a moving triangle shape's index
};

// One BVH and what its hits resolve through: the world's, or a prototype's (§13),
// built once in the prototype's own space and instanced.
struct Layer {
  RTCScene scene = nullptr;
  const std::vector<ir::Shape>* shapes = nullptr;  // what Hit::index names here
  UserSets user_sets;
  std::vector<GeomEntry> geoms;  // by geomID
  // The static triangles: per-primitive owner (shape index) and offset, and their
  // buffers as Embree holds them (camera-relative float), to rebuild hit points
  // from barycentrics.
  std::vector<std::uint32_t> tri_owner;
  std::vector<float> tri_offset;
  const float* tri_vb = nullptr;
  const unsigned* tri_ib = nullptr;
  SmoothNormals smooth;  // the static triangles' shading normals (smooth meshes only)
  // The first static triangle of each triangle shape (by shape index): a hit's
  // primitive less it is the triangle of the shape's own list (§17 "uv").
  std::unordered_map<std::uint32_t, std::uint32_t> tri_first;
  std::size_t triangle_count = 0;
  Box3 box;  // of a prototype, in its space (a moving instance's time steps)

  ~Layer() {
    if (scene) rtcReleaseScene(scene);
  }
  void enter(unsigned id, GeomEntry e) {
    if (geoms.size() <= id) geoms.resize(id + 1);
    e.layer = this;
    geoms[id] = e;
  }
  std::uint32_t material_of(std::uint32_t shape) const { return (*shapes)[shape].material; }
};

// An instance: the prototype layer it places and where (camera-relative).
struct InstanceEntry {
  const Layer* proto = nullptr;
  const ir::Shape* shape_ir = nullptr;
  std::uint32_t shape = 0;
  ir::Mat4 obj_from_rel, rel_from_obj;  // the static placement
  Vec3 origin;
  bool moving = false;
};

struct EmbreeScene::Impl {
  RTCDevice device = nullptr;
  EmbreeError error;
  Layer world;
  std::vector<std::unique_ptr<Layer>> protos;
  std::vector<InstanceEntry> instances;  // by the instance's geomID in the world BVH
  UnboundedSets unbounded;
  std::size_t moving_shapes = 0, motion_steps = 0, light_tris = 0, instance_count = 0;
  bool any_unbounded = false;  // some unbounded set is not empty (known once built)

  ~Impl() {
    protos.clear();  // the scenes before their device
    if (world.scene) rtcReleaseScene(world.scene);
    world.scene = nullptr;
    if (device) rtcReleaseDevice(device);
  }

  RTCScene new_scene() {
    RTCScene s = rtcNewScene(device);
    rtcSetSceneBuildQuality(s, RTC_BUILD_QUALITY_HIGH);
    // Robust mode: watertight triangle tests and conservative traversal. Without
    // it, rays aimed exactly at the shared vertices of a closed mesh missed 12.9 %
    // of the time (tests/hardcases, #6); see embree_scene.hpp for the cost.
    rtcSetSceneFlags(s, RTC_SCENE_FLAG_ROBUST);
    return s;
  }

  unsigned add_triangles(Layer& layer, const std::vector<Vec3>& verts,
                         const std::vector<std::uint32_t>& idx, const float** vb_out = nullptr,
                         const unsigned** ib_out = nullptr) {
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
    unsigned id = rtcAttachGeometry(layer.scene, g);
    rtcReleaseGeometry(g);
    return id;
  }

  // A moving box/triangle/mesh: Embree motion blur, one vertex buffer per time step,
  // the vertices placed exactly (Motion::at) at each step.
  void add_moving_triangles(const ir::Shape& s, std::uint32_t shape, const Soup& soup,
                            Vec3 origin) {
    if (soup.verts.empty()) return;
    unsigned segs = motion_segments(s, soup.verts, origin);
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
    unsigned id = rtcAttachGeometry(world.scene, g);
    rtcReleaseGeometry(g);
    world.enter(id, {&resolve_plain, nullptr, nullptr, nullptr, shape});
    ++moving_shapes;
    motion_steps += segs + 1;
  }

  template <class Set>
  void add_user(Layer& layer, const Set& set) {
    if (set.size() == 0) return;
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(set.size()));
    rtcSetGeometryUserData(g, const_cast<Set*>(&set));
    rtcSetGeometryBoundsFunction(g, &user_bounds<Set>, nullptr);
    rtcSetGeometryIntersectFunction(g, &user_intersect<Set>);
    rtcSetGeometryOccludedFunction(g, &user_occluded<Set>);
    rtcCommitGeometry(g);
    unsigned id = rtcAttachGeometry(layer.scene, g);
    rtcReleaseGeometry(g);
    layer.enter(id, {&resolve_user<Set>, &retrace_user<Set>, &set, nullptr, 0});
  }

  // Builds a layer's static triangles and user sets after its shapes were added.
  void finish_layer(Layer& layer, std::vector<Vec3>& tv, std::vector<std::uint32_t>& ti) {
    layer.triangle_count = ti.size() / 3;
    if (!ti.empty()) {
      unsigned id = add_triangles(layer, tv, ti, &layer.tri_vb, &layer.tri_ib);
      layer.enter(id, {&resolve_static_triangles, &retrace_triangles, &layer, nullptr, 0});
    }
    layer.tri_offset.resize(ti.size() / 3);
    for (std::size_t t = 0; t < layer.tri_offset.size(); ++t)
      layer.tri_offset[t] =
          triangle_offset(layer.tri_vb + 3 * ti[3 * t], layer.tri_vb + 3 * ti[3 * t + 1],
                          layer.tri_vb + 3 * ti[3 * t + 2]);
    std::apply([&](const auto&... set) { (add_user(layer, set), ...); }, layer.user_sets);
  }

  const Layer& prototype(const ir::Scene& sc, std::uint32_t index);
  void add_instance(const ir::Scene& sc, const ir::Shape& s, const ir::Instance& g,
                    std::uint32_t shape, Vec3 origin, bool moving);

  // The resolvers of GeomEntry, one per geometry class.
  static void resolve_static_triangles(const GeomEntry& e, unsigned prim, float u, float v,
                                       const Ray& r, float, Hit& hit) {
    const Layer& l = *static_cast<const Layer*>(e.data);
    hit.kind = Hit::Kind::Shape;
    hit.index = l.tri_owner[prim];
    hit.material = l.material_of(hit.index);
    hit.prim = prim, hit.tri_layer = &l;
    triangle_point(l.tri_vb, l.tri_ib, prim, u, v, hit.p);
    hit.offset = l.tri_offset[prim];
    if (!l.smooth.empty()) hit.smooth = l.smooth.shade(prim, u, v, r.dir, l.tri_vb, l.tri_ib, hit);
  }
  static bool retrace_triangles(const GeomEntry& e, unsigned prim, const Ray& r, float& t,
                                Vec3f& ng, float& u, float& v) {
    const Layer& l = *static_cast<const Layer*>(e.data);
    return geom::triangle_retrace(l.tri_vb, l.tri_ib, prim, r.org, r.dir, t, u, v, ng);
  }
  // Moving triangles: o + t·d and the Wächter–Binder offset.
  static void resolve_plain(const GeomEntry& e, unsigned prim, float, float, const Ray& r, float t,
                            Hit& hit) {
    hit.kind = Hit::Kind::Shape;
    hit.prim = prim, hit.tri_layer = nullptr;
    hit.index = e.shape;
    hit.material = e.layer->material_of(hit.index);
    hit.p = r.org + r.dir * t, hit.offset = unbounded_offset(r, hit.p);
  }
  static void resolve_light(const GeomEntry&, unsigned prim, float, float, const Ray& r, float t,
                            Hit& hit) {
    hit.kind = Hit::Kind::AreaLight;
    hit.index = prim / 2;
    hit.p = r.org + r.dir * t, hit.offset = unbounded_offset(r, hit.p);
  }
  // The nearest crossing of the user primitive past the ray's start (a CSG
  // object's leaf rides in u, as in user_intersect).
  template <class Set>
  static bool retrace_user(const GeomEntry& e, unsigned prim, const Ray& r, float& t, Vec3f& ng,
                           float& u, float&) {
    const Set& set = *static_cast<const Set*>(e.data);
    if constexpr (HasParts<Set>) {
      unsigned sub = 0;
      if (!set.hit(prim, r.time, r.org, r.dir, r.tnear, INFINITY, t, ng, sub)) return false;
      u = float(sub);
      return true;
    } else {
      return set.hit(prim, r.time, r.org, r.dir, r.tnear, INFINITY, t, ng);
    }
  }
  template <class Set>
  static void resolve_user(const GeomEntry& e, unsigned prim, float u, float, const Ray& r, float t,
                           Hit& hit) {
    const Set& set = *static_cast<const Set*>(e.data);
    hit.kind = Hit::Kind::Shape;
    hit.index = set.shape(prim);
    hit.material = e.layer->material_of(hit.index);
    if constexpr (HasParts<Set>)
      set.refine(prim, r, t, hit, static_cast<unsigned>(u));
    else
      set.refine(prim, r, t, hit);
  }
};
namespace {
// Adds one shape to a layer's inputs by its kind's geometry class.
struct ShapeAdder {
  EmbreeScene::Impl& im;
  Layer& layer;
  const ir::Scene& sc;
  Vec3 origin;
  bool shutter_open;
  std::vector<Vec3>& tv;  // static triangles, camera-relative (double until the float store)
  std::vector<std::uint32_t>& ti;

  template <class Kind>
  void operator()(const Kind& g, const ir::Shape& s, std::uint32_t si) {
    using G = Geometry<Kind>;
    bool moving = shutter_open && ir::moves(s, sc);  // a CSG object also when a leaf moves
    if constexpr (G::kind == GeometryClass::Triangles) {
      const ir::Transform& xf = s.world_from_object();
      Soup soup;
      bool flip = det3(xf.m) < 0;  // mirroring reverses the winding
      object_triangles(g, sc, flip, soup);
      if (moving) {  // smooth normals are not interpolated on moving meshes (flat)
        im.add_moving_triangles(s, si, soup, origin);
        return;
      }
      std::vector<Vec3> normals;
      if (object_normals(g, sc, flip, normals))
        layer.smooth.add(layer.tri_owner.size(), normals, xf);
      layer.tri_first.emplace(si, std::uint32_t(layer.tri_owner.size()));
      for (std::size_t i = 0; i < soup.verts.size(); ++i) {
        tv.push_back(xf.point(soup.verts[i]) - origin);
        ti.push_back(std::uint32_t(tv.size() - 1));
        if (i % 3 == 0) layer.tri_owner.push_back(si);
      }
    } else if constexpr (G::kind == GeometryClass::User) {
      auto& set = std::get<typename G::Static>(layer.user_sets);
      auto& mset = std::get<typename G::Moving>(layer.user_sets);
      auto add_to = [&](auto& target) {
        if constexpr (requires { target.add(s, g, si, origin, sc); })
          target.add(s, g, si, origin, sc);
        else
          target.add(s, g, si, origin);
      };
      if (moving) {
        add_to(mset);
        ++im.moving_shapes;
      } else {
        add_to(set);
      }
    } else if constexpr (G::kind == GeometryClass::Instance) {
      if (&layer != &im.world) throw std::runtime_error("an instance inside a prototype");
      im.add_instance(sc, s, g, si, origin, moving);
    } else {
      if (&layer != &im.world) throw std::runtime_error("an unbounded shape inside a prototype");
      std::get<typename G::Set>(im.unbounded).add(s, g, si, origin, moving);
      if (moving) ++im.moving_shapes;
    }
  }
};
}  // namespace

const Layer& EmbreeScene::Impl::prototype(const ir::Scene& sc, std::uint32_t index) {
  if (protos.size() <= index) protos.resize(sc.prototypes.size());
  if (protos[index]) return *protos[index];
  auto layer = std::make_unique<Layer>();
  layer->scene = new_scene();
  layer->shapes = &sc.parts;
  std::vector<Vec3> tv;
  std::vector<std::uint32_t> ti;
  ShapeAdder add{*this, *layer, sc, Vec3{0, 0, 0}, false, tv, ti};
  for (std::uint32_t pi : sc.prototypes[index].parts) {
    const ir::Shape& s = sc.parts[pi];
    std::visit([&](const auto& g) { add(g, s, pi); }, s.geom);
    ir::world_hull_points(s, sc, [&](Vec3 p) { layer->box.grow(p); });
  }
  finish_layer(*layer, tv, ti);
  rtcCommitScene(layer->scene);
  protos[index] = std::move(layer);
  return *protos[index];
}

void EmbreeScene::Impl::add_instance(const ir::Scene& sc, const ir::Shape& s, const ir::Instance& g,
                                     std::uint32_t shape, Vec3 origin, bool moving) {
  const Layer& proto = prototype(sc, g.prototype);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(geom, proto.scene);
  auto set_step = [&](unsigned step, const ir::Mat4& m) {
    float xfm[12];  // column-major 3x4
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 3; ++r) xfm[3 * c + r] = float(m(r, c));
    rtcSetGeometryTransform(geom, step, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
  };
  ir::Transform rel = ir::Transform::translate(-origin) * s.world_from_object();
  if (moving) {
    // The prototype's box corners stand for it (its hull) in the step counts.
    std::vector<Vec3> corners;
    for (int i = 0; i < 8; ++i)
      corners.push_back(Vec3{i & 1 ? proto.box.hi[0] : proto.box.lo[0],
                             i & 2 ? proto.box.hi[1] : proto.box.lo[1],
                             i & 4 ? proto.box.hi[2] : proto.box.lo[2]});
    const Vec3 centre = (Vec3(proto.box.lo[0], proto.box.lo[1], proto.box.lo[2]) +
                         Vec3(proto.box.hi[0], proto.box.hi[1], proto.box.hi[2])) *
                        0.5;
    // Turns are followed along their arcs (a wheel spinning in place takes one
    // segment); a placement with no rotation to speak of (a scale through 0) falls
    // back to matrices, which Embree interpolates linearly, cutting arcs' chords.
    std::vector<QuatPlacement> steps = quat_motion_steps(s, corners, centre, origin, 1e-6);
    unsigned segs = unsigned(steps.size()) - 1;
    if (steps.empty()) segs = motion_segments(s, corners, origin, 1e-6);
    rtcSetGeometryTimeStepCount(geom, segs + 1);
    for (unsigned step = 0; step <= segs; ++step) {
      if (steps.empty()) {
        set_step(step, rel_at(s, origin, double(step) / segs).m);
        continue;
      }
      const QuatPlacement& p = steps[step];
      RTCQuaternionDecomposition qd;
      rtcInitQuaternionDecomposition(&qd);
      rtcQuaternionDecompositionSetScale(&qd, float(p.u[0][0]), float(p.u[1][1]), float(p.u[2][2]));
      rtcQuaternionDecompositionSetSkew(&qd, float(p.u[0][1]), float(p.u[0][2]), float(p.u[1][2]));
      rtcQuaternionDecompositionSetShift(&qd, float(p.shift.x), float(p.shift.y), float(p.shift.z));
      rtcQuaternionDecompositionSetQuaternion(&qd, float(p.q[0]), float(p.q[1]), float(p.q[2]),
                                              float(p.q[3]));
      rtcQuaternionDecompositionSetTranslation(&qd, float(p.translation.x), float(p.translation.y),
                                               float(p.translation.z));
      rtcSetGeometryTransformQuaternion(geom, step, &qd);
    }
    ++moving_shapes;
    motion_steps += segs + 1;
  } else {
    set_step(0, rel.m);
  }
  rtcCommitGeometry(geom);
  unsigned id = rtcAttachGeometry(world.scene, geom);
  rtcReleaseGeometry(geom);
  if (instances.size() <= id) instances.resize(id + 1);
  instances[id] = {&proto, &s, shape, rel.inv, rel.m, origin, moving};
  ++instance_count;
}

EmbreeScene::EmbreeScene(const ir::Scene& sc, ir::Vec3 origin)
    : origin_(origin), impl_(std::make_unique<Impl>()) {
  Impl& im = *impl_;
  im.device = rtcNewDevice(nullptr);
  if (!im.device) throw std::runtime_error("cannot create the Embree device");
  rtcSetDeviceErrorFunction(im.device, embree_error, &im.error);
  im.world.scene = im.new_scene();
  im.world.shapes = &sc.shapes;
  // §6/§8: objects move only while the shutter is open; with a closed shutter they
  // stand where their transforms place them (the shutter-open placement).
  bool shutter_open = sc.camera.shutter_close > sc.camera.shutter_open;

  std::vector<Vec3> tv;
  std::vector<std::uint32_t> ti;
  ShapeAdder add{im, im.world, sc, origin, shutter_open, tv, ti};
  // The spheres' room at once: a million-sphere scene would otherwise hold the old
  // and the new array together as it doubles.
  std::get<SphereSet>(im.world.user_sets)
      .reserve(std::size_t(std::count_if(sc.shapes.begin(), sc.shapes.end(),
                                         [](const ir::Shape& s) { return s.as<ir::Sphere>(); })));
  for (std::uint32_t si = 0; si < sc.shapes.size(); ++si) {
    const ir::Shape& s = sc.shapes[si];
    std::visit([&](const auto& g) { add(g, s, si); }, s.geom);
  }
  im.finish_layer(im.world, tv, ti);
  im.any_unbounded =
      std::apply([](const auto&... set) { return (!set.empty() || ...); }, im.unbounded);

  // Area lights: two triangles each, so camera/reflection/refraction rays see them
  // and they block shadow rays of other lights (an area light is a surface).
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
    unsigned id = im.add_triangles(im.world, lv, li);
    im.world.enter(id, {&Impl::resolve_light, nullptr, nullptr, nullptr, 0});
    im.light_tris = 2;
  }
  rtcCommitScene(im.world.scene);
  if (im.error.out_of_memory) throw std::bad_alloc();
  if (!im.error.message.empty()) throw std::runtime_error(im.error.message);
}

bool EmbreeScene::has_motion() const {
  return impl_->moving_shapes > 0;
}

EmbreeScene::~EmbreeScene() = default;

namespace {
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

// A hit on an instance: resolved in the prototype's space from the ray carried
// there in double, then brought back. The point's error is the prototype's
// (its bounded offset, stretched by the transform) plus the rounding of the
// transformed point; a moving instance uses o + t·d and the Wächter–Binder offset,
// as moving shapes do (Embree interpolates its matrices between time steps).
void resolve_instance(const InstanceEntry& ie, const RTCRayHit& rh, const Ray& r, Hit& hit) {
  ir::Mat4 obj_from_rel = ie.obj_from_rel, rel_from_obj = ie.rel_from_obj;
  if (ie.moving) {
    ir::Transform t = rel_at(*ie.shape_ir, ie.origin, shutter_fraction(r.time));
    obj_from_rel = t.inv, rel_from_obj = t.m;
  }
  Vec3 o = xform_point(obj_from_rel, Vec3(r.org.x, r.org.y, r.org.z));
  Vec3 d = xform_vector(obj_from_rel, Vec3(r.dir.x, r.dir.y, r.dir.z));
  Ray ro{to_float(o.x, o.y, o.z), to_float(d.x, d.y, d.z), r.tmax, r.time, r.tnear};
  const GeomEntry& e = ie.proto->geoms[rh.hit.geomID];
  float u = rh.hit.u, v = rh.hit.v;
  Vec3f ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  if (ie.moving && e.retrace) {
    // Embree turns the ray into a moving instance's space by its own interpolation
    // (a slerp in rsqrt and polynomial approximations), whose bits differ between
    // a ray traced alone and one in a packet, and with the packet's other lanes: a
    // 1×1 crop differed from the whole render. Embree chose the primitive; its
    // crossing is found again from `ro`, Snell's own double transform at the ray's
    // time, so the hit is the same however the ray was traced.
    float t2, u2 = u, v2 = v;
    Vec3f ng2;
    if (e.retrace(e, rh.hit.primID, ro, t2, ng2, u2, v2) && t2 > r.tnear && t2 < INFINITY)
      hit.t = t2, u = u2, v = v2, ng = ng2;
  }
  e.resolve(e, rh.hit.primID, u, v, ro, hit.t, hit);
  if (hit.material == ir::kInheritMaterial) hit.material = ie.shape_ir->material;
  (hit.part == ir::kNoPart ? hit.part : hit.outer) = hit.index;  // a CSG part's leaf: kept
  hit.index = ie.shape;
  Vec3 n = ir::normalize(xform_normal_by_inverse(obj_from_rel, Vec3(ng.x, ng.y, ng.z)));
  hit.ng = to_float(n.x, n.y, n.z);
  if (hit.smooth) {  // a smooth mesh's shading normal and shadow-ray start, to the world
    Vec3 ns =
        ir::normalize(xform_normal_by_inverse(obj_from_rel, Vec3(hit.ns.x, hit.ns.y, hit.ns.z)));
    Vec3 ps = xform_point(rel_from_obj, Vec3(hit.ps.x, hit.ps.y, hit.ps.z));
    hit.ns = to_float(ns.x, ns.y, ns.z);
    hit.ps = to_float(ps.x, ps.y, ps.z);
  }
  if (ie.moving || !(hit.offset > 0)) {
    hit.p = r.org + r.dir * hit.t, hit.offset = unbounded_offset(r, hit.p);
    return;
  }
  Vec3 p = xform_point(rel_from_obj, Vec3(hit.p.x, hit.p.y, hit.p.z));
  // The largest stretch of the linear part bounds how far the offset grows.
  double stretch = 0;
  for (int i = 0; i < 3; ++i)
    stretch = std::fmax(stretch, std::fabs(rel_from_obj(i, 0)) + std::fabs(rel_from_obj(i, 1)) +
                                     std::fabs(rel_from_obj(i, 2)));
  hit.p = to_float(p.x, p.y, p.z);
  hit.offset =
      float(double(hit.offset) * stretch + kSurfaceOffsetUlps * 0x1p-24 * double(max_abs(hit.p)));
}
}  // namespace

namespace {
// What a traced ray's Embree hit becomes: the hit resolved, then the unbounded
// shapes (planes) tested against it in double. The same for a ray traced alone and
// one traced in a packet.
bool finish_hit(const EmbreeScene::Impl& im, const Ray& r, const RTCRayHit& rh, Hit& hit);
}  // namespace

bool EmbreeScene::intersect(const Ray& r, Hit& hit) const {
  const Impl& im = *impl_;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = make_rayhit(r);
  rtcIntersect1(im.world.scene, &ctx, &rh);
  return finish_hit(im, r, rh, hit);
}

namespace {
// The Embree hit resolved (finish_hit's first half), and the tmax and tie the
// unbounded shapes are then tested with.
bool resolve_hit(const EmbreeScene::Impl& im, const Ray& r, const RTCRayHit& rh, Hit& hit,
                 double& tmax, double& tie) {
  bool found = false;
  hit.smooth = false;
  hit.part = hit.outer = ir::kNoPart;
  // Embree's float test overflows on triangles ~1e13 across (t = inf, Ng = 0); the
  // compiler keeps scenes within 1e12 of the camera, and such a hit is a miss here.
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID && rh.ray.tfar < INFINITY &&
      (rh.hit.Ng_x != 0 || rh.hit.Ng_y != 0 || rh.hit.Ng_z != 0)) {
    found = true;
    hit.t = rh.ray.tfar;
    if (rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
      resolve_instance(im.instances[rh.hit.instID[0]], rh, r, hit);
    } else {
      hit.ng = normalize(Vec3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
      const GeomEntry& e = im.world.geoms[rh.hit.geomID];
      e.resolve(e, rh.hit.primID, rh.hit.u, rh.hit.v, r, hit.t, hit);
    }
  }
  tmax = found ? double(hit.t) : double(r.tmax);
  // Coincident surfaces (a box resting on a plane: its bottom face and the floor):
  // the face is a float triangle, the plane exact, so their hits differ by rounding
  // and the nearer one flipped from ray to ray (a speckled band at the foot of the
  // glass block in examples/glass). Within the face's error bound (its offset, at
  // least 32 ulps of the point) an unbounded shape wins: the floor under a block
  // resting on it.
  tie = found && im.any_unbounded ? std::fmax(double(hit.offset), 0x1p-19 * double(max_abs(hit.p)))
                                  : 0;
  return found;
}

// What a hit on an unbounded shape (written into `hit` by its set) carries besides.
void took_unbounded(const EmbreeScene::Impl& im, Hit& hit) {
  hit.smooth = false, hit.part = ir::kNoPart;
  hit.material = im.world.material_of(hit.index);
}

bool finish_hit(const EmbreeScene::Impl& im, const Ray& r, const RTCRayHit& rh, Hit& hit) {
  double tmax, tie;
  bool found = resolve_hit(im, r, rh, hit, tmax, tie);
  bool unbounded = false;
  std::apply(
      [&](const auto&... set) {
        ((set.intersect(r, tmax, tie, hit) ? (found = unbounded = true, tie = 0) : 0), ...);
      },
      im.unbounded);
  if (unbounded) took_unbounded(im, hit);
  return found;
}

// finish_hit of a packet's lanes [0, n) after rtcIntersect16 (rh: the packet, rays
// its rays): the unbounded shapes test the lanes together where they can
// (PlaneSet::intersect_lanes), each lane as finish_hit tests it.
void finish_hits(const EmbreeScene::Impl& im, const Ray* rays, std::size_t n, const RTCRayHit16& rh,
                 Hit* hits, std::uint8_t* found) {
  alignas(64) double tmax[16] = {}, tie[16] = {};  // lanes past n: read, masked
  for (std::size_t k = 0; k < n; ++k) {
    RTCRayHit one = make_rayhit(rays[k]);
    one.ray.tfar = rh.ray.tfar[k];
    one.hit.Ng_x = rh.hit.Ng_x[k], one.hit.Ng_y = rh.hit.Ng_y[k], one.hit.Ng_z = rh.hit.Ng_z[k];
    one.hit.u = rh.hit.u[k], one.hit.v = rh.hit.v[k];
    one.hit.primID = rh.hit.primID[k], one.hit.geomID = rh.hit.geomID[k];
    one.hit.instID[0] = rh.hit.instID[0][k];
    found[k] = resolve_hit(im, rays[k], one, hits[k], tmax[k], tie[k]);
  }
  if (!im.any_unbounded) return;
  const std::uint32_t live = std::uint32_t((1u << n) - 1);
  const geom::PlaneRayLanes lanes{rh.ray.org_x, rh.ray.org_y, rh.ray.org_z, rh.ray.dir_x,
                                  rh.ray.dir_y, rh.ray.dir_z, rh.ray.tnear};
  std::uint32_t took = 0;  // the lanes whose nearest hit is unbounded
  auto test = [&](const auto& set) {
    if constexpr (requires { set.intersect_lanes(lanes, live, tmax, tie, nullptr, took); }) {
      std::uint32_t which[16], hit_lanes;
      if (set.intersect_lanes(lanes, live, tmax, tie, which, hit_lanes)) {
        for (std::uint32_t bits = hit_lanes; bits; bits &= bits - 1) {
          const unsigned k = unsigned(std::countr_zero(bits));
          set.plane_hit(which[k], rays[k], tmax[k], hits[k]);
        }
        took |= hit_lanes;
        return;
      }
    }
    for (std::size_t k = 0; k < n; ++k)
      if (set.intersect(rays[k], tmax[k], tie[k], hits[k])) tie[k] = 0, took |= 1u << k;
  };
  std::apply([&](const auto&... set) { (test(set), ...); }, im.unbounded);
  for (std::uint32_t bits = took; bits; bits &= bits - 1) {
    const unsigned k = unsigned(std::countr_zero(bits));
    found[k] = true;
    took_unbounded(im, hits[k]);
  }
}
}  // namespace

bool EmbreeScene::occluded(const Ray& r) const {
  const Impl& im = *impl_;
  if (std::apply([&](const auto&... set) { return (set.occluded(r) || ...); }, im.unbounded))
    return true;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay ray = make_rayhit(r).ray;
  rtcOccluded1(im.world.scene, &ctx, &ray);
  return ray.tfar < 0;
}

std::uint32_t EmbreeScene::triangle_of(const Hit& hit) const {
  if (!hit.tri_layer) return hit.prim;
  const Layer& l = *static_cast<const Layer*>(hit.tri_layer);
  auto it = l.tri_first.find(l.tri_owner[hit.prim]);
  return it == l.tri_first.end() ? 0 : hit.prim - it->second;
}

namespace {
constexpr std::size_t kPacket = 16;

const StoreRays16Fn g_store_rays16 = store_rays16();
}  // namespace

// Packets of up to 16 rays (rtcIntersect16 / rtcOccluded16; the user geometry's
// callbacks take N rays). Embree's packet kernels compute each ray's triangle and
// box tests as its single-ray ones do, and the user geometry's double-precision
// tests are per ray, so a ray's answer does not depend on the packet it rides in
// (test_packets.cpp checks it against the one-ray queries). A lone ray is traced
// alone: a packet of one costs more than it saves.
void EmbreeScene::intersect(std::span<const Ray> rays, std::span<Hit> hits,
                            std::span<std::uint8_t> found, bool coherent) const {
  const Impl& im = *impl_;
  for (std::size_t b = 0; b < rays.size(); b += kPacket) {
    std::size_t n = std::min(kPacket, rays.size() - b);
    if (n == 1) {
      found[b] = intersect(rays[b], hits[b]);
      continue;
    }
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[kPacket];
    g_store_rays16(&rays[b], n, rh.ray);
    for (std::size_t k = 0; k < kPacket; ++k) {
      valid[k] = k < n ? -1 : 0;
      rh.hit.geomID[k] = rh.hit.primID[k] = rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags =
        coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    rtcIntersect16(valid, im.world.scene, &ctx, &rh);
    finish_hits(im, &rays[b], n, rh, &hits[b], &found[b]);
  }
}

void EmbreeScene::occluded(std::span<const Ray> rays, std::span<std::uint8_t> blocked) const {
  const Impl& im = *impl_;
  for (std::size_t b = 0; b < rays.size(); b += kPacket) {
    std::size_t n = std::min(kPacket, rays.size() - b);
    if (n == 1) {
      blocked[b] = occluded(rays[b]);
      continue;
    }
    alignas(64) RTCRay16 r;
    alignas(64) int valid[kPacket];
    std::size_t live = 0;
    for (std::size_t k = 0; k < kPacket; ++k) {
      const Ray& ray = rays[b + (k < n ? k : 0)];
      // The planes first, in double, as the one-ray query does.
      bool by_plane =
          k < n &&
          std::apply([&](const auto&... set) { return (set.occluded(ray) || ...); }, im.unbounded);
      if (k < n) blocked[b + k] = by_plane;
      valid[k] = k < n && !by_plane ? -1 : 0;
      live += valid[k] != 0;
    }
    g_store_rays16(&rays[b], n, r);
    if (live == 0) continue;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    // Shadow rays of neighbouring hits share an end, not an origin: Embree's
    // incoherent mode (its hybrid traversal) beat the coherent one on the
    // bench/peers scenes (motion 6 % faster, thin lens and lights.scn even).
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    rtcOccluded16(valid, im.world.scene, &ctx, &r);
    for (std::size_t k = 0; k < n; ++k)
      if (valid[k]) blocked[b + k] = r.tfar[k] < 0;
  }
}

std::uint32_t EmbreeScene::occluded(const ShadowLanes16& in, std::uint32_t live) const {
  const Impl& im = *impl_;
  std::uint32_t blocked = 0;
  if (im.any_unbounded)  // the planes first, in double, as the one-ray query does
    std::apply([&](const auto&... set) { ((blocked |= set.occluded_lanes(in, live)), ...); },
               im.unbounded);
  live &= ~blocked;
  if (live == 0) return blocked;
  if ((live & (live - 1)) == 0) {  // a lone ray is traced alone
    const unsigned k = unsigned(std::countr_zero(live));
    return occluded(in.ray(k)) ? blocked | live : blocked;
  }
  alignas(64) RTCRay16 r;
  alignas(64) int valid[kPacket];
  // Lanes off `live` hold what their producer left there (unlit lanes of
  // area_lanes may be unwritten); they take the first live lane's ray, since
  // Embree's debug checks (on in Debian's build) look at lanes it was told to skip
  // on some CPUs: the AVX2 kernels asserted on a garbage direction past 2^60.
  const std::size_t first = std::size_t(std::countr_zero(live));
  for (std::size_t k = 0; k < kPacket; ++k) {
    const std::size_t s = (live >> k) & 1 ? k : first;
    r.org_x[k] = in.ox[s], r.org_y[k] = in.oy[s], r.org_z[k] = in.oz[s];
    r.dir_x[k] = in.dx[s], r.dir_y[k] = in.dy[s], r.dir_z[k] = in.dz[s];
    r.time[k] = in.time[s];
  }
  for (std::size_t k = 0; k < kPacket; ++k) {
    r.tnear[k] = 0, r.tfar[k] = kAreaShadowEnd;
    r.mask[k] = ~0u, r.id[k] = 0, r.flags[k] = 0;
    valid[k] = (live >> k) & 1 ? -1 : 0;
  }
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;  // as the span form's
  rtcOccluded16(valid, im.world.scene, &ctx, &r);
  for (std::uint32_t bits = live; bits; bits &= bits - 1) {
    const unsigned k = unsigned(std::countr_zero(bits));
    if (r.tfar[k] < 0) blocked |= 1u << k;
  }
  return blocked;
}

std::string to_string(const Ray& r) {
  return fmt::format("ray {{ org {} dir {} tmax {} time {} }}", rt::to_string(r.org),
                     rt::to_string(r.dir), r.tmax, r.time);
}

std::string to_string(const Hit& h) {
  return fmt::format("hit {{ t {} ng {} p {} offset {} {} {} material {}{} }}", h.t,
                     rt::to_string(h.ng), rt::to_string(h.p), h.offset,
                     h.kind == Hit::Kind::Shape ? "shape" : "area_light", h.index, h.material,
                     h.smooth ? " ns " + rt::to_string(h.ns) : "");
}

std::string EmbreeScene::to_string() const {
  const Impl& im = *impl_;
  return fmt::format(
      "embree_scene {{ origin {} spheres {} csg {} planes {} triangles {} area_light_tris {} "
      "instances {} prototypes {} moving_shapes {} motion_steps {} }}",
      ir::to_string(origin_), std::get<SphereSet>(im.world.user_sets).size(),
      std::get<CsgSet>(im.world.user_sets).size(), std::get<PlaneSet>(im.unbounded).size(),
      im.world.triangle_count, im.light_tris, im.instance_count, im.protos.size(), im.moving_shapes,
      im.motion_steps);
}

}  // namespace snell::rt
