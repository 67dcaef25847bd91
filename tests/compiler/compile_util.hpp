// Helpers of the compiler's C++ tests: compile a scene from a string with the
// source tree's standard library, and its diagnostics as text.
#pragma once

#include <memory>
#include <string>

#include "compiler/compile.hpp"

namespace snell::test {

inline std::unique_ptr<compile::Compilation> compile_text(const std::string& src) {
  compile::CompileOptions opts;
  opts.stdlib_dir = std::string(SNELL_SOURCE_DIR) + "/stdlib";
  return compile::compile_source("test.scn", src, opts);
}

// Every message of the compilation, one a line: "Kind: message".
inline std::string messages(const compile::Compilation& c) {
  std::string s;
  for (const auto& d : c.diags.diagnostics())
    s += std::string(lang::diag_name(d.kind)) + ": " + d.message + "\n";
  return s;
}

}  // namespace snell::test
