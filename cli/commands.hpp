// The subcommands that compile and render (render, check, dump-ast) and merge
// (§18), for main.cpp to dispatch to. Exit status (spec §10): 0 success; 1 errors
// in the scene (or pieces that do not belong together); 2 wrong usage; 3 a file
// could not be read or written.
#pragma once

#include <string>
#include <vector>

#include "cli/options.hpp"
#include "compiler/compile.hpp"

namespace snell::cli {

inline constexpr int kExitOk = 0, kExitScene = 1, kExitUsage = 2, kExitIo = 3;

bool color_stderr();
int usage_error(const std::string& message);  // prints it, returns kExitUsage

// Turns the shorthand flags into settings overrides (--set first, then --spp, --res,
// --seed, which are more specific); false with `error` set on a malformed value.
bool build_compile_options(const CliArgs& o, compile::CompileOptions& c, std::string& error);
// Warns of a settings key the command line sets twice to different values (`--spp 3
// --set samples=2`): the last one wins, which the user may not have meant.
void warn_overridden_overrides(const compile::CompileOptions& c);

// An output never replaces a file the work reads (§10: nothing is lost): the
// scene, an import, a mesh, an image, a piece being merged. The same file by any
// name counts (a symlink, a hard link, "./a/../a"). kExitUsage after printing
// why, or -1 when every output is safe.
int check_not_an_input(const std::vector<std::string>& outputs,
                       const std::vector<std::string>& inputs);
// The files a compiled scene was made from.
std::vector<std::string> scene_inputs(const ir::Scene& s);
// The closing line of a scene's diagnostics, as `snell check` prints it: "3 errors
// in scene.scn" ("at least" when the parse stopped at --max-errors; at least one).
std::string error_count_line(const lang::DiagnosticEngine& diags, const std::string& scene);
// An output that cannot be written is said before the work (exit 3, §10): its
// folder missing or not a folder, the path a folder or not a regular file.
// kExitIo after printing why, or -1.
int check_output_folder(const std::string& out);

// §17 for editors (`snell lsp`, compile::CompileOptions::unreadable_images): each
// image opened through the texture system once per version of its file (its size
// and modification time), so an analysis per keystroke does not read them again.
decltype(compile::CompileOptions::unreadable_images) cached_image_check(std::string ocio_config);

int run_render(const CliArgs& o);
int run_check(const CliArgs& o);
int dump_ast(const std::string& path);
int run_merge(const CliArgs& o);

}  // namespace snell::cli
