// The strict OBJ reader; the format it reads and its limits are in obj_reader.hpp.
#include "compiler/obj_reader.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace snell::compile {
namespace {

constexpr const char* kKindName[3] = {"v", "vt", "vn"};
constexpr std::size_t kMaxElements = 0xfffffffeu;  // ObjCorner::kNone stays free

// Spaces between tokens; '\r' too, so CR LF line ends need nothing else.
bool blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// The next blank-separated token of `s` (empty at the end); `s` moves past it.
std::string_view next_token(std::string_view& s) {
  std::size_t i = 0;
  while (i < s.size() && blank(s[i])) ++i;
  std::size_t j = i;
  while (j < s.size() && !blank(s[j])) ++j;
  std::string_view tok = s.substr(i, j - i);
  s.remove_prefix(j);
  return tok;
}

// A token as a message shows it: at most 40 bytes (a 7 MB token is not repeated),
// bytes outside printable ASCII as \xNN — a binary file named as a mesh must not
// put control characters on the terminal or invalid UTF-8 into the LSP's JSON.
std::string quoted(std::string_view tok) {
  constexpr std::size_t kShown = 40;
  std::string s = "'";
  for (char c : tok.substr(0, kShown)) {
    auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f) {
      s += c;
    } else {
      const char* hex = "0123456789abcdef";
      s += {'\\', 'x', hex[u >> 4], hex[u & 15]};
    }
  }
  if (tok.size() > kShown) s += "...";
  return s + "'";
}

}  // namespace

ObjData parse_obj(std::string_view text) {
  ObjParser p;
  while (!text.empty()) {
    std::size_t nl = text.find('\n');
    p.line(text.substr(0, nl));
    if (nl == std::string_view::npos) break;
    text.remove_prefix(nl + 1);
  }
  return p.finish();
}

// A physical line: the comment cut, then either a statement of its own, the
// start or middle of one continued with a trailing `\`, or the end of one.
void ObjParser::line(std::string_view text) {
  ++line_no_;
  text = text.substr(0, text.find('#'));
  std::size_t end = text.size();
  while (end > 0 && blank(text[end - 1])) --end;
  bool continued = end > 0 && text[end - 1] == '\\';
  if (continued) text = text.substr(0, end - 1);
  if (continued || !segments_.empty()) {
    segments_.push_back({joined_.size(), line_no_});
    joined_.append(text);
    joined_ += ' ';
    if (continued) return;
    statement(joined_);
    joined_.clear();
    segments_.clear();
    return;
  }
  statement(text);
}

std::pair<std::size_t, std::size_t> ObjParser::where(std::string_view at) const {
  std::size_t off = static_cast<std::size_t>(at.data() - base_.data());
  if (segments_.empty()) return {line_no_, off + 1};
  auto it = std::upper_bound(segments_.begin(), segments_.end(),
                             std::pair<std::size_t, std::size_t>{off, SIZE_MAX});
  --it;  // segments_[0] starts at offset 0
  return {it->second, off - it->first + 1};
}

void ObjParser::error(std::string_view at, std::string message) {
  if (failed_) return;  // one error per statement: its first problem
  failed_ = true;
  ++d_.error_count;
  // Keep a few more than shown: forward indices found in finish() sort before some.
  if (d_.errors.size() < kMaxObjErrors) {
    auto [line, col] = where(at);
    d_.errors.push_back({line, col, std::move(message)});
  }
}

std::size_t ObjParser::count(int kind) const {
  return kind == 0 ? d_.positions.size() : kind == 1 ? d_.texcoords.size() : d_.normals.size();
}

// statement := keyword rest ; keyword := the first token
void ObjParser::statement(std::string_view s) {
  base_ = s;
  failed_ = false;
  std::string_view rest = s;
  std::string_view key = next_token(rest);
  if (key.empty()) return;
  if (key == "v")
    vertex(key, rest, 0);
  else if (key == "vt")
    vertex(key, rest, 1);
  else if (key == "vn")
    vertex(key, rest, 2);
  else if (key == "f")
    face(rest);
  else if (key == "l" || key == "p" || key == "curv" || key == "curv2" || key == "surf") {
    if (d_.ignored_geometry++ == 0) d_.first_ignored_line = where(key).first;
  }
  // o, g, s, usemtl, mtllib, vp, cstype, ... : nothing Snell draws.
}

// v  := "v"  number{3} [number] | "v" number{6} [number]
// vt := "vt" number [number [number]]
// vn := "vn" number{3}
// One element is added even when the line is malformed, so the indices of the
// lines after it mean what their author meant (the mesh is rejected anyway).
void ObjParser::vertex(std::string_view key, std::string_view rest, int kind) {
  double x[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::size_t n = 0;
  std::string_view all = rest;
  for (std::string_view tok = next_token(rest); !tok.empty(); tok = next_token(rest)) {
    if (n == 8) {
      error(tok, std::string("too many numbers after '") + kKindName[kind] + "'");
      break;
    }
    if (!number(tok, x[n])) break;
    ++n;
  }
  std::size_t lo = kind == 1 ? 1 : 3;
  bool ok = kind == 0 ? (n == 3 || n == 4 || n == 6 || n == 7) : kind == 1 ? n <= 3 : n == 3;
  if (n < lo) {
    std::string_view at = all.substr(all.size());  // the end of the line
    error(at, std::string("'") + kKindName[kind] + "' needs " +
                  (kind == 1 ? "a u coordinate" : "3 coordinates (x y z)") + ", found " +
                  std::to_string(n));
  } else if (!ok) {
    error(key, std::string("'") + kKindName[kind] + "' takes " +
                   (kind == 0   ? "x y z [w] or x y z r g b [a]"
                    : kind == 1 ? "u [v [w]]"
                                : "x y z") +
                   ", found " + std::to_string(n) + " numbers");
  }
  if (count(kind) >= kMaxElements) {
    error(key, std::string("more than ") + std::to_string(kMaxElements) + " '" + kKindName[kind] +
                   "' lines");
    return;
  }
  ir::Vec3 value(x[0], x[1], kind == 1 ? 0.0 : x[2]);
  (kind == 0 ? d_.positions : kind == 1 ? d_.texcoords : d_.normals).push_back(value);
}

// number := [+|-] (digits [. digits*] | . digits) [(e|E) [+|-] digits]
// read as double (std::from_chars: correctly rounded), then rounded to float.
bool ObjParser::number(std::string_view tok, double& out) {
  std::string_view t = tok;
  if (t.size() > 1 && t[0] == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);
  double d = 0;
  auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), d, std::chars_format::general);
  if (ptr != t.data() + t.size() || (ec != std::errc() && ec != std::errc::result_out_of_range)) {
    error(tok, quoted(tok) + " is not a number");
    return false;
  }
  if (ec == std::errc() && !std::isfinite(d)) {  // nan, inf, infinity
    error(tok, quoted(tok) + " is not a finite number");
    return false;
  }
  if (ec == std::errc::result_out_of_range) {
    // Too large, or too small for a double: strtod says which (0 when it underflows).
    d = std::strtod(std::string(t).c_str(), nullptr);
  }
  float f = static_cast<float>(d);
  if (!std::isfinite(f)) {
    error(tok, quoted(tok) + " is beyond float range (3.4e38)");
    return false;
  }
  out = f;
  return true;
}

// index := [-] digits   (1-based; negative: back from the latest element)
bool ObjParser::index(std::string_view tok, int kind, std::uint32_t& out) {
  std::int64_t k = 0;
  auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), k);
  if (tok.empty() || ptr != tok.data() + tok.size() ||
      (ec != std::errc() && ec != std::errc::result_out_of_range)) {
    error(tok, quoted(tok) + " is not a " + kKindName[kind] + " index");
    return false;
  }
  // Messages are built only on an error: this runs three times per corner.
  std::size_t n = count(kind);
  auto fail = [&](const std::string& what) {
    error(tok, std::string(kKindName[kind]) + " index " + what + " (the file has " +
                   std::to_string(n) + " '" + kKindName[kind] + "' lines so far)");
    return false;
  };
  if (ec == std::errc::result_out_of_range)
    return fail(std::string(tok.substr(0, 40)) + " is out of range");  // digits only
  if (k == 0) {
    error(tok,
          std::string(kKindName[kind]) + " index 0: OBJ indices start at 1 (-1 is the latest)");
    return false;
  }
  if (k < 0) {
    // |k| in unsigned arithmetic: -k overflows for INT64_MIN (found by fuzz_obj).
    std::uint64_t back = 0 - static_cast<std::uint64_t>(k);
    if (back > n) return fail(std::to_string(k) + " counts back past the first one");
    out = static_cast<std::uint32_t>(n - back);
    return true;
  }
  if (static_cast<std::uint64_t>(k) > kMaxElements)
    return fail(std::to_string(k) + " is out of range");
  out = static_cast<std::uint32_t>(k - 1);
  if (static_cast<std::uint64_t>(k) > n) {
    auto [line, col] = where(tok);
    forward_.push_back({static_cast<std::uint64_t>(k), line, col, kind});
  }
  return true;
}

// corner := v | v "/" vt | v "//" vn | v "/" vt "/" vn
bool ObjParser::corner(std::string_view tok, ObjCorner& c) {
  std::string_view part[3];
  std::size_t parts = 0, start = 0;
  for (std::size_t i = 0; i <= tok.size(); ++i) {
    if (i < tok.size() && tok[i] != '/') continue;
    if (parts == 3) {
      error(tok, "corner " + quoted(tok) + " has more than v/vt/vn");
      return false;
    }
    part[parts++] = tok.substr(start, i - start);
    start = i + 1;
  }
  // "1/" and "1//" leave the last part empty: malformed, as is an empty v.
  if (part[0].empty() || (parts >= 2 && part[parts - 1].empty())) {
    error(tok, "corner " + quoted(tok) + " is not v, v/vt, v//vn or v/vt/vn");
    return false;
  }
  if (!index(part[0], 0, c.v)) return false;
  if (parts >= 2 && !part[1].empty() && !index(part[1], 1, c.vt)) return false;
  if (parts == 3 && !index(part[2], 2, c.vn)) return false;
  return true;
}

// f := "f" corner corner corner corner*
void ObjParser::face(std::string_view rest) {
  face_.clear();
  std::string_view all = rest;
  std::size_t forward = forward_.size();  // a dropped face's later checks go too
  for (std::string_view tok = next_token(rest); !tok.empty(); tok = next_token(rest)) {
    ObjCorner c;
    if (!corner(tok, c)) {
      forward_.resize(forward);
      return;
    }
    face_.push_back(c);
  }
  if (face_.size() < 3) {
    forward_.resize(forward);
    error(all.substr(all.size()),
          "a face needs at least 3 corners, this one has " + std::to_string(face_.size()));
    return;
  }
  std::size_t n = face_.size();
  auto& out = d_.corners;
  if (n == 3) {
    out.insert(out.end(), face_.begin(), face_.end());
  } else if (n == 4) {
    std::size_t slot = out.size();
    out.resize(slot + 6);
    bool known = true;
    for (const ObjCorner& c : face_) known &= c.v < d_.positions.size();
    if (known)
      split_quad(face_.data(), slot);
    else
      quads_.push_back({slot, {face_[0], face_[1], face_[2], face_[3]}});
  } else {
    out.reserve(out.size() + 3 * (n - 2));
    for (std::size_t k = 1; k + 1 < n; ++k)
      out.insert(out.end(), {face_[0], face_[k], face_[k + 1]});
  }
}

// tinyobjloader 2.0's quad rule (see the header), in float as it computed it.
void ObjParser::split_quad(const ObjCorner* c, std::size_t slot) {
  auto p = [&](int i) {
    const ir::Vec3& v = d_.positions[c[i].v];
    return std::array<float, 3>{float(v.x), float(v.y), float(v.z)};
  };
  auto sqr = [](std::array<float, 3> a, std::array<float, 3> b) {
    float x = b[0] - a[0], y = b[1] - a[1], z = b[2] - a[2];
    return x * x + y * y + z * z;
  };
  const int k02[6] = {0, 1, 2, 0, 2, 3}, k13[6] = {0, 1, 3, 1, 2, 3};
  const int* k = sqr(p(0), p(2)) < sqr(p(1), p(3)) ? k02 : k13;
  for (int i = 0; i < 6; ++i) d_.corners[slot + i] = c[k[i]];
}

ObjData ObjParser::finish() {
  if (!segments_.empty()) {  // the file ended on a `\`
    statement(joined_);
    joined_.clear();
    segments_.clear();
  }
  std::vector<ObjError> late;
  std::size_t last_line = 0;
  for (const Forward& f : forward_) {
    std::size_t n = count(f.kind);
    if (f.index <= n || f.line == last_line) continue;  // one error per statement
    last_line = f.line;
    ++d_.error_count;
    if (late.size() < kMaxObjErrors)
      late.push_back({f.line, f.col,
                      std::string(kKindName[f.kind]) + " index " + std::to_string(f.index) +
                          " is out of range (the file has " + std::to_string(n) + " '" +
                          kKindName[f.kind] + "' lines)"});
  }
  d_.errors.insert(d_.errors.end(), late.begin(), late.end());
  std::stable_sort(d_.errors.begin(), d_.errors.end(), [](const ObjError& a, const ObjError& b) {
    return a.line != b.line ? a.line < b.line : a.col < b.col;
  });
  if (d_.errors.size() > kMaxObjErrors) d_.errors.resize(kMaxObjErrors);
  if (d_.error_count == 0)
    for (const Quad& q : quads_) split_quad(q.c, q.slot);
  return std::move(d_);
}

}  // namespace snell::compile
