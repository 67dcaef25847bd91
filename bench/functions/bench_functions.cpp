// bench_functions: what §15's `pattern { function f }` costs. Each case is one
// pattern written twice: as a .scn function compiled to a shading program and run
// by the interpreter, and as C++ calling the same math (what a built-in pattern
// does). Both are called once per point through a function that is not inlined,
// as the renderer calls a pattern once per hit, on the same 4096 points, clamped
// as a pattern value is; interleaved in one run, median of repeats, 1 thread.
// The target is a ratio of at most 3.
//
//   bench_functions [--evals N] [--repeats N]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "compiler/shading_function.hpp"
#include "language/parser.hpp"
#include "runtime/ir/scalar_math.hpp"
#include "runtime/pattern/noise.hpp"
#include "runtime/pattern/program_eval.hpp"

using namespace snell;

namespace {

using Native = double (*)(ir::Vec3 p, ir::Vec3 n);

[[gnu::noinline]] double gradient(ir::Vec3 p, ir::Vec3) {
  return p.y - std::floor(p.y);
}
[[gnu::noinline]] double onion(ir::Vec3 p, ir::Vec3) {
  double l = ir::length(p);
  return l - std::floor(l);
}
[[gnu::noinline]] double fbm6(ir::Vec3 p, ir::Vec3) {
  return pattern::fbm(p * 2, 6);
}
[[gnu::noinline]] double marble(ir::Vec3 p, ir::Vec3) {
  return 0.5 + 0.5 * ir::scalar::sin_deg(p.x * 90 + pattern::turbulence(p, 4) * 360);
}
[[gnu::noinline]] double lit(ir::Vec3 p, ir::Vec3 n) {
  double s = n.y > 0 ? n.y : 0;
  return ir::scalar::mix(pattern::cells(p * 3), 1, s * s);
}
// An escape-time fractal: the .scn form is a tail recursion, run as a loop.
[[gnu::noinline]] double mandel(ir::Vec3 p, ir::Vec3) {
  double zx = 0, zy = 0, cx = p.x * 0.25, cy = p.y * 0.25;
  for (int i = 0; i < 100; ++i) {
    if (zx * zx + zy * zy > 4) return i / 100.0;
    double x = zx * zx - zy * zy + cx;
    zy = 2 * zx * zy + cy, zx = x;
  }
  return 1;
}
[[gnu::noinline]] double interpreted(const ir::Program& prog, ir::Vec3 p, ir::Vec3 n) {
  bool finite;
  double r = pattern::run_program(prog, p, n, finite);
  return pattern::pattern_value(r, finite);
}

struct Case {
  const char* name;
  const char* fn;
  Native native;
  long share;  // evaluations are --evals / share (the noise cases cost ~100 ns each)
};
const Case kCases[] = {
    {"gradient", "fn f(p) = p.y - floor(p.y);", gradient, 1},
    {"onion", "fn f(p) = length(p) - floor(length(p));", onion, 1},
    {"fbm", "fn f(p) = fbm(p * 2, 6);", fbm6, 10},
    {"marble", "fn f(p) = 0.5 + 0.5 * sin(p.x * 90 + turbulence(p, 4) * 360);", marble, 10},
    {"cells+normal",
     "fn f(p, n) { let s = if_up(n.y); return mix(cells(p * 3), 1, s * s); }\n"
     "fn if_up(y) { if y > 0 { return y; } return 0; }",
     lit, 10},
    {"mandelbrot",
     "fn esc(zx, zy, cx, cy, i) {\n"
     "  if i >= 100 { return 1; }\n"
     "  if zx * zx + zy * zy > 4 { return i / 100; }\n"
     "  return esc(zx * zx - zy * zy + cx, 2 * zx * zy + cy, cx, cy, i + 1);\n"
     "}\n"
     "fn f(p) = esc(0, 0, p.x * 0.25, p.y * 0.25, 0);",
     mandel, 20},
};

ir::Program compile_case(const Case& c) {
  lang::SourceManager sources;
  lang::DiagnosticEngine diags(sources);
  lang::FileId file = sources.add("bench.scn", c.fn);
  lang::Program program = lang::parse(sources, file, diags);
  compile::SceneBuilder builder(sources, diags);
  compile::Evaluator ev(
      sources, diags, builder,
      [](const std::string&, lang::Span) -> const compile::ImportedFile* { return nullptr; });
  std::shared_ptr<compile::Env> env = ev.run_file(program);
  ir::Program prog;
  const compile::Value* f = compile::find_value(ev, *env, "f");
  if (!f || !compile::compile_shading_function(ev, *f, {}, {}, prog)) {
    for (const lang::Diagnostic& d : diags.diagnostics())
      std::fprintf(stderr, "%s: %s\n", c.name, d.message.c_str());
    std::exit(1);
  }
  return prog;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

template <class F>
double seconds(F&& f) {
  auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  long evals = 2'000'000;
  int repeats = 5;
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string a = argv[i];
    if (a == "--evals") evals = std::max(1000L, std::atol(argv[i + 1]));
    if (a == "--repeats") repeats = std::max(1, std::atoi(argv[i + 1]));
  }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-8, 8), un(-1, 1);
  std::vector<ir::Vec3> pts(4096), nrm(4096);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    pts[i] = {u(rng), u(rng), u(rng)};
    nrm[i] = ir::normalize({un(rng), un(rng), un(rng)});
  }
  std::printf("%-13s %6s %11s %11s %7s %9s\n", "case", "instrs", "program ns", "C++ ns", "ratio",
              "max diff");
  for (const Case& c : kCases) {
    ir::Program prog = compile_case(c);
    double worst = 0;
    for (std::size_t i = 0; i < pts.size(); ++i)
      worst = std::fmax(worst, std::fabs(interpreted(prog, pts[i], nrm[i]) -
                                         pattern::pattern_value(c.native(pts[i], nrm[i]), true)));
    long n = evals / c.share;
    std::vector<double> tp, tn;
    volatile double sink = 0;
    for (int r = 0; r < repeats; ++r) {
      double s1 = 0, s2 = 0;
      tp.push_back(seconds([&] {
        for (long i = 0; i < n; ++i) s1 += interpreted(prog, pts[i & 4095], nrm[i & 4095]);
      }));
      tn.push_back(seconds([&] {
        for (long i = 0; i < n; ++i)
          s2 += pattern::pattern_value(c.native(pts[i & 4095], nrm[i & 4095]), true);
      }));
      sink = sink + s1 + s2;
    }
    double p = median(tp) / double(n) * 1e9, q = median(tn) / double(n) * 1e9;
    std::printf("%-13s %6zu %11.2f %11.2f %7.2f %9.2g\n", c.name, prog.code.size(), p, q, p / q,
                worst);
    std::fflush(stdout);
  }
  return 0;
}
