// The only translation unit that includes OpenColorIO.
#include "runtime/color.hpp"

#include <OpenColorIO/OpenColorIO.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace OCIO = OCIO_NAMESPACE;

namespace snell::rt {

std::string resolve_ocio_config(const std::string& explicit_path) {
  if (!explicit_path.empty()) return explicit_path;
  if (const char* env = std::getenv("OCIO"); env && *env) return env;
  std::error_code ec;
#ifdef SNELL_OCIO_BUILD_CONFIG
  if (std::filesystem::exists(SNELL_OCIO_BUILD_CONFIG, ec)) return SNELL_OCIO_BUILD_CONFIG;
#endif
#ifdef SNELL_OCIO_INSTALL_CONFIG
  if (std::filesystem::exists(SNELL_OCIO_INSTALL_CONFIG, ec)) return SNELL_OCIO_INSTALL_CONFIG;
#endif
  return {};
}

std::string apply_display_transform(const std::string& config_path, float* rgb,
                                    std::size_t pixels) {
  std::string path = resolve_ocio_config(config_path);
  if (path.empty()) return "no OpenColorIO config found (set $OCIO or reinstall snell)";
  try {
    OCIO::ConstConfigRcPtr cfg = OCIO::Config::CreateFromFile(path.c_str());
    auto dvt = OCIO::DisplayViewTransform::Create();
    dvt->setSrc(OCIO::ROLE_SCENE_LINEAR);
    dvt->setDisplay("sRGB - Display");
    dvt->setView("Standard");
    OCIO::ConstCPUProcessorRcPtr cpu = cfg->getProcessor(dvt)->getDefaultCPUProcessor();
    // One row of one pixel height: OCIO processes packed RGB float in place.
    OCIO::PackedImageDesc desc(rgb, static_cast<long>(pixels), 1, 3);
    cpu->apply(desc);
  } catch (const OCIO::Exception& e) {
    return std::string("OpenColorIO config '") + path + "': " + e.what();
  }
  return {};
}

unsigned char quantize8(float v) {
  if (!(v > 0)) return 0;  // also NaN
  if (v >= 1) return 255;
  return static_cast<unsigned char>(std::lround(double(v) * 255.0));
}

}  // namespace snell::rt
