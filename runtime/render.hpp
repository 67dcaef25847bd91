// The runtime's public face: render an ir::Scene into an image, write images.
// The CLI, tests and benchmarks use only this header (and ir/).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "runtime/image_format.hpp"  // is_supported_image_extension
#include "runtime/ir/ir.hpp"

namespace snell::rt {

// Linear scene-referred RGB radiance, row-major, pixel (0, 0) top-left.
// A crop (§18) is a window of a larger image: its pixel (0, 0) is pixel (x0, y0) of
// the full_width × full_height image (an EXR's data and display windows); a whole
// image has x0 = y0 = 0 and full_* = 0 (meaning width and height).
struct Image {
  std::uint32_t width = 0, height = 0;
  std::uint32_t x0 = 0, y0 = 0, full_width = 0, full_height = 0;
  std::vector<float> rgb;  // 3 floats per pixel
  std::uint32_t display_width() const { return full_width ? full_width : width; }
  std::uint32_t display_height() const { return full_height ? full_height : height; }
  float* at(std::uint32_t x, std::uint32_t y) { return &rgb[3 * (std::size_t(y) * width + x)]; }
  const float* at(std::uint32_t x, std::uint32_t y) const {
    return &rgb[3 * (std::size_t(y) * width + x)];
  }
};

struct RenderOptions {
  int threads = 0;              // 0: every core
  bool general_kernel = false;  // --features=all: ignore ir::Features
  // Kernel axes compiled in although the scene does not use them (bit i: axis i of
  // SNELL_KERNEL_AXES): for measuring what one effect costs a scene without it
  // (bench_kernels --with AXIS). The picture must not change.
  unsigned extra_axes = 0;
  // The OCIO config whose colour spaces §17 images tagged with one are in (a path;
  // empty: $OCIO, else Snell's), as --ocio-config gives it.
  std::string ocio_config;
  // Called from the render loop with the fraction done (0..1); may be empty.
  std::function<void(double)> progress;
  // --pixel X,Y: print that pixel's ray tree to `trace_out` (stderr in the CLI).
  std::optional<std::pair<std::uint32_t, std::uint32_t>> trace_pixel;
  // --stats: time a subset of camera samples by effect (RenderStats' *_seconds),
  // each traced alone (the rest of the tile still in packets). Off, the render
  // never reads the clock per sample; the picture is the same either way.
  bool measure_cost = false;
  // Camera rays in packets (render/tile.hpp); off, every tile goes one ray at a time
  // (tests: the two must make the same picture).
  bool packets = true;
  // §18 split renders. `crop`: only the pixels x0 <= x < x1, y0 <= y < y1 of the
  // full image (the result is that window, Image::x0/y0 set). `sample_range`: only
  // samples [first, second) of every pixel's full sequence (the sampler is a pure
  // function of the full image's pixel, the sample index and the full spp), each
  // pixel the mean of those samples. Both are clamped to the image and to spp; the
  // CLI rejects values outside them first.
  struct Window {
    std::uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  };
  std::optional<Window> crop;
  std::optional<std::pair<std::uint32_t, std::uint32_t>> sample_range;
  // snell watch: set (from any thread) to abandon the render; tiles not yet begun
  // are skipped and running ones stop within 16 samples per pixel block. The result's
  // image is then incomplete (RenderResult::cancelled); a render never cancelled
  // is unchanged by the check.
  const std::atomic<bool>* cancel = nullptr;
};

// Counters for --stats; summed over threads after the render.
struct RenderStats {
  std::uint64_t camera_rays = 0, shadow_rays = 0, reflection_rays = 0, refraction_rays = 0;
  std::uint64_t glossy_rays = 0;
  std::uint64_t pruned_by_depth = 0, pruned_by_weight = 0, tir_events = 0;
  std::uint64_t nonfinite_samples = 0;  // dropped, never written to the film
  // §14 interiors: surfaces passed straight through (inside a solid of higher
  // priority), entries forgotten by a full interior, branches lost after
  // kMaxPassThroughs surfaces in a row.
  std::uint64_t interior_passes = 0, interior_overflows = 0, interior_lost = 0;
  // §15: hits where a shading function's value was not finite (0 used there).
  std::uint64_t function_nonfinite = 0;
  double build_seconds = 0, render_seconds = 0;
  // Distribution effects: camera samples that drew a lens / a time sample.
  std::uint64_t lens_samples = 0, time_samples = 0;
  // Cost by effect, in thread-seconds, when RenderOptions::measure_cost: measured with a steady
  // clock on a fixed, deterministic subset of camera samples (1 in `cost_stride`) and scaled up by
  // the ratio of all camera samples to timed ones (docs/effects.md). Each ray's time is its query
  // plus its shading; direct light (all its shadow rays) is shadow time; lens and time are the
  // sample draw plus, for the lens, the thin-lens ray setup.
  double camera_seconds = 0, shadow_seconds = 0, reflection_seconds = 0, refraction_seconds = 0,
         glossy_seconds = 0, lens_seconds = 0, time_seconds = 0;
  std::uint64_t timed_samples = 0;  // camera samples that were timed
  std::uint32_t cost_stride = 0;
  std::string kernel;  // the render kernel that ran, e.g. "specialised: pinhole, static, ..."
  // Adds another thread's counters (stats.cpp: declared, merged and printed there).
  void merge(const RenderStats& other);
  std::string to_string() const;
};

struct RenderResult {
  Image image;
  RenderStats stats;
  std::string trace;          // the --pixel ray tree, when asked for
  std::string texture_stats;  // §17: OIIO's texture statistics when the scene has images
  bool cancelled = false;     // RenderOptions::cancel was set: some tiles were skipped
};

RenderResult render(const ir::Scene& scene, const RenderOptions& options);

struct OutputInfo {
  std::string scene_path;
  std::uint32_t samples = 0;
  std::uint64_t seed = 0;
  double render_seconds = 0;
  // Further metadata, written as string attributes (EXR header, PNG text): the
  // §18 piece identity (cli/split.hpp names them).
  std::vector<std::pair<std::string, std::string>> attributes;
};

// Writes `image` to `path`; the format follows the extension: .exr holds linear
// float32 radiance, .png/.jpg/.jpeg/.tif/.tiff display-referred codes made through
// `display` (an OCIO config, display and view; empty fields take the defaults).
// The image is encoded whole in memory, then written by write_file_atomically
// (atomic_file.hpp): an existing file is replaced whole or left untouched, a
// symlink is written through. Returns an error message, or an empty string on
// success. The encoder lives in a module loaded on first use (image_out.cpp); a
// missing module is an error message, like a failed write.
std::string write_image(const std::string& path, const Image& image, const OutputInfo& info,
                        const DisplayView& display);
// Who encodes `image` for write_image: "this process", or the image helper or
// resident server (image_writer_kind) for images whose film is at most 64 MB.
std::string image_encoder_for(const Image& image);

// An image file read back (snell merge): its pixels as linear float RGB (the
// first three channels), its data window at its place in the display window,
// and its string-valued metadata (every attribute, as text). Returns an error
// message, or empty. Through the image module, like write_image.
struct ImageFile {
  Image image;
  std::vector<std::pair<std::string, std::string>> attributes;
  const std::string* attribute(const std::string& name) const {
    for (const auto& [k, v] : attributes)
      if (k == name) return &v;
    return nullptr;
  }
};
std::string read_image(const std::string& path, ImageFile& out);

// Loads the image-output module now rather than at the first write_image (the
// CLI calls it before the render, so a writer that cannot load fails early).
// Returns an error message, or empty when the module is ready. Thread-safe.
std::string preload_image_writer();
// Whether the display transform of the PNG/JPEG/TIFF outputs can be made (`display`
// as write_image takes it): the error message a write would give, or empty. The
// CLI asks before the render, so a bad config, display or view loses no render.
std::string check_display_transform(const DisplayView& display);

// §17: opens every image of the scene through the texture system (colour spaces
// by name from `ocio_config`, as RenderOptions::ocio_config) (the CLI calls it
// before the render, so an unreadable image fails with exit 3 before the work).
// Returns an error message, or empty; `failed` and `why` as ImageTextures::open
// sets them (the image that could not be read, the reader's reason). Defined in
// shading/image_texture.cpp.
std::string check_images(const ir::Scene& scene, const std::string& ocio_config = {},
                         std::size_t* failed = nullptr, std::string* why = nullptr);

// §10's "all independent errors": every image that cannot be read, as (index into
// `images`, the reader's reason), in order; empty when all can. `error` is set
// instead when the image module itself cannot load. `notes`, when given, gets
// what a readable image's reading says of it (NaN texels mended), likewise.
std::vector<std::pair<std::size_t, std::string>> unreadable_images(
    const std::vector<ir::ImageFile>& images, const std::string& ocio_config, std::string& error,
    std::vector<std::pair<std::size_t, std::string>>* notes = nullptr);

// One-line descriptions for logs and test failures.
std::string to_string(const Image& image);
std::string to_string(const RenderOptions& options);
std::string to_string(const OutputInfo& info);

}  // namespace snell::rt
