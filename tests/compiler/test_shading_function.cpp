// §15 shading functions: the compiled program against the evaluator calling the
// same function at compile time, folding and dead-code removal, the errors with
// their places, the limits, and the op registry's agreement with the compiler,
// the interpreter and the dump.
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <set>

#include "compiler/builtins.hpp"
#include "compiler/compile.hpp"
#include "compiler/evaluator.hpp"
#include "compiler/shading_function.hpp"
#include "language/parser.hpp"
#include "runtime/pattern/noise.hpp"
#include "runtime/pattern/program_eval.hpp"
#include "runtime/shading/textures.hpp"
#include "tests/compiler/compile_util.hpp"

using namespace snell;

namespace {

// A program run by the evaluator (no imports, no scene kept), whose functions can
// then be compiled to shading programs.
struct Harness {
  lang::SourceManager sources;
  lang::DiagnosticEngine diags{sources};
  std::unique_ptr<lang::Program> program;
  std::unique_ptr<compile::SceneBuilder> builder;
  std::unique_ptr<compile::Evaluator> ev;
  std::shared_ptr<compile::Env> env;
  lang::FileId file = 0;
  std::string text;

  explicit Harness(std::string src) : text(std::move(src)) {
    diags.set_max_errors(0);
    file = sources.add("test.scn", text);
    program = std::make_unique<lang::Program>(lang::parse(sources, file, diags));
    builder = std::make_unique<compile::SceneBuilder>(sources, diags);
    ev = std::make_unique<compile::Evaluator>(
        sources, diags, *builder,
        [](const std::string&, lang::Span) -> const compile::ImportedFile* { return nullptr; });
    env = ev->run_file(*program);
  }
  // The place of the first `marker` in the text, as a span.
  lang::Span at(const std::string& marker) const {
    auto pos = static_cast<std::uint32_t>(text.find(marker));
    return {file, pos, pos + static_cast<std::uint32_t>(marker.size())};
  }
  const compile::Value& value(const std::string& name) {
    const compile::Value* v = compile::find_value(*ev, *env, name);
    REQUIRE(v);
    return *v;
  }
  bool compile(const std::string& fn, ir::Program& out) {
    lang::Span use = text.find("USE") != std::string::npos ? at("USE") : lang::Span{file, 0, 0};
    return compile::compile_shading_function(*ev, value(fn), use, use, out);
  }
  // "Kind line:col" of every diagnostic, with "note line:col" for notes with places.
  std::string report() const {
    std::string s;
    for (const lang::Diagnostic& d : diags.diagnostics()) {
      auto lc = sources.file(d.span.file).line_col(d.span.begin);
      s += std::string(lang::diag_name(d.kind)) + " " + std::to_string(lc.line) + ":" +
           std::to_string(lc.col);
      for (const lang::DiagNote& n : d.notes)
        if (n.span) {
          auto nl = sources.file(n.span->file).line_col(n.span->begin);
          s += " note " + std::to_string(nl.line) + ":" + std::to_string(nl.col);
        }
      s += "\n";
    }
    return s;
  }
};

using test::num;
std::string vec(ir::Vec3 v) {
  return "<" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ">";
}

struct Sample {
  ir::Vec3 p, n;
};
std::vector<Sample> samples(int count, double extent, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-extent, extent), un(-1, 1);
  std::vector<Sample> s;
  for (int i = 0; i < count; ++i)
    s.push_back({{u(rng), u(rng), u(rng)}, {un(rng), un(rng), un(rng)}});
  return s;
}

// Compiles `fname` from `defs` and checks that the program gives, at every sample,
// the very bits the evaluator computes for `fname(p)` (or `fname(p, n)`).
void same_as_evaluator(const std::string& defs, const std::string& fname, bool with_normal,
                       double extent = 4) {
  std::vector<Sample> pts = samples(150, extent, std::hash<std::string>{}(fname));
  std::string src = defs + "\n";
  for (std::size_t i = 0; i < pts.size(); ++i)
    src += "let r_" + std::to_string(i) + " = " + fname + "(" + vec(pts[i].p) +
           (with_normal ? ", " + vec(pts[i].n) : "") + ");\n";
  Harness h(src);
  INFO(h.report());
  REQUIRE(h.diags.diagnostics().empty());
  ir::Program prog;
  REQUIRE(h.compile(fname, prog));
  INFO(ir::to_string(prog));
  REQUIRE(ir::check(prog).empty());
  CHECK(prog.reads_normal == with_normal);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const compile::Value& want = h.value("r_" + std::to_string(i));
    REQUIRE(want.type == compile::Type::Number);
    bool finite = false;
    double got = pattern::run_program(prog, pts[i].p, pts[i].n, finite);
    INFO("at " << vec(pts[i].p) << " n " << vec(pts[i].n));
    CHECK(finite);
    CHECK(num(got) == num(want.n));  // bit for bit: the same functions compute both
  }
}

}  // namespace

TEST_CASE("shading: builtins noise, fbm, turbulence, cells equal snell::pattern", "[shading]") {
  Harness h(R"(
let a = noise(<1, 2, 3>);
let b = fbm(<0.3, 1.7, -2.2>, 6);
let c = turbulence(<0.3, 1.7, -2.2>, 3);
let d = cells(<0.3, 1.7, -2.2>);
let e = fbm(<5.5, 0.25, 9>, 32);
)");
  INFO(h.report());
  REQUIRE(h.diags.diagnostics().empty());
  CHECK(h.value("a").n == 0.5);  // a lattice point
  ir::Vec3 q{0.3, 1.7, -2.2};
  CHECK(h.value("b").n == pattern::fbm(q, 6));
  CHECK(h.value("c").n == pattern::turbulence(q, 3));
  CHECK(h.value("d").n == pattern::cells(q));
  CHECK(h.value("e").n == pattern::fbm({5.5, 0.25, 9}, 32));
}

TEST_CASE("shading: noise builtins reject bad arguments", "[shading]") {
  Harness h(R"(
let a = noise(1);
let b = noise(<1, 2>);
let c = fbm(<1, 2, 3>, 2.5);
let d = fbm(<1, 2, 3>, 0);
let e = turbulence(<1, 2, 3>, 33);
let f = cells(true);
)");
  CHECK(h.report() ==
        "TypeMismatch 2:15\nTypeMismatch 3:15\nNotAnInteger 4:24\nInvalidValue 5:24\n"
        "InvalidValue 6:31\nTypeMismatch 7:15\n");
}

TEST_CASE("shading: every op matches the evaluator bit for bit", "[shading]") {
  same_as_evaluator("fn f(p) = p.y - floor(p.y);", "f", false);
  same_as_evaluator("fn f(p) = (p.x + p.y * 2 - p.z / 3) % 1.5 + -p.x;", "f", false);
  same_as_evaluator(
      "fn f(p) = length((p + <1, 2, 3>) * p.x - p / 4 % <1, 2, 3> + -p) + "
      "dot(p * 2, 1 - p);",
      "f", false);
  same_as_evaluator(R"(fn f(p) {
    if p.x < 0 && p.y >= 1 || !(p.z > 2) { return 1; }
    else if p.x <= p.y { return 2; }
    else if p.x == p.z || p.y != 3 { return 3; }
    return 4;
  })",
                    "f", false);
  same_as_evaluator(R"(fn f(p) {
    if p == <1, 2, 3> || <p.x, p.y> != <0, 0> && (p.x > 0) == (p.y > 0) { return p.x; }
    return p.y;
  })",
                    "f", false);
  same_as_evaluator(
      "fn f(p) = sin(p.x * 30) + cos(p.y * 45) + tan(p.z * 10) + "
      "asin(clamp(p.x / 4, -1, 1)) + acos(clamp(p.y / 4, -1, 1)) + atan(p.z) + "
      "atan2(p.y, p.x) + sin(90) + cos(p.x * 0 + 90);",
      "f", false);
  same_as_evaluator(
      "fn f(p) = sqrt(abs(p.x)) + pow(abs(p.y), 1.5) + exp(p.z / 10) + "
      "log(abs(p.x) + 1) + ceil(p.y) + round(p.z) + min(p.x, p.y) + "
      "max(p.y, p.z) + mix(p.x, p.y, p.z) + clamp(p.x, p.y, p.z + 10);",
      "f", false);
  same_as_evaluator(R"(fn f(p) {
    let a = sin(p * 10) + cos(p) + tan(p) + asin(clamp(p / 4, -1, 1)) + acos(clamp(p / 4, -1, 1));
    let b = atan(p) + atan2(p, <1, -2, 3>) + sqrt(abs(p)) + pow(abs(p), 0.5) + exp(p / 8);
    let c = log(abs(p) + 1) + abs(p) + floor(p) + ceil(p) + round(p) + min(p, 0) + max(p, 1);
    let d = clamp(p, -1, 1) + mix(p, <1, 2, 3>, 0.25) + mix(p, -p, p.x);
    let e = sin(<p.x, p.y>) + <1, 2> * p.z;
    return dot(a + b + c + d, <1, 1, 1>) + dot(e, <1, 0.5>) + length(e);
  })",
                    "f", false);
  same_as_evaluator(
      "fn f(p, n) = dot(cross(p, n), normalize(p + <0.1, 0.2, 0.3>)) + "
      "length(<p.x, p.y>) + dot(<p.x, p.z>, <1, 2>) + normalize(<p.x, 1>).x + "
      "normalize(<p.x, 1>).y;",
      "f", true);
  same_as_evaluator("fn f(p) = random(floor(p.x * 10)) + random(p.y);", "f", false);
  same_as_evaluator(
      "fn f(p) = noise(p) + fbm(p * 2, 6) + turbulence(p, 3) + cells(p) + "
      "fbm(p, 1 + floor(abs(p.x)) % 5) + turbulence(p, 1 + floor(abs(p.y)));",
      "f", false);
  same_as_evaluator("fn f(p) = 0.5 + 0.5 * sin(p.x * 90 + turbulence(p, 4) * 360);", "f", false);
}

TEST_CASE("shading: let, return, captured constants, inlined and local functions, loops",
          "[shading]") {
  std::string lib = R"(
let k = 3;
let off = <1, 2, 3>;
let flag = true;
fn helper(q, s) = dot(q, off) * s;
fn fact(n) { if n <= 1 { return 1; } return n * fact(n - 1); }
)";
  same_as_evaluator(lib + R"(fn f(p) {
    let a = helper(p, k);
    fn inner(x) = x * a + k;
    if flag { return inner(2) + helper(p, 1) + fact(5); }
    return 0;
  })",
                    "f", false);
  same_as_evaluator(lib + R"(fn f(p) {
    for i in 0 .. 5 { if p.x < i - 2 { return i; } }
    for j in 3 .. 0 step -1.5 { if p.y > j { return j * 10; } }
    return 5;
  })",
                    "f", false);
  same_as_evaluator(lib + R"(fn g(p) { if p.x > 0 { return p; } return -p; }
    fn f(p) { let q = g(p); if q.y > 1 { let r = q.y * 2; return r; } else { return q.z; } })",
                    "f", false);
  same_as_evaluator(lib +
                        "fn f(p, n) = if_less(p.x, n.y);\n"
                        "fn if_less(a, b) { if a < b { return 1; } return 0; }",
                    "f", true);
}

TEST_CASE("shading: constant folding, dead code, shared subexpressions, inputs read", "[shading]") {
  Harness h(R"(
let two = 2;
fn dead(p) { let unused = sin(p.x) * 100; let k = two * 3 + sqrt(16); return p.y * k + (1 + 2); }
fn twice(p) = sin(p.x) + sin(p.x);
fn konst(p) = 0.25 + two;
fn normal(p, n) = n.y;
fn ignores(p, n) = p.x;
fn folded_if(p) { if two > 1 { return p.x; } else { return sin(p.y); } }
fn call_fold(p) = p.x * fact(4);
fn fact(n) { if n <= 1 { return 1; } return n * fact(n - 1); }
)");
  REQUIRE(h.diags.diagnostics().empty());
  ir::Program p;
  REQUIRE(h.compile("dead", p));
  INFO(ir::to_string(p));
  CHECK(p.code.size() == 2);  // mul, add: the dead let and the constants are gone
  CHECK(p.constants == std::vector<double>{10, 3});
  REQUIRE(h.compile("twice", p));
  CHECK(p.code.size() == 2);  // sin once
  REQUIRE(h.compile("konst", p));
  CHECK(p.code.empty());
  CHECK(!p.reads_point);
  CHECK(p.constants == std::vector<double>{2.25});
  bool finite = false;
  CHECK(pattern::run_program(p, {}, {}, finite) == 2.25);
  REQUIRE(h.compile("normal", p));
  CHECK(p.code.empty());
  CHECK(p.reads_normal);
  CHECK(!p.reads_point);
  CHECK(p.result == ir::kNormalSlot + 1);
  REQUIRE(h.compile("ignores", p));
  CHECK(!p.reads_normal);
  REQUIRE(h.compile("folded_if", p));
  CHECK(p.code.empty());
  CHECK(p.result == ir::kPointSlot);
  REQUIRE(h.compile("call_fold", p));
  CHECK(p.code.size() == 1);
  CHECK(p.constants == std::vector<double>{24});
  // Equal programs compare equal (materials are deduplicated by value).
  ir::Program q;
  REQUIRE(h.compile("dead", p));
  REQUIRE(h.compile("dead", q));
  CHECK(p == q);
  CHECK(ir::to_string(p) ==
        "program: 2 instructions, 2 constants, 10 slots, reads p; result r9\n"
        "  r6 = 10\n  r7 = 3\n  r8 = mul p.y r6\n  r9 = add r8 r7\n");
}

TEST_CASE("shading: impure functions are errors at the item, with a note at the use", "[shading]") {
  Harness h(R"(
fn maker(x) { sphere { center <x, 0, 0> radius 1 } return x; }
fn f(p) { let a = maker(p.x); return a; }
fn g(p) { box { min <0, 0, 0> max <1, 1, 1> } return 1; }
fn h(p) { background <1, 1, 1> return 1; }
fn o(p) { let s = sphere { radius 1 }; return 1; }
// USE
)");
  REQUIRE(h.diags.diagnostics().empty());
  ir::Program p;
  CHECK(!h.compile("f", p));
  CHECK(!h.compile("g", p));
  CHECK(!h.compile("h", p));
  CHECK(!h.compile("o", p));
  // maker's sphere (notes: the call in f, the use); g's box; h's background; o's object.
  CHECK(h.report() ==
        "ImpureShadingFunction 2:15 note 3:19 note 7:4\n"
        "ImpureShadingFunction 4:11 note 7:4\n"
        "ImpureShadingFunction 5:11 note 7:4\n"
        "ImpureShadingFunction 6:19 note 7:4\n");
}

TEST_CASE("shading: recursion on run-time values is unrolled while it ends on constants",
          "[shading]") {
  // Not a tail call (a product of the levels), so not a loop: x is a run-time
  // value and n a constant, so the recursion unrolls 12 levels, each with a
  // run-time return selected. Bit for bit the evaluator's value.
  same_as_evaluator(R"(
fn damped(x, n) {
  if n <= 0 { return 1; }
  if abs(x) > 3 { return n / 12; }
  return (1 - 0.01 * n) * damped(x * x - 0.5, n - 1);
}
fn f(p) = damped(p.x, 12);)",
                    "f", false, 1.5);
  ir::Program p;
  {
    Harness u(
        "fn damped(x, n) { if n <= 0 { return 1; } return 0.5 * damped(x * x, n - 1); }\n"
        "fn f(p) = damped(p.x, 12);\n");
    REQUIRE(u.compile("f", p));
    CHECK(p.loops.empty());  // unrolled, not a loop
  }
  // Two recursions in one function, one of them through a helper.
  same_as_evaluator(R"(
fn sum_to(x, n) { if n == 0 { return 0; } return x * n + sum_to(x, n - 1); }
fn twice(p, n) = sum_to(p.y, n) - sum_to(p.z, n);
fn f(p) = twice(p, 12) + sum_to(p.x, 7);)",
                    "f", false);
  // One that is not a tail call and never ends on constants is an error at the
  // call, saying why.
  Harness h(R"(
fn halvings(x) { if x < 1 { return 0; } return 1 + halvings(x / 2); }
fn g(p) = halvings(p.x);
// USE
)");
  CHECK(!h.compile("g", p));
  CHECK(h.report() == "UnsupportedInShadingFunction 2:52 note 3:11 note 4:4\n");
  REQUIRE(!h.diags.diagnostics().empty());
  CHECK_THAT(h.diags.diagnostics()[0].message,
             Catch::Contains("'halvings' calls itself more than 256 deep") &&
                 Catch::Contains("must end on constants"));
}

TEST_CASE("shading: a tail recursion on run-time values runs as a loop", "[shading]") {
  // `return f(...)` as the only self-call: the body is a loop of its own, run until
  // it returns, with every value bit for bit the evaluator's. 500 iterations of an
  // escape-time fractal (far past what unrolling fits), a recursion that ends only
  // on run-time values, a loop of vectors and bools, and loops nested in loops.
  same_as_evaluator(R"(
fn escape(z, c, i) {
  if i >= 500 { return 1; }
  if dot(z, z) > 4 { return i / 500; }
  return escape(<z.x * z.x - z.y * z.y + c.x, 2 * z.x * z.y + c.y>, c, i + 1);
}
fn mandel(p) = escape(<0, 0>, <p.x - 0.5, p.y>, 0);)",
                    "mandel", false, 1.5);
  same_as_evaluator(R"(
fn halve(x) { if x < 1 { return x; } return halve(x / 2); }
fn f(p) = halve(abs(p.x) * 1000) + halve(abs(p.y) * 7);)",
                    "f", false);
  // The inputs take their next values all at once: b's old value becomes a.
  same_as_evaluator(R"(
fn swap(a, b, n) { if n <= 0 { return a + 0.25 * b; } return swap(b, a, n - 1); }
fn f(p) = swap(p.x, p.y, floor(abs(p.z) * 3));)",
                    "f", false);
  same_as_evaluator(R"(
fn walk(q, up, n) {
  if n <= 0 { return q; }
  if up && q.y > 2 { return walk(q * 0.5, false, n - 1); }
  return walk(q + <0.3, 0.7, -0.2>, !up || q.x > 1, n - 1);
}
fn f(p, nrm) = length(walk(p, nrm.x > 0, floor(abs(p.z) * 10))) / 20;)",
                    "f", true);
  same_as_evaluator(R"(
fn inner(x, n) { if n <= 0 { return x; } return inner(x * 0.5 + 0.1, n - 1); }
fn outer(x, k) { if k <= 0 { return x; } return outer(inner(x, floor(abs(x)) + k), k - 1); }
fn f(p) = outer(p.x, 3 + floor(abs(p.y))) + outer(p.z, 2);)",
                    "f", false);
  // The program: one loop instruction, its body apart.
  Harness h(R"(
fn halve(x) { if x < 1 { return x; } return halve(x / 2); }
fn f(p) = halve(p.x);
fn spin(x) { if x != x { return 0; } return spin(x + 1); }
fn g(p) = spin(p.x);
)");
  ir::Program p;
  REQUIRE(h.compile("f", p));
  REQUIRE(p.loops.size() == 1);
  CHECK(ir::to_string(p).find("= loop L0") != std::string::npos);
  bool finite = false;
  CHECK(pattern::run_program(p, {1000, 0, 0}, {}, finite) == 1000 / 1024.0);
  CHECK(finite);
  // A loop that never returns stops at §4's call depth with NaN (the evaluator
  // stops the same call with RecursionLimit).
  REQUIRE(h.compile("g", p));
  pattern::run_program(p, {0, 0, 0}, {}, finite);
  CHECK(!finite);
  // Loops in loops share one budget of work per evaluation (ir::kMaxWork, 2^20
  // instructions): 1000 outer runs of 1000 inner ones are too many (the inner
  // loops' bounds would multiply), 300 of 200 are not.
  Harness n(R"(
fn inner(x, k) { if k <= 0 { return x; } return inner(x + 1, k - 1); }
fn outer(x, k, m) { if k <= 0 { return x; } return outer(inner(x, m), k - 1, m); }
fn big(p) = outer(p.x, 1000, 1000);
fn small(p) = outer(p.x, 300, 200);
)");
  REQUIRE(n.compile("big", p));
  pattern::run_program(p, {0, 0, 0}, {}, finite);
  CHECK(!finite);
  REQUIRE(n.compile("small", p));
  CHECK(pattern::run_program(p, {0, 0, 0}, {}, finite) == 300 * 200);
  CHECK(finite);
}

// §4's 10 000 calls, counted as the evaluator counts them: the shading function's
// own call is one, so a loop of 9 999 runs under it is the deepest that has a
// value; one run more is NaN at render time where the evaluator stops with
// RecursionLimit (the loop allowed 10 000 runs whatever called it).
TEST_CASE("shading: a loop's depth limit is the evaluator's, call for call", "[shading]") {
  for (int n : {9998, 9999}) {
    INFO("runs " << n + 1);
    const std::string defs = "fn cnt(x, i) { if i >= " + std::to_string(n) +
                             " { return x; } return cnt(x + 1, i + 1); }\n"
                             "fn f(p) = cnt(p.x * 0, 0);\n";
    Harness h(defs);
    ir::Program p;
    REQUIRE(h.compile("f", p));
    bool finite = false;
    const double v = pattern::run_program(p, {0, 0, 0}, {}, finite);
    bool limit = false;
    // 10 000 calls deep: on the stack the compiler runs on (the sanitizers' frames
    // are large).
    compile::run_with_large_stack([&] {
      Harness eval(defs + "let v = f(<0, 0, 0>);\n");
      for (const auto& d : eval.diags.diagnostics())
        limit = limit || d.kind == lang::DiagKind::RecursionLimit;
    });
    CHECK(finite == !limit);
    CHECK(finite == (n == 9998));
    if (finite) CHECK(v == n);
  }
  // Helpers between the shading function and the loop count too.
  Harness h(R"(
fn cnt(x, i) { if i >= 9997 { return x; } return cnt(x + 1, i + 1); }
fn mid(x) = cnt(x, 0);
fn f(p) = mid(p.x * 0);
fn g(p) = cnt(p.x * 0, 0);
)");
  ir::Program p;
  bool finite = true;
  REQUIRE(h.compile("f", p));  // f, mid and 9 998 runs: 10 000 calls
  CHECK(pattern::run_program(p, {0, 0, 0}, {}, finite) == 9997);
  CHECK(finite);
  Harness deeper(R"(
fn cnt(x, i) { if i >= 9998 { return x; } return cnt(x + 1, i + 1); }
fn mid(x) = cnt(x, 0);
fn f(p) = mid(p.x * 0);
)");
  REQUIRE(deeper.compile("f", p));  // 10 001 calls
  pattern::run_program(p, {0, 0, 0}, {}, finite);
  CHECK(!finite);
}

// A hostile function (32-octave fbm calls in loops in loops) ran for seconds at one
// hit under a bound on loop runs alone; the work budget ends it within ~2^20
// instructions' worth (a noise octave counting 16).
TEST_CASE("shading: a function's work at one point is bounded", "[shading]") {
  Harness h(R"(
fn heavy(q) = fbm(q, 32) + fbm(q * 1.1, 32) + fbm(q * 1.2, 32) + fbm(q * 1.3, 32);
fn inner(q, s, j) { if j >= 1000 { return s; } return inner(q + <0.01, 0, 0>, s + heavy(q), j + 1); }
fn outer(q, s, i) { if i >= 1000 { return s; } return outer(q, inner(q + <0, i, 0>, s, 0), i + 1); }
fn f(p) = outer(p, 0, 0);
)");
  ir::Program p;
  REQUIRE(h.compile("f", p));
  bool finite = true;
  const auto t0 = std::chrono::steady_clock::now();
  pattern::run_program(p, {0.5, 0.25, 0}, {}, finite);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(!finite);
  // 2^20 / (4 · 32 · 16) ≈ 512 runs of fbm calls: milliseconds, where it was
  // seconds (a bound loose enough for a loaded machine and the sanitizers).
  CHECK(seconds < 1.0);
}

TEST_CASE("shading: a loop's limits are errors with places", "[shading]") {
  Harness h(R"(
fn t(x) { if x.x > 0 { return 1; } return t(1); }
fn a(p) = t(p);
fn forever(x) { return forever(x + 1); }
fn b(p) = forever(p.x);
fn h2(x) = hop(x);
fn hop(x) { if x < 1 { return x; } return hop(h2(x / 2)); }
fn twice(x) { if x > 1 { return x; } return twice(x, 2); }
fn d(p) = twice(p.x);
fn c(p) = hop(p.x);
// USE
)");
  ir::Program p;
  for (const char* f : {"a", "b", "c", "d"}) CHECK(!h.compile(f, p));
  CHECK(h.report() ==
        // t's parameter changes type; forever never returns; hop calls itself
        // through h2, not as its return; twice passes two arguments for one.
        "UnsupportedInShadingFunction 2:45 note 3:11 note 11:4\n"
        "UnsupportedInShadingFunction 4:4 note 5:11 note 11:4\n"
        "UnsupportedInShadingFunction 6:12 note 7:47 note 10:11 note 11:4\n"
        "WrongArgumentCount 8:45 note 8:4 note 9:11 note 11:4\n");
}

TEST_CASE("shading: unsupported constructs and bad functions are errors with places", "[shading]") {
  Harness h(R"(
let name = "x";
let m = diffuse <1, 1, 1>;
fn s(p) { let t = "text"; return 1; }
fn cap(p) { let t = name; return 1; }
fn mat(p) { let q = diffuse <1, 0, 0>; return 1; }
fn usem(p) { let q = m; return 1; }
fn loop(p) { for i in 0 .. p.x { if p.y > i { return 1; } } return 0; }
fn rec(p) { if p.x > 1 { return rec(p - 1); } return 0; }  // a loop: fine
fn vecres(p) = p;
fn three(a, b, c) = 1;
fn mixed(p) { if p.x > 0 { return 1; } return p; }
fn partial(p) { if p.x > 0 { return 1; } }
fn none(p) { let a = 1; }
fn typed(p) = p + <1, 2>;
fn cond(p) { if p.x { return 1; } return 0; }
// USE
)");
  REQUIRE(h.diags.diagnostics().empty());
  ir::Program p;
  CHECK(h.compile("rec", p));
  for (const char* f : {"s", "cap", "mat", "usem", "loop", "vecres", "three", "mixed", "partial",
                        "none", "typed", "cond"})
    CHECK(!h.compile(f, p));
  CHECK(h.report() ==
        "UnsupportedInShadingFunction 4:19 note 17:4\n"
        "UnsupportedInShadingFunction 5:21 note 17:4\n"
        "UnsupportedInShadingFunction 6:21 note 17:4\n"
        "UnsupportedInShadingFunction 7:22 note 17:4\n"
        "UnsupportedInShadingFunction 8:28 note 17:4\n"
        "InvalidValue 17:4 note 10:4 note 17:4\n"
        "InvalidValue 17:4 note 11:4 note 17:4\n"
        "UnsupportedInShadingFunction 12:40 note 17:4\n"
        "UnsupportedInShadingFunction 13:4 note 17:4\n"
        "MissingReturn 14:4 note 17:4\n"
        "TypeMismatch 15:15 note 15:15 note 15:19 note 17:4\n"
        "TypeMismatch 16:17 note 17:4\n");
}

TEST_CASE("shading: the program's limits are errors, not overflows", "[shading]") {
  // 400 distinct live vector values need more slots than the register file has.
  std::string body = "fn big(p) = 0";
  for (int i = 0; i < 400; ++i) body += " + length(p * " + std::to_string(i + 2) + ")";
  body += ";\n";
  std::string loop = "fn long(p) { for i in 0 .. 5000 { if p.x > i { return i; } } return 0; }\n";
  std::string rec =
      "fn r(n) { if n <= 0 { return 0; } return 1 + r(n - 1); }\n"
      "fn deep(p) = p.x * r(1000);\n";
  Harness h(body + loop + rec + "// USE\n");
  REQUIRE(h.diags.diagnostics().empty());
  ir::Program p;
  CHECK(!h.compile("big", p));
  CHECK(!h.compile("long", p));
  CHECK(!h.compile("deep", p));
  CHECK(h.report() ==
        "UnsupportedInShadingFunction 1:4 note 5:4\n"
        "UnsupportedInShadingFunction 2:14 note 5:4\n"
        // r(1000) inlined 256 deep: one note for the recursive calls, one for deep's.
        "UnsupportedInShadingFunction 3:46 note 4:20 note 5:4\n");
  // A function within the limits compiles to a program that passes the check.
  std::string ok = "fn fine(p) = 0";
  for (int i = 0; i < 60; ++i) ok += " + length(p * " + std::to_string(i + 2) + ")";
  Harness g(ok + ";\n");
  REQUIRE(g.compile("fine", p));
  CHECK(ir::check(p).empty());
  CHECK(p.code.size() <= static_cast<std::size_t>(ir::kMaxCode));
}

TEST_CASE("shading: a non-finite result is reported to the caller", "[shading]") {
  Harness h(R"(
fn inv(p) = 1 / p.x;
fn root(p) = sqrt(p.x);
fn oct(p) = fbm(p, p.x);
)");
  ir::Program p;
  bool finite = true;
  REQUIRE(h.compile("inv", p));
  CHECK(pattern::run_program(p, {0, 0, 0}, {}, finite) == std::numeric_limits<double>::infinity());
  CHECK(!finite);
  CHECK(pattern::pattern_value(1 / 0.0, finite) == 0);
  CHECK(pattern::run_program(p, {4, 0, 0}, {}, finite) == 0.25);
  CHECK(finite);
  CHECK(pattern::pattern_value(0.25, finite) == 0.25);
  CHECK(pattern::pattern_value(7, true) == 1);
  CHECK(pattern::pattern_value(-7, true) == 0);
  REQUIRE(h.compile("root", p));
  pattern::run_program(p, {-1, 0, 0}, {}, finite);
  CHECK(!finite);
  REQUIRE(h.compile("oct", p));
  pattern::run_program(p, {2.5, 0, 0}, {}, finite);  // 2.5 octaves: NaN, as no error can be given
  CHECK(!finite);
  pattern::run_program(p, {2, 0, 0}, {}, finite);
  CHECK(finite);
}

TEST_CASE("shading: a folded non-finite constant is kept for the points that reach it",
          "[shading]") {
  // §15: a non-finite result at a hit gives 0 there. A `1 / 0` folded on a branch
  // only some points take was refused as NonFiniteValue, rejecting the scene.
  Harness h(R"(
fn f(p) { if p.x < 0 { return 1 / 0; } return 0.5; }
fn g(p) { if p.x < 0 { return sqrt(-1) + <1, 2, 3>.x; } return 0.25; }
)");
  INFO(h.report());
  ir::Program p;
  bool finite = false;
  REQUIRE(h.compile("f", p));
  CHECK(h.diags.diagnostics().empty());
  CHECK(pattern::run_program(p, {1, 0, 0}, {}, finite) == 0.5);
  CHECK(finite);
  pattern::run_program(p, {-1, 0, 0}, {}, finite);
  CHECK(!finite);
  REQUIRE(h.compile("g", p));
  CHECK(pattern::run_program(p, {1, 0, 0}, {}, finite) == 0.25);
  pattern::run_program(p, {-1, 0, 0}, {}, finite);
  CHECK(!finite);
}

TEST_CASE("shading: a comparison in a vector is 1 or 0, and its component a number", "[shading]") {
  // §3's `<(a > b), 1, 2>`: the evaluator makes it <1, 1, 2>; the shading compiler
  // kept the component a bool, so `.x * 0.5` was a TypeMismatch.
  same_as_evaluator("fn f(p) = <(p.x > 0), 1, 2>.x * 0.5 + <p.y, (p.z <= 1)>.y;", "f", false);
}

TEST_CASE("shading: the op registry, the compiler, the interpreter and the dump agree",
          "[shading][registry]") {
  // Every op has a distinct enumerator, a spelling and a destination, and the dump
  // prints each with its operands; every op runs without leaving the slots.
  std::set<std::string> names;
  for (int i = 0; i < ir::program_op_count(); ++i) {
    const ir::ProgramOpInfo& info = ir::program_op_info(static_cast<ir::ProgramOp>(i));
    INFO(info.name);
    CHECK(names.insert(std::string(info.name)).second);
    CHECK(!info.spelling.empty());
    CHECK(info.operand[0] != ir::OperandKind::None);
    ir::Program p;
    p.constants = {1, 2, 3, 4, 5, 6, 0.5, 2, 0.25};
    p.slots = ir::kFirstConstantSlot + 9 + 3;
    ir::Instr in;
    in.op = static_cast<ir::ProgramOp>(i);
    in.dst = ir::kFirstConstantSlot + 9;
    in.a = ir::kFirstConstantSlot;
    in.b = ir::kFirstConstantSlot + 3;
    in.c = ir::kFirstConstantSlot + 6;
    if (in.op == ir::ProgramOp::LoopS || in.op == ir::ProgramOp::LoopV) {
      // A body that is done at once, its result its inputs (a scalar, or a vector).
      ir::Program body;
      const int w = in.op == ir::ProgramOp::LoopV ? 3 : 1;
      body.first_constant = static_cast<std::uint8_t>(w);
      body.constants = {1};
      body.slots = static_cast<std::uint16_t>(w + 1);
      body.done = static_cast<std::uint8_t>(w);
      for (int k = 0; k < w; ++k) body.next.push_back(static_cast<std::uint8_t>(k));
      p.loops.push_back(body);
      in.a = 0;
    }
    p.code.push_back(in);
    p.result = in.dst;
    CHECK(ir::check(p).empty());
    std::string dump = ir::to_string(p);
    CHECK(dump.find(" = " + std::string(info.spelling)) != std::string::npos);
    bool finite;
    pattern::run_program(p, {1, 2, 3}, {0, 1, 0}, finite);
  }
  // Every builtin of builtins.def has native ops of the right shapes.
  for (int id = 0; id < compile::builtin_count(); ++id) {
    compile::BuiltinOps ops = compile::builtin_ops(id);
    INFO(compile::builtin_info(id).name);
    CHECK(ops.found);
  }
  // The checker refuses what the interpreter could not run safely.
  ir::Program bad;
  bad.code.push_back({ir::ProgramOp::AddV, 250, 0, 0, 0});
  bad.slots = ir::kMaxSlots;
  CHECK(ir::check(bad).empty());  // 250..252 is inside 256 slots
  bad.code[0].dst = 254;          // 254..256 is not
  CHECK(!ir::check(bad).empty());
  bad.code[0] = {ir::ProgramOp::AddS, 1, 0, 0, 0};  // writes an input
  CHECK(!ir::check(bad).empty());
  bad.code[0] = {ir::ProgramOp::LoopS, 10, 0, 20, 0};  // runs a loop that is not there
  CHECK(!ir::check(bad).empty());
  ir::Program body;  // inputs r0..r2, next from r3..r5, done r6
  body.first_constant = 3;
  body.slots = 7;
  body.done = 6;
  body.next = {3, 4, 5};
  bad.loops.push_back(body);
  CHECK(ir::check(bad).empty());
  bad.loops[0].next.pop_back();  // an input with no next value
  CHECK(!ir::check(bad).empty());
  bad.loops[0].next = {3, 4, 9};  // a next value outside the body's slots
  CHECK(!ir::check(bad).empty());
  bad.loops[0].next = {3, 4, 5};
  bad.code[0].b = 254;  // its three inputs from 254..256
  CHECK(!ir::check(bad).empty());
}

TEST_CASE("shading: a background's zero normal stays zero through the pattern's transforms",
          "[shading]") {
  // A sky has no surface: f(p, n) gets n = 0 there. A `rotate` on the pattern took
  // it through the normal transform and normalised it: NaN, a black sky.
  Harness h("fn f(p, n) = 0.5 + 0.5 * n.y + 0 * p.x;");
  ir::FunctionPattern fp;
  REQUIRE(h.compile("f", fp.program));
  rt::PatternFrame frame;
  frame.space_from_world = ir::Transform::rotate_z(90).inverse();
  frame.identity = false;
  rt::TexturePoint sky;  // n_out = 0
  std::uint64_t nonfinite = 0;
  sky.nonfinite = &nonfinite;
  CHECK(rt::function_value(fp, frame, {0, 1, 0}, sky) == 0.5);
  CHECK(nonfinite == 0);
  // On a surface the normal is taken into the pattern's space: the pattern turned
  // 90° about z sees the world's +x as its own -y.
  rt::TexturePoint hit = sky;
  hit.n_out = rt::Vec3f(1, 0, 0);
  CHECK(rt::function_value(fp, frame, {0, 1, 0}, hit) == Approx(0.0).margin(1e-12));
  hit.n_out = rt::Vec3f(-1, 0, 0);
  CHECK(rt::function_value(fp, frame, {0, 1, 0}, hit) == Approx(1.0));
}

TEST_CASE("shading: a recursion on constants folds however deep the evaluator would go",
          "[shading]") {
  // §4 lets functions recurse 10 000 calls deep; on constants the shading compiler
  // folds each call away, and refused past 256 where the evaluator computes it.
  // Compiled as snell compiles, on a stack of its own (the main thread's 8 MB,
  // half kept in reserve by the stack check, held 600 calls in a release build
  // but not under the sanitizers' larger frames).
  compile::run_with_large_stack([] {
    Harness h(R"(
fn s(n) { if n <= 0 { return 0; } return n + s(n - 1); }
fn f(p) = p.x * s(3000);
fn g(p) = s(20000) + p.x;
fn depth(x) { if x < 1 { return 0; } return 1 + depth(x / 2); }
fn r(p) = depth(p.x * 1e300);
)");
    ir::Program p;
    REQUIRE(h.compile("f", p));
    bool finite = false;
    CHECK(pattern::run_program(p, {1, 0, 0}, {}, finite) == 3000.0 * 3001 / 2);
    CHECK(p.code.size() == 1);  // one multiply: s(3000) is a constant
    // Past the evaluator's own limit, and on run-time values past 256, still refused.
    CHECK_FALSE(h.compile("g", p));
    CHECK_FALSE(h.compile("r", p));
    CHECK(h.report().find("UnsupportedInShadingFunction") != std::string::npos);
  });
}
