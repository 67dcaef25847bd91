#include "runtime/pattern/program_eval.hpp"

#include <cmath>
#include <cstring>
#include <limits>

#include "runtime/ir/scalar_math.hpp"
#include "runtime/pattern/noise.hpp"

namespace snell::pattern {
namespace {

// The octave operand of fbm/turbulence: an integer in 1..kMaxOctaves, else 0
// (the result is then NaN, as the evaluator would have stopped with an error).
int octaves(double o) {
  return o >= 1 && o <= kMaxOctaves && o == std::floor(o) ? static_cast<int>(o) : 0;
}

ir::Vec3 load(const double* s) {
  return {s[0], s[1], s[2]};
}

// What bounds one evaluation (ir::kMaxWork, ir::kMaxCallDepth).
struct Budget {
  std::int64_t work = ir::kMaxWork;
};

void run_code(const ir::Program& prog, double* s, Budget& budget, int depth);

// A LoopS/LoopV started from a frame at call depth `depth`: the body in a register
// file of its own, its inputs from `args`, run until its done slot is true; the
// result into `d` (`w` slots). NaN when its calls would nest deeper than §4 allows
// or the evaluation's work runs out.
void run_loop(const ir::Program& body, const double* args, double* d, int w, Budget& budget,
              int depth) {
  double t[ir::kMaxSlots], next[ir::kMaxSlots];
  const int inputs = body.first_constant;
  std::memcpy(t, args, inputs * sizeof(double));
  if (!body.constants.empty())
    std::memcpy(t + inputs, body.constants.data(), body.constants.size() * sizeof(double));
  const std::int64_t run_work = std::int64_t(body.code.size()) + 1;
  for (int at = depth + body.depth0; at <= ir::kMaxCallDepth && budget.work > 0; ++at) {
    budget.work -= run_work;
    run_code(body, t, budget, at);
    if (t[body.done] != 0) {
      for (int k = 0; k < w; ++k) d[k] = t[body.result + k];
      return;
    }
    // All at once: an input's next value may be another input's current one.
    for (int j = 0; j < inputs; ++j) next[j] = t[body.next[j]];
    std::memcpy(t, next, inputs * sizeof(double));
  }
  for (int k = 0; k < w; ++k) d[k] = std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

double run_program(const ir::Program& prog, ir::Vec3 p, ir::Vec3 n, bool& finite) {
  double s[ir::kMaxSlots];
  s[0] = p.x, s[1] = p.y, s[2] = p.z;
  s[3] = n.x, s[4] = n.y, s[5] = n.z;
  if (!prog.constants.empty())
    std::memcpy(s + ir::kFirstConstantSlot, prog.constants.data(),
                prog.constants.size() * sizeof(double));
  Budget budget;
  run_code(prog, s, budget, 0);
  double r = s[prog.result];
  finite = std::isfinite(r);
  return r;
}

namespace {

void run_code(const ir::Program& prog, double* s, Budget& budget, int depth) {
  namespace m = ir::scalar;
  using Op = ir::ProgramOp;
  for (const ir::Instr& in : prog.code) {
    double* d = s + in.dst;
    const double* a = s + in.a;
    const double* b = s + in.b;
    const double* c = s + in.c;
// One component-wise operation on a scalar (NameS) and on each of 3 (NameV).
#define SNELL_MAP1(Name, f)                     \
  case Op::Name##S:                             \
    d[0] = f(a[0]);                             \
    break;                                      \
  case Op::Name##V:                             \
    for (int k = 0; k < 3; ++k) d[k] = f(a[k]); \
    break;
#define SNELL_MAP2(Name, f)                           \
  case Op::Name##S:                                   \
    d[0] = f(a[0], b[0]);                             \
    break;                                            \
  case Op::Name##V:                                   \
    for (int k = 0; k < 3; ++k) d[k] = f(a[k], b[k]); \
    break;
#define SNELL_MAP3(Name, f)                                 \
  case Op::Name##S:                                         \
    d[0] = f(a[0], b[0], c[0]);                             \
    break;                                                  \
  case Op::Name##V:                                         \
    for (int k = 0; k < 3; ++k) d[k] = f(a[k], b[k], c[k]); \
    break;
    switch (in.op) {
      SNELL_MAP2(Add, [](double x, double y) { return x + y; })
      SNELL_MAP2(Sub, [](double x, double y) { return x - y; })
      SNELL_MAP2(Mul, [](double x, double y) { return x * y; })
      SNELL_MAP2(Div, [](double x, double y) { return x / y; })
      SNELL_MAP2(Mod, m::floored_mod)
      SNELL_MAP1(Neg, [](double x) { return -x; })
      case Op::Splat:
        d[0] = d[1] = d[2] = a[0];
        break;
      case Op::MakeV: {
        double x = a[0], y = b[0], z = c[0];  // d may overlap a, b or c
        d[0] = x, d[1] = y, d[2] = z;
        break;
      }
      case Op::Lt:
        d[0] = a[0] < b[0];
        break;
      case Op::Le:
        d[0] = a[0] <= b[0];
        break;
      case Op::Gt:
        d[0] = a[0] > b[0];
        break;
      case Op::Ge:
        d[0] = a[0] >= b[0];
        break;
      case Op::EqS:
        d[0] = a[0] == b[0];
        break;
      case Op::NeS:
        d[0] = a[0] != b[0];
        break;
      case Op::Eq3:
        d[0] = a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
        break;
      case Op::Eq2:
        d[0] = a[0] == b[0] && a[1] == b[1];
        break;
      case Op::Not:
        d[0] = a[0] == 0;
        break;
      case Op::And:
        d[0] = a[0] != 0 && b[0] != 0;
        break;
      case Op::Or:
        d[0] = a[0] != 0 || b[0] != 0;
        break;
      case Op::SelS:
        d[0] = a[0] != 0 ? b[0] : c[0];
        break;
      case Op::SelV: {
        const double* from = a[0] != 0 ? b : c;
        double x = from[0], y = from[1], z = from[2];
        d[0] = x, d[1] = y, d[2] = z;
        break;
      }
        SNELL_MAP1(Sin, m::sin_deg)
        SNELL_MAP1(Cos, m::cos_deg)
        SNELL_MAP1(Tan, m::tan_deg)
        SNELL_MAP1(Asin, m::asin_deg)
        SNELL_MAP1(Acos, m::acos_deg)
        SNELL_MAP1(Atan, m::atan_deg)
        SNELL_MAP2(Atan2, m::atan2_deg)
        SNELL_MAP1(Sqrt, [](double x) { return std::sqrt(x); })
        SNELL_MAP2(Pow, [](double x, double y) { return std::pow(x, y); })
        SNELL_MAP1(Exp, [](double x) { return std::exp(x); })
        SNELL_MAP1(Log, [](double x) { return std::log(x); })
        SNELL_MAP1(Abs, [](double x) { return std::fabs(x); })
        SNELL_MAP1(Floor, [](double x) { return std::floor(x); })
        SNELL_MAP1(Ceil, [](double x) { return std::ceil(x); })
        SNELL_MAP1(Round, [](double x) { return std::round(x); })
        SNELL_MAP2(Min, [](double x, double y) { return std::fmin(x, y); })
        SNELL_MAP2(Max, [](double x, double y) { return std::fmax(x, y); })
        SNELL_MAP3(Clamp, m::clamp)
        SNELL_MAP3(Mix, m::mix)
      case Op::Dot3:
        d[0] = ir::dot(load(a), load(b));
        break;
      case Op::Dot2:
        d[0] = ir::dot({a[0], a[1], 0}, {b[0], b[1], 0});
        break;
      case Op::Cross: {
        ir::Vec3 r = ir::cross(load(a), load(b));
        d[0] = r.x, d[1] = r.y, d[2] = r.z;
        break;
      }
      case Op::Len3:
        d[0] = ir::length(load(a));
        break;
      case Op::Len2:
        d[0] = ir::length({a[0], a[1], 0});
        break;
      case Op::Norm3: {
        ir::Vec3 v = load(a);
        double len = ir::length(v);
        d[0] = v.x / len, d[1] = v.y / len, d[2] = v.z / len;
        break;
      }
      case Op::Norm2: {
        double x = a[0], y = a[1];
        double len = ir::length({x, y, 0});
        d[0] = x / len, d[1] = y / len;
        break;
      }
      case Op::Random:
        d[0] = m::random_hash(a[0]);
        break;
      case Op::Noise:
        budget.work -= ir::kNoiseWork;
        d[0] = noise(load(a));
        break;
      case Op::Fbm: {
        int o = octaves(b[0]);
        budget.work -= std::int64_t(ir::kNoiseWork) * o;
        d[0] = o ? fbm(load(a), o) : std::numeric_limits<double>::quiet_NaN();
        break;
      }
      case Op::Turb: {
        int o = octaves(b[0]);
        budget.work -= std::int64_t(ir::kNoiseWork) * o;
        d[0] = o ? turbulence(load(a), o) : std::numeric_limits<double>::quiet_NaN();
        break;
      }
      case Op::Cells:
        budget.work -= 2 * ir::kNoiseWork;
        d[0] = cells(load(a));
        break;
      case Op::LoopS:
        run_loop(prog.loops[in.a], s + in.b, d, 1, budget, depth);
        break;
      case Op::LoopV:
        run_loop(prog.loops[in.a], s + in.b, d, 3, budget, depth);
        break;
      case Op::MovS:
        d[0] = a[0];
        break;
      case Op::MovV: {
        double x = a[0], y = a[1], z = a[2];
        d[0] = x, d[1] = y, d[2] = z;
        break;
      }
    }
#undef SNELL_MAP1
#undef SNELL_MAP2
#undef SNELL_MAP3
  }
}

}  // namespace

}  // namespace snell::pattern
