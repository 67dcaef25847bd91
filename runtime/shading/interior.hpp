// §14 interiors: the prioritised dielectric solids a ray is inside, and what a
// crossing of one of their surfaces does (Schmidt & Budge, "Simple nested
// dielectrics in ray traced images", JGT 7(2), 2002; higher priority wins, as in
// Arnold and RenderMan).
//
// A ray carries the prioritised solids it has entered, in order (`Interior`). Its
// medium is the entry of highest priority, the one entered last among equals; air
// (index 1) when there is none. A surface of a prioritised solid *counts* only
// where the medium on its far side differs from the one the ray is in: a surface
// inside a solid of higher priority changes nothing and the ray passes straight
// through it (a false hit). Where it counts, the interface is n_leaving →
// n_entering of those two media. Dielectrics without a priority are not tracked:
// each is still the core's air ↔ ior interface wherever it is (§8).
//
// Limits, chosen to be defined rather than exact:
//   - a ray passes through at most kMaxPassThroughs surfaces between two
//     interactions; past that its branch is lost (black, counted in --stats);
//   - at most Interior::kMax entries; entering one more forgets the entry of lowest
//     priority (the earliest among equals, the new one included), counted in
//     --stats as an interior overflow;
//   - leaving a solid the ray has no entry for (forgotten, or a camera inside one
//     the start-up test does not see) is taken as if the ray had entered it first:
//     it counts when its priority beats the medium left on the stack;
//   - the camera's starting interior is found once, by inside tests at the camera
//     location at shutter open (geometry/point_inside.hpp: solid primitives, a
//     plane's half-space, closed meshes, CSG objects by their trees, instances).
//
// A solid is a top-level shape, or one part of an instance (§13): each instance
// of an object value places its own solids, so a glass of water bound by `let`
// and placed with `object { }` nests as the same glass written out does. Solids
// are numbered: the scene's shapes first, then the parts of each instance that has
// a prioritised one, in the scene's order.
#pragma once

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "runtime/geometry/ray.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::rt {

// The prioritised solids a ray is inside, oldest first. Plain data, copied into
// each branch of the ray tree.
struct Interior {
  static constexpr int kMax = 8;
  static constexpr std::uint32_t kAir = 0xffffffffu;  // the medium outside every solid
  struct Entry {
    std::uint32_t shape = 0;     // the solid (Interiors::solid)
    std::uint32_t priority = 0;  // >= 1
  };
  Entry entries[kMax];
  std::uint8_t count = 0;

  bool empty() const { return count == 0; }
  // The position of the medium's entry: highest priority, the latest among
  // equals; -1 for air.
  int medium_index() const {
    int best = -1;
    for (int i = 0; i < count; ++i)
      if (best < 0 || entries[i].priority >= entries[best].priority) best = i;
    return best;
  }
  // The solid whose inside the ray travels in, or kAir.
  std::uint32_t medium() const {
    int i = medium_index();
    return i < 0 ? kAir : entries[i].shape;
  }
  // The position of the latest entry of `shape`, or -1.
  int find(std::uint32_t shape) const {
    for (int i = count - 1; i >= 0; --i)
      if (entries[i].shape == shape) return i;
    return -1;
  }
  // Pushes an entry; false when the stack was full and an entry was forgotten
  // (the lowest priority, the earliest among equals; possibly this one).
  bool enter(std::uint32_t shape, std::uint32_t priority) {
    if (count < kMax) {
      entries[count++] = {shape, priority};
      return true;
    }
    int low = 0;
    for (int i = 1; i < count; ++i)
      if (entries[i].priority < entries[low].priority) low = i;
    if (priority < entries[low].priority) return false;
    remove(low);
    entries[count++] = {shape, priority};
    return false;
  }
  void remove(int i) {
    for (int k = i; k + 1 < count; ++k) entries[k] = entries[k + 1];
    --count;
  }
};

std::string to_string(const Interior& in);

// Surfaces one ray may pass straight through before its branch is given up as
// lost (black, counted in --stats): false hits cost no depth, so this bounds them.
inline constexpr int kMaxPassThroughs = 64;

// What crossing one surface of a prioritised solid does.
struct Crossing {
  bool counts = false;                  // false: a false hit, the ray goes straight on
  bool overflow = false;                // entering it forgot an entry (Interior::enter)
  std::uint32_t from = Interior::kAir;  // the medium the ray leaves (shape index or kAir)
  std::uint32_t to = Interior::kAir;    // the medium it enters
  Interior after;                       // the interior on the far side
};

std::string to_string(const Crossing& c);

// The scene's prioritised solids: each shape's priority, the media's indices and
// absorption, and the camera's starting interior. A scene without priorities
// keeps no table, and every shape's priority is 0.
class Interiors {
 public:
  explicit Interiors(const ir::Scene& scene);

  // The solid a shape hit is on: the top-level shape, or the instance's part.
  std::uint32_t solid(const Hit& hit) const {
    if (instance_base_.empty()) return hit.index;
    return solid_of_instance(hit);
  }
  // The solid's priority, or 0 when it is not a prioritised dielectric solid.
  std::uint32_t priority(std::uint32_t solid) const {
    return solid < priority_.size() ? priority_[solid] : 0;
  }
  // The index of refraction of a medium (1 for air).
  double ior(std::uint32_t medium) const;
  // Its Beer coefficient, or null for air.
  const ir::Vec3* absorb(std::uint32_t medium) const;
  // The interior camera rays start with.
  const Interior& camera() const { return camera_; }

  // Crossing the surface of prioritised solid `solid` (priority(solid) > 0) with
  // interior `in`, entering (against the outward normal) or leaving it.
  Crossing cross(const Interior& in, std::uint32_t solid, bool entering) const;

  std::string to_string() const;

 private:
  std::uint32_t solid_of_instance(const Hit& hit) const;

  const ir::Scene& scene_;
  std::vector<std::uint32_t> priority_;  // per solid; empty when the scene has none
  std::vector<std::uint32_t> medium_;    // per prioritised solid: the material of its medium
  // Instances with a prioritised part: the solid of their first part; and each such
  // part's place in its value (into Prototype::parts).
  std::unordered_map<std::uint32_t, std::uint32_t> instance_base_;
  std::unordered_map<std::uint32_t, std::uint32_t> part_place_;
  Interior camera_;
};

}  // namespace snell::rt
