// The integrators by the `integrator` setting: the row X(spelling, Name) of
// runtime/ir/kinds.def's SNELL_INTEGRATOR_VALUES is the class NameIntegrator.
#include "runtime/integrators/integrator.hpp"

#include "runtime/integrators/whitted.hpp"

namespace snell::rt {

namespace {
template <class I>
std::unique_ptr<Integrator> make(const ir::Scene& scene, const EmbreeScene& embree,
                                 const ImageTextures* images) {
  return std::make_unique<I>(scene, embree, images);
}
using Factory = std::unique_ptr<Integrator> (*)(const ir::Scene&, const EmbreeScene&,
                                                const ImageTextures*);
#define SNELL_INTEGRATOR_FACTORY(spelling, Name) &make<Name##Integrator>,
constexpr Factory kFactories[] = {SNELL_INTEGRATOR_VALUES(SNELL_INTEGRATOR_FACTORY)};
#undef SNELL_INTEGRATOR_FACTORY
}  // namespace

std::unique_ptr<Integrator> make_integrator(const ir::Scene& scene, const EmbreeScene& embree,
                                            const ImageTextures* images) {
  return kFactories[std::size_t(scene.settings.integrator) % std::size(kFactories)](scene, embree,
                                                                                    images);
}

}  // namespace snell::rt
