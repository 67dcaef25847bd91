// Diagnostics: every error and warning the front end and the compiler report goes
// through one DiagnosticEngine, which collects them (all independent errors, not
// just the first) and prints them as
//   file:line:col: error: message [Kind]
//      12 |   sphere { radus 1 }
//         |            ^~~~~
//   note: did you mean 'radius'?
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "language/source.hpp"

namespace snell::lang {

enum class Severity : std::uint8_t { Error, Warning };

enum class DiagKind : std::uint16_t {
#define SNELL_DIAG(name, severity, summary) name,
#include "language/diagnostics.def"
#undef SNELL_DIAG
};

std::string_view diag_name(DiagKind kind);
std::string_view diag_summary(DiagKind kind);
Severity diag_severity(DiagKind kind);
// All kinds, in registry order (for tests that check every kind has a case).
std::vector<DiagKind> all_diag_kinds();

struct DiagNote {
  std::optional<Span> span;
  std::string message;
};

struct Diagnostic {
  DiagKind kind{};
  Severity severity = Severity::Error;
  Span span;
  std::string message;
  std::vector<DiagNote> notes;
  // The same error reported again at the same place (a loop's body, a function
  // called again; DiagnosticEngine::report says when): counted here, shown once as
  // "(and N more times)".
  std::size_t repeats = 0;
  // The message as shown: with the repeats, when there were any.
  std::string text() const {
    if (repeats == 0) return message;
    return message + " (and " + std::to_string(repeats) + " more time" + (repeats == 1 ? "" : "s") +
           ")";
  }
};

class DiagnosticEngine;

// Returned by DiagnosticEngine::report so notes can be chained:
//   diags.report(Kind::UnknownProperty, span, "...").note("did you mean 'radius'?");
class DiagBuilder {
 public:
  DiagBuilder(DiagnosticEngine* engine, std::size_t index) : engine_(engine), index_(index) {}
  DiagBuilder& note(std::string message);
  DiagBuilder& note(Span span, std::string message);

 private:
  DiagnosticEngine* engine_;
  std::size_t index_;  // SIZE_MAX when the diagnostic was dropped (over the limit)
};

class DiagnosticEngine {
 public:
  explicit DiagnosticEngine(const SourceManager& sources) : sources_(sources) {}

  DiagBuilder report(DiagKind kind, Span span, std::string message);

  std::size_t error_count() const { return errors_; }
  std::size_t warning_count() const { return warnings_; }
  bool has_errors() const { return errors_ > 0; }
  // Errors past this many are counted but not kept; 0 means no limit.
  void set_max_errors(std::size_t n) { max_errors_ = n; }
  bool limit_reached() const { return max_errors_ != 0 && errors_ >= max_errors_; }
  // The parser read no further once the limit was reached: the counts are then
  // what was found before it stopped, a lower bound.
  void stopped_reading() { stopped_ = true; }
  bool counts_are_lower_bounds() const { return stopped_; }
  // A call site that every diagnostic reported while it is set gets as a note "in
  // the call from here" (an empty span: none). The scene builder sets it while it
  // checks and places an object made inside a function call, whose errors are
  // found after the call returned. Returns the previous one, to put back.
  Span set_call_context(Span call) {
    Span old = call_context_;
    call_context_ = call;
    return old;
  }

  const std::vector<Diagnostic>& diagnostics() const { return diags_; }
  const SourceManager& sources() const { return sources_; }

  // Prints every kept diagnostic, then "N errors generated." style summary when
  // errors were dropped. `color` adds ANSI colours (for terminals).
  void print(std::ostream& out, bool color = false) const;
  // One diagnostic, formatted as above (no colour); used by tests.
  std::string format(const Diagnostic& d, bool color = false) const;

 private:
  friend class DiagBuilder;
  void snippet(std::string& out, Span span, bool color) const;

  const SourceManager& sources_;
  std::vector<Diagnostic> diags_;
  std::size_t errors_ = 0;
  std::size_t warnings_ = 0;
  std::size_t max_errors_ = 0;
  std::size_t dropped_ = 0;
  bool stopped_ = false;  // stopped_reading()
  Span call_context_{};   // set_call_context()
  // (kind, file, begin, end) of each kept diagnostic -> its index.
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> places_;
};

// Levenshtein-closest candidate for "did you mean" notes, or empty when nothing is
// close enough (distance at most max(1, len/3)).
std::string closest_match(std::string_view word, const std::vector<std::string_view>& candidates);

}  // namespace snell::lang
