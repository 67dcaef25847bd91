// libFuzzer target over the whole front end: lex + parse + evaluate + lower one
// random .scn text (compile::compile_source), then the IR's own checks
// (ir::validate, ir::analyze_features) on whatever scene came out.
//
// What it looks for: crashes, sanitizer reports (ASan/UBSan are linked in), hangs
// (libFuzzer's -timeout) and runaway memory (-rss_limit_mb). It does not check
// diagnostics' wording; the language tests do that.
//
// Limits that keep one input fast: a step budget of 200 000 evaluation steps (the
// default is 400 million) and at most 20 reported errors. Nesting is bounded by the
// parser (kMaxNesting) and recursion by the evaluator (10 000 calls on a 1 GiB
// stack thread), so neither needs a fuzz-specific limit.
//
// Files: the input is compiled as if it were `<nonexistent dir>/fuzz.scn`, so
// relative imports and mesh files resolve to nothing; the standard library
// (SNELL_FUZZ_STDLIB, set by CMake) is reachable, so `import "materials.scn"`
// works. Absolute paths are not blocked: an input naming a device file could read
// it. libFuzzer never builds such a path from the seed corpus in practice; if one
// shows up, it is a harness artefact, not a compiler bug.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "compiler/compile.hpp"
#include "runtime/ir/ir.hpp"

#ifndef SNELL_FUZZ_STDLIB
#define SNELL_FUZZ_STDLIB ""
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace snell;
  compile::CompileOptions options;
  options.step_budget = 200000;
  options.max_errors = 20;
  options.stdlib_dir = SNELL_FUZZ_STDLIB;
  std::string text(reinterpret_cast<const char*>(data), size);
  auto c = compile::compile_source("/nonexistent-snell-fuzz/fuzz.scn", std::move(text), options);
  // Every diagnostic must be printable (spans inside their files).
  for (const auto& d : c->diags.diagnostics()) (void)c->diags.format(d);
  if (c->status == compile::CompileStatus::Ok) {
    // A scene the compiler accepted must pass the runtime's contract checks.
    auto problems = ir::validate(c->scene);
    if (!problems.empty()) {
      std::string all;
      for (const auto& p : problems) all += ir::to_string(p, c->scene) + "\n";
      std::fprintf(stderr, "compiled scene fails ir::validate:\n%s", all.c_str());
      __builtin_trap();
    }
    (void)ir::analyze_features(c->scene);
    (void)ir::to_string(c->scene);
  }
  return 0;
}
