// §17: the image files `image` patterns name. The compiler only checks that each
// is a readable regular file (an error at its `file`, exit 3, before anything is
// rendered); decoding is the texture system's (runtime/shading/image_texture.hpp),
// and the CLI opens every image through it before the render starts, so a file
// that exists but is not an image also fails before the render (exit 3).
#include <filesystem>
#include <fstream>

#include "compiler/compile.hpp"
#include "compiler/lower.hpp"

namespace snell::compile {

using lang::DiagKind;
using lang::Span;

bool SceneBuilder::add_image(const std::string& file, Span span, std::uint32_t& index) {
  namespace fs = std::filesystem;
  fs::path p(file);
  if (p.is_relative() && span.file < sources_.size())
    p = fs::path(sources_.file(span.file).path()).parent_path() / p;
  std::string key = p.lexically_normal().string();
  if (auto it = image_ids_.find(key); it != image_ids_.end()) {
    index = it->second;
    return true;
  }
  if (std::string why = not_a_file(p.string()); !why.empty()) {
    diags_.report(DiagKind::FileUnreadable, span, "image file '" + key + "' " + why);
    return false;
  }
  if (!std::ifstream(p, std::ios::binary).good()) {
    diags_.report(DiagKind::FileUnreadable, span, "cannot read image file '" + key + "'");
    return false;
  }
  index = std::uint32_t(scene_.images.size());
  scene_.images.push_back({key, ref(span)});
  image_ids_.emplace(key, index);
  return true;
}

}  // namespace snell::compile
