#include "language/diagnostics.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <ostream>
#include <utility>
#include <vector>

namespace snell::lang {
namespace {

struct KindInfo {
  std::string_view name;
  Severity severity;
  std::string_view summary;
};

constexpr KindInfo kKinds[] = {
#define SNELL_DIAG(name, severity, summary) {#name, Severity::severity, summary},
#include "language/diagnostics.def"
#undef SNELL_DIAG
};

constexpr std::size_t kDropped = std::numeric_limits<std::size_t>::max();

// The length of the UTF-8 sequence at s[i] (1..4), or 0 when the bytes there are
// not one (a stray continuation byte, an overlong form, a surrogate, past U+10FFFF,
// or cut short).
std::size_t utf8_length(std::string_view s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[i + k]); };
  const unsigned char c = b(0);
  if (c < 0x80) return 1;
  std::size_t n = c >= 0xC2 && c <= 0xDF   ? 2
                  : c >= 0xE0 && c <= 0xEF ? 3
                  : c >= 0xF0 && c <= 0xF4 ? 4
                                           : 0;
  if (n == 0 || i + n > s.size()) return 0;
  unsigned char lo = 0x80, hi = 0xBF;  // the second byte's range
  if (c == 0xE0) lo = 0xA0;
  if (c == 0xED) hi = 0x9F;
  if (c == 0xF0) lo = 0x90;
  if (c == 0xF4) hi = 0x8F;
  if (b(1) < lo || b(1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (b(k) < 0x80 || b(k) > 0xBF) return 0;
  return n;
}

// Calls f(text, is_tab) once per character of `s` as a terminal should show it:
// valid UTF-8 as it is, a byte that is not as U+FFFD, and a control character (C0
// but tab, DEL, C1) as a space, so a source line or a message that echoes one can
// neither drive the terminal nor shift the caret under it.
template <class F>
void each_visible(std::string_view s, F&& f) {
  for (std::size_t i = 0; i < s.size();) {
    std::size_t n = utf8_length(s, i);
    if (n == 0) {
      f(std::string_view("\xEF\xBF\xBD"), false);
      ++i;
      continue;
    }
    const auto c = static_cast<unsigned char>(s[i]);
    const bool c1 = n == 2 && c == 0xC2 && static_cast<unsigned char>(s[i + 1]) < 0xA0;
    if (c == '\t')
      f(std::string_view("\t"), true);
    else if ((n == 1 && (c < 0x20 || c == 0x7F)) || c1)
      f(std::string_view(" "), false);
    else
      f(s.substr(i, n), false);
    i += n;
  }
}

// The columns a character takes in a terminal: 2 for East Asian wide and
// fullwidth characters and emoji (the common blocks of Unicode's
// EastAsianWidth W and F), 1 for the rest; combining marks are not told apart.
int columns(std::string_view t) {
  if (t.size() < 3) return 1;
  const auto b = [&](std::size_t i) { return static_cast<unsigned char>(t[i]); };
  const std::uint32_t cp =
      t.size() == 3
          ? (b(0) & 0x0Fu) << 12 | (b(1) & 0x3Fu) << 6 | (b(2) & 0x3Fu)
          : (b(0) & 0x07u) << 18 | (b(1) & 0x3Fu) << 12 | (b(2) & 0x3Fu) << 6 | (b(3) & 0x3Fu);
  const bool wide = (cp >= 0x1100 && cp <= 0x115F) || (cp >= 0x2E80 && cp <= 0x303E) ||
                    (cp >= 0x3041 && cp <= 0x33FF) || (cp >= 0x3400 && cp <= 0x4DBF) ||
                    (cp >= 0x4E00 && cp <= 0x9FFF) || (cp >= 0xA000 && cp <= 0xA4CF) ||
                    (cp >= 0xAC00 && cp <= 0xD7A3) || (cp >= 0xF900 && cp <= 0xFAFF) ||
                    (cp >= 0xFE30 && cp <= 0xFE4F) || (cp >= 0xFF00 && cp <= 0xFF60) ||
                    (cp >= 0xFFE0 && cp <= 0xFFE6) || (cp >= 0x1F300 && cp <= 0x1F64F) ||
                    (cp >= 0x1F900 && cp <= 0x1F9FF) || (cp >= 0x20000 && cp <= 0x3FFFD);
  return wide ? 2 : 1;
}

std::string visible(std::string_view s) {
  std::string out;
  each_visible(s, [&](std::string_view t, bool) { out += t; });
  return out;
}

}  // namespace

std::string_view diag_name(DiagKind kind) {
  return kKinds[static_cast<int>(kind)].name;
}
std::string_view diag_summary(DiagKind kind) {
  return kKinds[static_cast<int>(kind)].summary;
}
Severity diag_severity(DiagKind kind) {
  return kKinds[static_cast<int>(kind)].severity;
}

std::vector<DiagKind> all_diag_kinds() {
  std::vector<DiagKind> out;
  for (std::size_t i = 0; i < std::size(kKinds); ++i) out.push_back(static_cast<DiagKind>(i));
  return out;
}

DiagBuilder& DiagBuilder::note(std::string message) {
  if (index_ != kDropped)
    engine_->diags_[index_].notes.push_back({std::nullopt, std::move(message)});
  return *this;
}

DiagBuilder& DiagBuilder::note(Span span, std::string message) {
  if (index_ != kDropped) engine_->diags_[index_].notes.push_back({span, std::move(message)});
  return *this;
}

DiagBuilder DiagnosticEngine::report(DiagKind kind, Span span, std::string message) {
  Severity sev = diag_severity(kind);
  // One diagnostic per kind and source place: a repeat is counted on the first.
  std::uint64_t key = (std::uint64_t(span.file) * 0x9E3779B97F4A7C15ull) ^
                      (std::uint64_t(span.begin) << 32 | span.end) ^
                      (std::uint64_t(kind) * 0xC2B2AE3D27D4EB4Full);
  // Only placed diagnostics: those without a place (command-line overrides) differ
  // by their words alone.
  std::vector<std::size_t>* bucket = span.file < sources_.size() ? &places_[key] : nullptr;
  // The same words again are a repeat; so is anything past the third different
  // message there (a loop whose message names the iteration's value). Up to three
  // stay apart: different functions failing at one call site say different things.
  if (bucket) {
    Diagnostic* first = nullptr;
    int same_place = 0;
    for (std::size_t i : *bucket) {
      Diagnostic& d = diags_[i];
      if (d.kind != kind || d.span.file != span.file || d.span.begin != span.begin ||
          d.span.end != span.end)
        continue;
      if (!first) first = &d;
      ++same_place;
      if (d.message == message) {
        ++d.repeats;
        return DiagBuilder(this, kDropped);
      }
    }
    if (first && same_place >= 3) {
      ++first->repeats;
      return DiagBuilder(this, kDropped);
    }
  }
  if (sev == Severity::Error) {
    if (limit_reached()) {
      ++dropped_;
      ++errors_;
      return DiagBuilder(this, kDropped);
    }
    ++errors_;
  } else {
    ++warnings_;
  }
  diags_.push_back({kind, sev, span, std::move(message), {}, 0});
  if (bucket) bucket->push_back(diags_.size() - 1);
  DiagBuilder d(this, diags_.size() - 1);
  if (call_context_.end > call_context_.begin) d.note(call_context_, "in the call from here");
  return d;
}

void DiagnosticEngine::snippet(std::string& out, Span span, bool color) const {
  if (span.file >= sources_.size()) return;
  const SourceFile& f = sources_.file(span.file);
  if (f.text().empty() && span.begin == 0) return;
  LineCol lc = f.line_col(span.begin);
  std::string_view line = f.line_text(lc.line);
  // Very long lines (minified or generated input) are cut around the caret.
  constexpr std::size_t kMaxShown = 200;
  std::size_t start = 0;
  std::size_t col0 = lc.col - 1;
  if (line.size() > kMaxShown && col0 > kMaxShown / 2) start = col0 - kMaxShown / 2;
  // Not from inside a character.
  while (start < col0 && start < line.size() &&
         (static_cast<unsigned char>(line[start]) & 0xC0) == 0x80)
    ++start;
  std::string_view shown = line.substr(std::min(start, line.size()), kMaxShown);
  std::string num = std::to_string(lc.line);
  std::string pad(num.size(), ' ');
  out += " " + num + " | ";
  each_visible(shown, [&](std::string_view t, bool) { out += t; });
  out += "\n " + pad + " | ";
  // The columns of each character up to the caret (col is in bytes: a wide
  // character takes two), tabs kept.
  if (start < col0 && start < line.size())
    each_visible(line.substr(start, col0 - start), [&](std::string_view t, bool tab) {
      if (tab)
        out += '\t';
      else
        out.append(std::size_t(columns(t)), ' ');
    });
  std::size_t bytes = span.end > span.begin ? span.end - span.begin : 1;
  std::size_t len = 0;
  if (col0 < line.size())
    each_visible(line.substr(col0, std::min(bytes, kMaxShown)),
                 [&](std::string_view t, bool) { len += std::size_t(columns(t)); });
  len = std::max<std::size_t>(1, std::min(len, kMaxShown));
  if (color) out += "\x1b[1;32m";
  out += '^';
  out += std::string(len - 1, '~');
  if (color) out += "\x1b[0m";
  out += '\n';
}

std::string DiagnosticEngine::format(const Diagnostic& d, bool color) const {
  std::string out;
  auto header = [&](Span span, std::string_view label, std::string_view label_color,
                    const std::string& msg) {
    if (span.file < sources_.size()) {
      if (color) out += "\x1b[1m";
      out += sources_.location(span) + ": ";
    }
    if (color) out += label_color;
    out += label;
    if (color) out += "\x1b[0m\x1b[1m";
    out += ": " + visible(msg);
    if (color) out += "\x1b[0m";
  };
  bool err = d.severity == Severity::Error;
  header(d.span, err ? "error" : "warning", err ? "\x1b[1;31m" : "\x1b[1;35m", d.text());
  out += " [" + std::string(diag_name(d.kind)) + "]\n";
  snippet(out, d.span, color);
  for (const DiagNote& n : d.notes) {
    if (n.span) {
      header(*n.span, "note", "\x1b[1;36m", n.message);
      out += '\n';
      snippet(out, *n.span, color);
    } else {
      out += color ? "\x1b[1;36mnote\x1b[0m: " : "note: ";
      out += visible(n.message) + '\n';
    }
  }
  return out;
}

void DiagnosticEngine::print(std::ostream& out, bool color) const {
  // In source order: the parser's errors are found before the evaluator's, and
  // printed as found a file read "3:1" before "1:9". Diagnostics without a place
  // (the command line's) first; files in the order they first appear.
  std::vector<std::size_t> order(diags_.size());
  std::vector<std::size_t> file_rank;
  for (std::size_t i = 0; i < diags_.size(); ++i) {
    order[i] = i;
    const Span& sp = diags_[i].span;
    if (sp.file < sources_.size()) {
      if (file_rank.size() <= sp.file) file_rank.resize(sp.file + 1, SIZE_MAX);
      if (file_rank[sp.file] == SIZE_MAX) file_rank[sp.file] = i;
    }
  }
  auto key = [&](std::size_t i) {
    const Span& sp = diags_[i].span;
    if (sp.file >= sources_.size()) return std::pair<std::size_t, std::size_t>{0, 0};
    return std::pair<std::size_t, std::size_t>{file_rank[sp.file] + 1, sp.begin};
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  for (std::size_t i : order) out << format(diags_[i], color);
  if (stopped_)
    out << "error: too many errors: reading stopped at the limit, after " << errors_
        << (dropped_ > 0 ? " (" + std::to_string(dropped_) + " not shown)" : std::string())
        << ", and more may follow; raise --max-errors to see them all [TooManyErrors]\n";
  else if (dropped_ > 0)
    out << "error: too many errors (" << errors_ << " in all, " << dropped_
        << " not shown); raise --max-errors to see more [TooManyErrors]\n";
}

std::string closest_match(std::string_view word, const std::vector<std::string_view>& candidates) {
  std::string best;
  std::size_t best_d = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> prev2, prev, cur;
  for (std::string_view c : candidates) {
    // Levenshtein distance with a swap of two neighbouring letters as one edit (the
    // optimal string alignment distance): `bmup` is one slip from `bump`, not two.
    // Candidate lists are short (property tables).
    prev2.assign(c.size() + 1, 0);
    prev.resize(c.size() + 1);
    cur.resize(c.size() + 1);
    for (std::size_t j = 0; j <= c.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= word.size(); ++i) {
      cur[0] = i;
      for (std::size_t j = 1; j <= c.size(); ++j) {
        std::size_t sub = prev[j - 1] + (word[i - 1] == c[j - 1] ? 0 : 1);
        cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
        if (i > 1 && j > 1 && word[i - 1] == c[j - 2] && word[i - 2] == c[j - 1])
          cur[j] = std::min(cur[j], prev2[j - 2] + 1);
      }
      std::swap(prev2, prev);
      std::swap(prev, cur);
    }
    std::size_t dist = prev[c.size()];
    if (dist < best_d) {
      best_d = dist;
      best = std::string(c);
    }
  }
  std::size_t allowed = std::max<std::size_t>(1, word.size() / 3);
  if (best_d == 0 || best_d > allowed) return {};
  return best;
}

}  // namespace snell::lang
