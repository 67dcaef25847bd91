// The snell_image_io module (OpenImageIO and OpenColorIO), loaded once on first
// use by whatever needs it: image output (image_out.cpp) and the §17 texture
// system (shading/image_texture.cpp). See image_module.cpp for why it is a module.
#pragma once

#include <string>

namespace snell::rt {

// The module's symbol `name`, or null with `error` saying why (the module could
// not be loaded, or lacks the symbol). Thread-safe; the module is never unloaded.
void* image_module_symbol(const char* name, std::string& error);

}  // namespace snell::rt
