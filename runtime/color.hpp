// Display colour through OpenColorIO. color.cpp is the only translation unit that
// includes OCIO. Linear scene-referred radiance (the config's scene_linear role)
// goes through a display and view of the chosen config; by default the config's
// default display and that display's default view ("sRGB - Display" / "Standard"
// in the config Snell ships, which does not clamp: callers clamp before
// quantising).
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "runtime/image_format.hpp"  // DisplayView

namespace snell::rt {

// The config to use: `explicit_path` if not empty, else $OCIO, else the file baked
// at build time (source tree), else the installed one. Empty when none exists.
std::string resolve_ocio_config(const std::string& explicit_path);

// One OCIO colour transform, made once (loading the config and building the
// processor is the expensive part) and applied to any number of pixels, from any
// number of threads.
class ColorTransform {
 public:
  // Linear radiance to the display and view `dv` names, or null with `error`
  // saying why: no config, one that does not load, a display or view it does not
  // have (with the ones it has).
  static std::unique_ptr<ColorTransform> to_display(const DisplayView& dv, std::string& error);
  // A file's colour space (its oiio:ColorSpace, as a name or alias of the config
  // at `config`, resolved as resolve_ocio_config does) to the config's
  // scene_linear role, or null with `error` when the config lacks that space.
  static std::unique_ptr<ColorTransform> to_scene_linear(const std::string& config,
                                                         const std::string& space,
                                                         std::string& error);
  ~ColorTransform();

  // Whether it changes nothing (a file already in scene_linear).
  bool is_identity() const;
  // In place, on `pixels` packed RGB triples.
  void apply(float* rgb, std::size_t pixels) const;
  // "CONFIG: DISPLAY / VIEW" or "CONFIG: SPACE -> scene_linear", as resolved.
  std::string to_string() const;
  // The same without the config's path: "DISPLAY / VIEW" (image metadata).
  const std::string& name() const;

 private:
  struct Impl;
  explicit ColorTransform(std::unique_ptr<Impl> impl);
  static bool resolve_into(const std::string& config, Impl& impl, std::string& error);
  std::unique_ptr<Impl> impl_;
};

// 8-bit code of a display value: NaN → 0, clamp to [0, 1], round(255·v).
unsigned char quantize8(float v);

}  // namespace snell::rt
