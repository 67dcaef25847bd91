// The strict Wavefront OBJ reader behind `mesh { file }` (§8): the statements Snell
// draws (v, vt, vn, f) read exactly, every malformed one an error at its line and
// column, polygons triangulated in linear time. No file system here: read_obj
// (mesh_load.hpp) feeds it the file's lines, the fuzz target
// (tests/fuzz/fuzz_obj.cpp) feeds it bytes, through the same code.
//
// The format read, one statement per line:
//   v  x y z [w]   or   v x y z r g b [a]   a position (w and a colour: read, ignored)
//   vt u [v [w]]                            a texture coordinate (v defaults to 0)
//   vn x y z                                a normal as written (normalised later)
//   f  c c c ...                            a polygon of >= 3 corners, each
//                                           v | v/vt | v//vn | v/vt/vn
// - `#` starts a comment anywhere on a line; a `\` ending a line (after the comment
//   is cut, spaces after it allowed) joins the next line to it, as the OBJ
//   specification allows; LF and CR LF line ends, a last line without a newline.
// - Numbers are decimal: [+|-] digits [. digits] [(e|E) [+|-] digits] (C's strtod
//   form without hex, nan or inf). "1,5", "zero", "nan", "inf", a missing
//   coordinate or a value beyond float range (3.4e38) is an error; a value that
//   underflows reads as 0 or a subnormal, as strtod reads it. Values are rounded to
//   float: the precision meshes were always read at (tinyobjloader read floats;
//   Embree intersects in float), so a file reads to the same numbers as before.
// - Indices are 1-based; a negative one counts back from the last element read so
//   far (-1 = the latest), as the OBJ specification defines. 0, a negative index
//   reaching before the first element, a positive one beyond the file's count, or
//   one beyond 64 bits is an error. A positive index may name an element defined
//   further down the file (tinyobjloader and most readers resolve indices over the
//   whole file), so those are checked at the end.
// - A face with fewer than 3 corners is an error. Corners of one face may mix forms
//   (`f 1//1 2 3//1`): the face then shades flat, as before.
// - Every other statement (o, g, s, usemtl, mtllib, vp, and unknown keywords) is
//   ignored, as OBJ readers do; `l`, `p` and free-form geometry (curv, curv2, surf)
//   are counted, so the caller can warn that they are not drawn.
//
// Triangulation, linear in the corners:
// - a triangle is kept as written;
// - a quad is split along its shorter diagonal, compared in float:
//   (0 1 2)(0 2 3) when |v0 v2|² < |v1 v3|², else (0 1 3)(1 2 3) — exactly
//   tinyobjloader 2.0's rule, so every quad mesh read before reads to the same
//   triangles in the same order;
// - a polygon of n >= 5 corners is a fan around its first corner: (0 k k+1),
//   k = 1 .. n-2. For a convex planar polygon — what modellers export, and the
//   only kind OBJ defines a meaning for — every triangulation covers the same
//   surface, so it renders as tinyobjloader's ear clipping did (which was
//   quadratic: 40 k corners took 3.3 s, 1 M never ended). A concave or non-planar
//   polygon may come out differently: triangulate it in the modeller.
//
// Limits: at most kMaxObjErrors errors are kept (in line order; all are counted);
// one error per statement (its first problem); at most 2³² - 2 elements of a kind.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "runtime/ir/math.hpp"

namespace snell::compile {

inline constexpr std::size_t kMaxObjErrors = 20;

struct ObjError {
  std::size_t line = 0;  // 1-based, the physical line of the offending token
  std::size_t col = 0;   // 1-based byte column
  std::string message;
};

// One corner of a triangle: 0-based indices into ObjData's arrays, kNone when the
// corner does not name one.
struct ObjCorner {
  static constexpr std::uint32_t kNone = 0xffffffffu;
  std::uint32_t v = kNone, vt = kNone, vn = kNone;
};

struct ObjData {
  std::vector<ir::Vec3> positions;
  std::vector<ir::Vec3> texcoords;   // (u, v, 0)
  std::vector<ir::Vec3> normals;     // as written, not normalised
  std::vector<ObjCorner> corners;    // three per triangle, faces in file order
  std::vector<ObjError> errors;      // the first kMaxObjErrors, in line order
  std::size_t error_count = 0;       // all of them
  std::size_t ignored_geometry = 0;  // l, p, curv, curv2, surf statements
  std::size_t first_ignored_line = 0;
};

// Reads an OBJ file line by line; finish() once after the last line.
class ObjParser {
 public:
  // One physical line, without its '\n' (a trailing '\r' is allowed).
  void line(std::string_view text);
  ObjData finish();

 private:
  // A quad naming a vertex further down the file: split in finish(), into the
  // six corners reserved for it at `slot` (keeping the file's triangle order).
  struct Quad {
    std::size_t slot;
    ObjCorner c[4];
  };
  // A positive index beyond the count read so far: checked in finish().
  struct Forward {
    std::uint64_t index;  // 1-based, as written
    std::size_t line, col;
    int kind;  // 0 v, 1 vt, 2 vn
  };

  void statement(std::string_view s);
  void vertex(std::string_view key, std::string_view rest, int kind);
  void face(std::string_view rest);
  bool corner(std::string_view tok, ObjCorner& c);
  bool index(std::string_view tok, int kind, std::uint32_t& out);
  bool number(std::string_view tok, double& out);
  void error(std::string_view at, std::string message);
  std::pair<std::size_t, std::size_t> where(std::string_view at) const;
  std::size_t count(int kind) const;
  void split_quad(const ObjCorner* c, std::size_t slot);

  ObjData d_;
  std::size_t line_no_ = 0;
  // The statement being read: the physical line itself, or joined_ when it was
  // continued with `\`; segments_ maps joined_'s offsets to their lines.
  std::string_view base_;
  std::string joined_;
  std::vector<std::pair<std::size_t, std::size_t>> segments_;  // (offset, line)
  bool failed_ = false;          // the current statement already has its error
  std::vector<ObjCorner> face_;  // the face being read (reused)
  std::vector<Quad> quads_;
  std::vector<Forward> forward_;
};

// The whole text of a file (lines split at '\n').
ObjData parse_obj(std::string_view text);

}  // namespace snell::compile
