// The compiler's entry point: read a scene file, parse it, run it (with its
// imports) and lower it into an ir::Scene, reporting every independent error.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "compiler/evaluator.hpp"
#include "language/ast.hpp"
#include "language/diagnostics.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::compile {

struct CompileOptions {
  std::vector<std::string> include_dirs;  // -I, searched after the importing file's folder
  // --set KEY=VALUE (and --spp/--res/--seed, turned into these): VALUE is a .scn
  // expression; for sampler and fresnel a bare word is taken as the string.
  std::vector<std::pair<std::string, std::string>> overrides;
  // How the user wrote each override, for its messages ("--res 0x24"), by its
  // index in `overrides`; missing or empty: "--set KEY=VALUE".
  std::vector<std::string> override_labels;
  std::size_t max_errors = 0;  // 0: all (§10: all independent errors)
  std::uint64_t step_budget = kDefaultStepBudget;
  std::string stdlib_dir;  // empty: $SNELL_STDLIB, else the installed/build stdlib
  // Editors (snell lsp): the text of a file the scene imports that is open and
  // perhaps unsaved, by its canonical path, or null to read the disk. Such a
  // file counts as existing even before it is first saved.
  std::function<const std::string*(const std::string& canonical_path)> overlay;
  // Editors: sees every value bound by let, fn and a call's parameters (for
  // hovers that show a name's type). Null in the CLI.
  DefineObserver on_define;
  // §18: the predeclared names' values (--clock, --frames: one compilation a frame).
  double clock = 0;
  double frame = 0;
  // §17: what the texture system finds of each image the scene names, asked once
  // it has been evaluated, beside its other errors (§10): an image it cannot read
  // becomes a FileUnreadable error at the image's `file`, a note on a readable one
  // (NaN texels mended) a MendedImage warning there. Null: images are only checked
  // for existence and signature (the runtime opens them; the compiler does not
  // load the image module).
  struct ImageVerdict {
    std::size_t image = 0;  // index in `images`
    std::string why;        // the reader's reason, or the note
    bool readable = false;  // why is a note on an image that can be read
  };
  std::function<std::vector<ImageVerdict>(const std::vector<ir::ImageFile>& images)>
      unreadable_images;
};

// The names every file sees above its top level (compile_source predeclares §18's
// from CompileOptions::clock and ::frame, and sky_gradient), with what editors show
// for them.
struct PredeclaredName {
  const char* name;
  const char* doc;
};
inline constexpr PredeclaredName kPredeclared[] = {
    {"clock",
     "predeclared number (§18): 0 by default; `--clock X` sets it, and under "
     "`--frames A..B` it is (frame - A) / (B - A)"},
    {"frame",
     "predeclared number (§18): the frame being rendered under `--frames A..B`, "
     "0 otherwise"},
    {"sky_gradient",
     "predeclared pattern (§17's `background sky_gradient`): a daylight sky over the "
     "escaping ray's direction, from a dark ground below the horizon through a pale "
     "horizon to a blue zenith (docs/language.md)"},
};
// The value of `sky_gradient` (compile.cpp).
ir::Texture sky_gradient();

// Where `import "NAME";` written in the file `from` finds its file, searched as
// the compiler does (§9: the importing file's folder, each -I folder, the standard
// library; a file never imports itself); empty when nowhere. `searched` gets the
// folders tried, `skipped_self` whether the only match was `from` itself.
std::string find_import(const std::string& name, const std::string& from,
                        const CompileOptions& options, std::vector<std::string>* searched = nullptr,
                        bool* skipped_self = nullptr);
// A path as the import cache keys it (weakly canonical).
std::string canonical_path(const std::string& path);

enum class CompileStatus {
  Ok,
  SceneErrors,  // exit 1
  UsageError,   // exit 2: a bad --set
  IoError,      // exit 3: the scene file could not be read
  FileErrors,   // exit 3: every error is a file the scene names (an import, a mesh)
                // that is missing or unreadable; the diagnostics say which
};

// Everything one compilation owns; diagnostics point into `sources`.
struct Compilation {
  lang::SourceManager sources;
  lang::DiagnosticEngine diags{sources};
  std::vector<std::unique_ptr<lang::Program>> programs;
  CompileStatus status = CompileStatus::Ok;
  std::string message;  // for UsageError / IoError
  ir::Scene scene;
};

std::unique_ptr<Compilation> compile_file(const std::string& path, const CompileOptions& options);
// The same for text already in memory; `path` names it in diagnostics and
// anchors relative imports and mesh files.
std::unique_ptr<Compilation> compile_source(const std::string& path, std::string text,
                                            const CompileOptions& options);

// Settings keys that --set accepts (for usage messages).
std::vector<std::string_view> setting_keys();

// The folder of the standard library that imports fall back to.
std::string stdlib_dir(const CompileOptions& options);

// Reads a whole file; false when it cannot be read (message set).
bool read_file(const std::string& path, std::string& text, std::string& message);
// Why `path` cannot be read as a file, in words that follow its name ("does not
// exist", "is a folder, not a file", "is a named pipe (FIFO), not a file", ...), or
// "" for a regular file. Only regular files are opened: a FIFO would block the
// compiler until something writes to it.
std::string not_a_file(const std::string& path);

// Runs `fn` on a thread with a large stack (deeply nested programs and deep
// recursion in the interpreter must never overflow the native stack).
void run_with_large_stack(const std::function<void()>& fn);

}  // namespace snell::compile
