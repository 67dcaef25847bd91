// Helpers of the compiler's C++ tests: compile a scene from a string with the
// source tree's standard library, and its diagnostics as text.
#pragma once

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
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

// A number as the language reads it back exactly (17 significant digits).
inline std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// A file's bytes.
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace snell::test
