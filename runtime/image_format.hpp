// Which image files Snell writes, by extension, and through which display
// transform: shared by the loader (image_out.cpp, checked before a render starts)
// and the OIIO module.
#pragma once

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <string>

namespace snell::rt {

// The extension of `path`, lower-cased, with its dot (".exr"); empty if none.
inline std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

inline bool is_supported_image_extension(const std::string& path) {
  std::string e = lower_extension(path);
  return e == ".exr" || e == ".png" || e == ".jpg" || e == ".jpeg" || e == ".tif" || e == ".tiff";
}

// Why a `width`×`height` image cannot be written as `path`'s format, or empty.
// Checked before the render: libjpeg ends the process (exit(1), no message, any
// later outputs lost) on an image it cannot hold, instead of returning an error.
inline std::string format_limit(const std::string& path, std::uint64_t width,
                                std::uint64_t height) {
  std::string e = lower_extension(path);
  // JPEG_MAX_DIMENSION in libjpeg's jmorecfg.h.
  if ((e == ".jpg" || e == ".jpeg") && (width > 65500 || height > 65500))
    return "a JPEG holds at most 65500 pixels a side (write .png, .tif or .exr)";
  // libpng's user limits (PNG_USER_WIDTH_MAX, PNG_USER_HEIGHT_MAX), which
  // OpenImageIO keeps: its IHDR is refused only once the render is done.
  if (e == ".png" && (width > 1000000 || height > 1000000))
    return "a PNG holds at most 1000000 pixels a side here, libpng's limit (write .tif or .exr)";
  return {};
}

// How display-referred outputs (PNG, JPEG, TIFF) are made from linear radiance:
// the OpenColorIO config, and a display and view of it. Empty fields take the
// defaults: the config from $OCIO, else the one Snell ships; the config's
// default display, and that display's default view.
struct DisplayView {
  std::string config;
  std::string display;
  std::string view;
};

}  // namespace snell::rt
