// The render kernels' specialisation axes (architecture: "simulate only the effects
// a scene calls for"), in ONE list. From it come the kernel's compile-time flags,
// its bits, its name in --stats, the choice from ir::Features and every table of
// instantiations: adding an axis is one row here and its `if constexpr` uses.
//
//   X(axis, feature, needs, on, off)
//     axis     the flag's name (Kernel<B>::axis)
//     feature  the ir::Features member that turns it on
//     needs    an axis that must be on too (or `none`): absorption and interiors
//              need dielectric; highlights (§16) needs nothing
//     on, off  how --stats names the kernel's choice
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>

#include "runtime/ir/ir.hpp"

#define SNELL_KERNEL_AXES(X)                                                 \
  X(lens, depth_of_field, none, "thin lens", "pinhole")                      \
  X(time, motion_blur, none, "motion (time sampled)", "static")              \
  X(area, area_lights, none, "area lights", "point lights only")             \
  X(dielectric, dielectric, none, "clear dielectrics", "no dielectrics")     \
  X(absorption, absorption, dielectric, "dielectrics with absorption", "")   \
  X(interiors, interiors, dielectric, "nested dielectrics (priorities)", "") \
  X(finish, finish, none, "finish (highlights, bumps)", "")

namespace snell::rt {

enum KernelAxis : unsigned {
#define SNELL_AXIS_ENUM(axis, feature, needs, on, off) kAxis_##axis,
  SNELL_KERNEL_AXES(SNELL_AXIS_ENUM)
#undef SNELL_AXIS_ENUM
      kAxisCount,
  kAxis_none = 64  // "needs nothing": a bit that is never set
};
inline constexpr unsigned kKernelCount = 1u << kAxisCount;

// Bits with every axis whose `needs` is off cleared: the kernels that exist.
constexpr unsigned canonical_kernel(unsigned bits) {
  auto on = [&](unsigned axis) { return axis >= kAxisCount || ((bits >> axis) & 1); };
#define SNELL_AXIS_NEEDS(axis, feature, needs, on_, off_) \
  if (kAxis_##needs != kAxis_none && !on(kAxis_##needs)) bits &= ~(1u << kAxis_##axis);
  SNELL_KERNEL_AXES(SNELL_AXIS_NEEDS)
#undef SNELL_AXIS_NEEDS
  return bits;
}

// A kernel's flags at compile time: Kernel<B>::lens, ::time, ...
template <unsigned B>
struct Kernel {
  static constexpr unsigned bits = canonical_kernel(B);
#define SNELL_AXIS_FLAG(axis, feature, needs, on, off) \
  static constexpr bool axis = ((bits >> kAxis_##axis) & 1) != 0;
  SNELL_KERNEL_AXES(SNELL_AXIS_FLAG)
#undef SNELL_AXIS_FLAG
};
using GeneralKernel = Kernel<kKernelCount - 1>;

// Which kernel a scene needs: the effects it uses, or every one (--features=all).
struct KernelChoice {
  unsigned bits = kKernelCount - 1;
  bool general = true;
  std::string name() const;  // "general (...)" or "specialised: pinhole, static, ..."
};
KernelChoice choose_kernel(const ir::Scene& scene, bool general);

// {F<Kernel<0>>, F<Kernel<1>>, ...}: one entry per bit pattern, bit patterns with
// the same canonical kernel sharing one instantiation (Kernel<canonical>), so only
// the distinct kernels are compiled. `Make<K>::value` is the entry.
template <template <class> class Make, unsigned... B>
constexpr auto kernel_table(std::integer_sequence<unsigned, B...>) {
  return std::array{Make<Kernel<canonical_kernel(B)>>::value...};
}
template <template <class> class Make>
constexpr auto kernel_table() {
  return kernel_table<Make>(std::make_integer_sequence<unsigned, kKernelCount>{});
}

}  // namespace snell::rt
