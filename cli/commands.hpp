// The subcommands that compile and render (render, check, dump-ast) and merge
// (§18), for main.cpp to dispatch to. Exit status (spec §10): 0 success; 1 errors
// in the scene (or pieces that do not belong together); 2 wrong usage; 3 a file
// could not be read or written.
#pragma once

#include <string>

#include "cli/options.hpp"
#include "compiler/compile.hpp"

namespace snell::cli {

inline constexpr int kExitOk = 0, kExitScene = 1, kExitUsage = 2, kExitIo = 3;

bool color_stderr();
int usage_error(const std::string& message);  // prints it, returns kExitUsage

// Turns the shorthand flags into settings overrides (--set first, then --spp, --res,
// --seed, which are more specific); false with `error` set on a malformed value.
bool build_compile_options(const CliArgs& o, compile::CompileOptions& c, std::string& error);

int run_render(const CliArgs& o);
int run_check(const CliArgs& o);
int dump_ast(const std::string& path);
int run_merge(const CliArgs& o);

}  // namespace snell::cli
