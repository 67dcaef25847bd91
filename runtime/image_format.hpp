// Which image files Snell writes, by extension: shared by the loader
// (image_out.cpp, checked before a render starts) and the OIIO module.
#pragma once

#include <algorithm>
#include <cctype>
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

}  // namespace snell::rt
