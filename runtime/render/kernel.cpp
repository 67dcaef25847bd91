#include "runtime/render/kernel.hpp"

namespace snell::rt {

KernelChoice choose_kernel(const ir::Scene& scene, bool general) {
  KernelChoice k;
  if (general) return k;
  ir::Features f = ir::analyze_features(scene);
  k.general = false;
  k.bits = 0;
#define SNELL_AXIS_CHOOSE(axis, feature, needs, on, off) \
  if (f.feature) k.bits |= 1u << kAxis_##axis;
  SNELL_KERNEL_AXES(SNELL_AXIS_CHOOSE)
#undef SNELL_AXIS_CHOOSE
  k.bits = canonical_kernel(k.bits);
  return k;
}

// Each axis names its choice; an axis that refines another (absorption refines
// dielectric) replaces that one's name when on, and says nothing when off.
std::string KernelChoice::name() const {
  if (general) return "general (every effect compiled in)";
  std::string words[kAxisCount];
  bool shown[kAxisCount] = {};
#define SNELL_AXIS_NAME(axis, feature, needs, on, off)                                 \
  {                                                                                    \
    bool set = (bits >> kAxis_##axis) & 1;                                             \
    words[kAxis_##axis] = set ? on : off;                                              \
    shown[kAxis_##axis] = !words[kAxis_##axis].empty();                                \
    if (set && kAxis_##needs != kAxis_none) shown[kAxis_##needs % kAxisCount] = false; \
  }
  SNELL_KERNEL_AXES(SNELL_AXIS_NAME)
#undef SNELL_AXIS_NAME
  std::string s = "specialised: ";
  bool first = true;
  for (unsigned a = 0; a < kAxisCount; ++a) {
    if (!shown[a]) continue;
    s += (first ? "" : ", ") + words[a];
    first = false;
  }
  return s;
}

}  // namespace snell::rt
