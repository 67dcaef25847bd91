// §17: the image files `image` patterns name. The compiler checks that each is a
// readable regular file and, where its extension names a format with a signature,
// that its first bytes are that signature (an error at its `file`, exit 3, before
// anything is rendered, in `snell check` too; a text file named .png is caught
// here without loading the image module). Decoding is the texture system's
// (runtime/shading/image_texture.hpp), and the CLI opens every image through it
// before the render starts, so a file that is damaged past its first bytes also
// fails before the render (exit 3, at the same place).
#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "compiler/compile.hpp"
#include "compiler/lower.hpp"

namespace snell::compile {

using lang::DiagKind;
using lang::Span;

namespace {

// What a file named with a format's extension must begin with; "" when the file
// starts as that format does (or the extension names no format with a signature:
// TGA and the camera raw formats have none, and are left to the texture system).
std::string signature_mismatch(const std::filesystem::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  struct Format {
    const char* ext;
    const char* name;                // with its article
    std::vector<std::string> magic;  // any of them
  };
  using namespace std::string_literals;
  static const std::array<Format, 12> kFormats{{
      {".png", "a PNG", {"\x89PNG\r\n\x1a\n"s}},
      {".jpg", "a JPEG", {"\xff\xd8\xff"s}},
      {".jpeg", "a JPEG", {"\xff\xd8\xff"s}},
      {".exr", "an OpenEXR", {"\x76\x2f\x31\x01"s}},
      {".tif", "a TIFF", {"II*\0"s, "MM\0*"s, "II+\0"s, "MM\0+"s}},
      {".tiff", "a TIFF", {"II*\0"s, "MM\0*"s, "II+\0"s, "MM\0+"s}},
      {".hdr", "a Radiance HDR", {"#?"s}},
      {".ppm", "a PNM", {"P3"s, "P6"s}},
      {".pgm", "a PNM", {"P2"s, "P5"s}},
      {".pnm", "a PNM", {"P1"s, "P2"s, "P3"s, "P4"s, "P5"s, "P6"s}},
      {".bmp", "a BMP", {"BM"s}},
      {".gif", "a GIF", {"GIF87a"s, "GIF89a"s}},
  }};
  for (const Format& f : kFormats) {
    if (ext != f.ext) continue;
    char head[8] = {};
    std::ifstream in(p, std::ios::binary);
    in.read(head, sizeof head);
    std::size_t got = std::size_t(in.gcount());
    for (const std::string& m : f.magic)
      if (got >= m.size() && std::memcmp(head, m.data(), m.size()) == 0) return "";
    return "is not " + std::string(f.name) + " image (" +
           (got == 0 ? std::string("it is empty")
                     : "its first bytes are not those of " + std::string(f.name) + " file") +
           ")";
  }
  return "";
}

}  // namespace

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
  if (std::string why = signature_mismatch(p); !why.empty()) {
    diags_.report(DiagKind::FileUnreadable, span, "image file '" + key + "' " + why);
    return false;
  }
  index = std::uint32_t(scene_.images.size());
  scene_.images.push_back({key, ref(span)});
  image_ids_.emplace(key, index);
  return true;
}

}  // namespace snell::compile
