// The integrator interface: what the renderer asks of a light-transport algorithm.
// An integrator hands out its per-tile loop specialised on a render kernel
// (render/kernel.hpp), so its radiance function is inlined into the pixel loop
// and compiled once per kernel, with no virtual call per ray. Chosen by the
// `integrator` setting (make_integrator); today's ray tree ("whitted") is the first.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "runtime/embree_scene.hpp"
#include "runtime/ir/ir.hpp"
#include "runtime/shading/image_texture.hpp"

namespace snell::rt {

struct TileContext;
struct Worker;
using TileFn = void (*)(const TileContext&, std::uint32_t tile, Worker&);

// A camera ray's nearest hit found ahead of its tree (the pixel loop traces the
// camera rays of a block of pixels as one packet): what EmbreeScene::intersect
// returned for that ray.
struct PrimaryHit {
  Hit* hit = nullptr;  // the integrator may work on it in place (the packet's copy)
  bool found = false;
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  // The tile loop of kernel `bits` (KernelChoice::bits) for this integrator.
  virtual TileFn tile_kernel(unsigned bits) const = 0;
  virtual std::string to_string() const = 0;
};

// `images`: the render's §17 texture system (null when the scene has no images).
std::unique_ptr<Integrator> make_integrator(const ir::Scene& scene, const EmbreeScene& embree,
                                            const ImageTextures* images = nullptr);

}  // namespace snell::rt
