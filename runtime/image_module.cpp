// The snell_image_io module, dlopen'ed once on first use. Linking OIIO directly
// made every start of `snell` bind ~260 shared libraries (0.3 s of a `snell
// check`); now only a command that writes an image or renders a scene with §17
// images pays it.
//
// Where the module is looked for: the build tree's copy (tests and programs run in
// place), then the installed one. Both paths are fixed when Snell is configured.
#include "runtime/image_module.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <filesystem>
#include <mutex>

namespace snell::rt {

namespace {

struct Module {
  void* handle = nullptr;
  std::string error;  // why the module could not be loaded
};

const Module& module() {
  static Module m;
  static std::once_flag once;
  std::call_once(once, [] {
    std::string tried;
    for (const char* path : {SNELL_IMAGE_IO_BUILD_MODULE, SNELL_IMAGE_IO_INSTALL_MODULE}) {
      std::error_code ec;
      if (!std::filesystem::exists(path, ec)) {
        tried += fmt::format("{}{} (missing)", tried.empty() ? "" : ", ", path);
        continue;
      }
      // RTLD_NOW: a broken module fails here, not in the middle of a write.
      // Never unloaded: OIIO keeps threads and static state.
      if (void* h = dlopen(path, RTLD_NOW | RTLD_LOCAL)) {
        m.handle = h;
        return;
      }
      tried += fmt::format("{}{}", tried.empty() ? "" : ", ", dlerror());
    }
    m.error = fmt::format("cannot load the image module (tried {})", tried);
  });
  return m;
}

}  // namespace

void* image_module_symbol(const char* name, std::string& error) {
  const Module& m = module();
  if (!m.handle) {
    error = m.error;
    return nullptr;
  }
  void* f = dlsym(m.handle, name);
  if (!f) error = fmt::format("the image module has no {}", name);
  return f;
}

}  // namespace snell::rt
