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

struct ColorTransform::Impl {
  std::string path, what;
  OCIO::ConstCPUProcessorRcPtr cpu;
};

ColorTransform::ColorTransform(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ColorTransform::~ColorTransform() = default;

namespace {

// "a", "b" and "c" — for the error that names what a config offers.
template <class Count, class Name>
std::string listing(Count count, Name name) {
  std::string s;
  int n = count();
  for (int i = 0; i < n; ++i) {
    s += std::string(i == 0 ? "" : i + 1 == n ? " and " : ", ") + "'" + name(i) + "'";
  }
  return s.empty() ? "none" : s;
}

}  // namespace

// The config path both transforms start from, or false with `error`.
bool ColorTransform::resolve_into(const std::string& config, Impl& impl, std::string& error) {
  impl.path = resolve_ocio_config(config);
  if (impl.path.empty()) error = "no OpenColorIO config found (set $OCIO or reinstall snell)";
  return !impl.path.empty();
}

std::unique_ptr<ColorTransform> ColorTransform::to_display(const DisplayView& dv,
                                                           std::string& error) {
  auto impl = std::make_unique<Impl>();
  if (!resolve_into(dv.config, *impl, error)) return nullptr;
  const std::string where = "OpenColorIO config '" + impl->path + "'";
  try {
    OCIO::ConstConfigRcPtr cfg = OCIO::Config::CreateFromFile(impl->path.c_str());
    // A studio config (ACES, Blender's) names its displays and views as it likes:
    // only the ones asked for, or its defaults, are assumed to exist.
    const std::string display = dv.display.empty() ? cfg->getDefaultDisplay() : dv.display;
    bool has_display = false;
    for (int i = 0; i < cfg->getNumDisplays(); ++i)
      has_display = has_display || display == cfg->getDisplay(i);
    if (!has_display) {
      error = where + " has no display '" + display + "' (it has " +
              listing([&] { return cfg->getNumDisplays(); },
                      [&](int i) { return std::string(cfg->getDisplay(i)); }) +
              ")";
      return nullptr;
    }
    const char* d = display.c_str();
    const std::string view = dv.view.empty() ? cfg->getDefaultView(d) : dv.view;
    bool has_view = false;
    for (int i = 0; i < cfg->getNumViews(d); ++i) has_view = has_view || view == cfg->getView(d, i);
    if (!has_view) {
      error = where + ": the display '" + display + "' has no view '" + view + "' (it has " +
              listing([&] { return cfg->getNumViews(d); },
                      [&](int i) { return std::string(cfg->getView(d, i)); }) +
              ")";
      return nullptr;
    }
    auto dvt = OCIO::DisplayViewTransform::Create();
    dvt->setSrc(OCIO::ROLE_SCENE_LINEAR);
    dvt->setDisplay(d);
    dvt->setView(view.c_str());
    impl->cpu = cfg->getProcessor(dvt)->getDefaultCPUProcessor();
    impl->what = display + " / " + view;
  } catch (const OCIO::Exception& e) {
    error = where + ": " + e.what();
    return nullptr;
  }
  return std::unique_ptr<ColorTransform>(new ColorTransform(std::move(impl)));
}

std::unique_ptr<ColorTransform> ColorTransform::to_scene_linear(const std::string& config,
                                                                const std::string& space,
                                                                std::string& error) {
  auto impl = std::make_unique<Impl>();
  if (!resolve_into(config, *impl, error)) return nullptr;
  const std::string where = "OpenColorIO config '" + impl->path + "'";
  try {
    OCIO::ConstConfigRcPtr cfg = OCIO::Config::CreateFromFile(impl->path.c_str());
    // getColorSpace knows names, aliases and roles, case-insensitively.
    OCIO::ConstColorSpaceRcPtr cs = cfg->getColorSpace(space.c_str());
    if (!cs) {
      error = where + " has no colour space '" + space + "'";
      return nullptr;
    }
    impl->cpu = cfg->getProcessor(cs->getName(), OCIO::ROLE_SCENE_LINEAR)->getDefaultCPUProcessor();
    impl->what = std::string(cs->getName()) + " -> scene_linear";
  } catch (const OCIO::Exception& e) {
    error = where + ": " + e.what();
    return nullptr;
  }
  return std::unique_ptr<ColorTransform>(new ColorTransform(std::move(impl)));
}

void ColorTransform::apply(float* rgb, std::size_t pixels) const {
  // One row of one pixel height: OCIO processes packed RGB float in place.
  OCIO::PackedImageDesc desc(rgb, static_cast<long>(pixels), 1, 3);
  impl_->cpu->apply(desc);
}

bool ColorTransform::is_identity() const {
  return impl_->cpu->isNoOp();
}

const std::string& ColorTransform::name() const {
  return impl_->what;
}

std::string ColorTransform::to_string() const {
  return impl_->path + ": " + impl_->what;
}

unsigned char quantize8(float v) {
  if (!(v > 0)) return 0;  // also NaN
  if (v >= 1) return 255;
  return static_cast<unsigned char>(std::lround(double(v) * 255.0));
}

}  // namespace snell::rt
