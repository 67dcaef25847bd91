// Display colour through OpenColorIO. color.cpp is the only translation unit that
// includes OCIO. Linear scene-referred Rec.709 → "sRGB - Display" / "Standard" of
// the chosen config (which does not clamp: callers clamp before quantising).
#pragma once

#include <cstddef>
#include <string>

namespace snell::rt {

// The config to use: `explicit_path` if not empty, else $OCIO, else the file baked
// at build time (source tree), else the installed one. Empty when none exists.
std::string resolve_ocio_config(const std::string& explicit_path);

// Applies the display view transform in place to `pixels` RGB triples. Returns an
// error message, or empty on success.
std::string apply_display_transform(const std::string& config_path, float* rgb, std::size_t pixels);

// 8-bit code of a display value: NaN → 0, clamp to [0, 1], round(255·v).
unsigned char quantize8(float v);

}  // namespace snell::rt
