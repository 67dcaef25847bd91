// A compiled shading function (§15 `pattern { function f }`): a straight-line
// register program the runtime interprets at each hit
// (runtime/pattern/program_eval.hpp). The compiler (compiler/shading_function.hpp)
// builds it from a user `fn`; the renderer never sees the syntax tree.
//
// The machine. One register file of kMaxSlots doubles, on the interpreter's stack:
//   slots 0-2   the point p (x, y, z)
//   slots 3-5   the normal n
//   slots 6..   the constants, copied in before the first instruction
//   then        temporaries
// A scalar register is one slot; a vector register is three consecutive slots
// (a 2-vector leaves its third slot don't-care). So `p.y` is simply slot 1: a
// component needs no instruction. Each instruction names its operation
// (program_ops.def says which operands are scalars or vectors) and up to four
// slots. There are no jumps: an `if` on a run-time value computes both arms and
// selects (the functions are pure, so this is exact), which keeps the interpreter
// one loop over the code and dead-code removal a backward sweep.
//
// The one exception is a tail recursion on run-time values (`return f(...)` as
// the only way a function calls itself): its body is a program of its own in
// `loops`, run by a LoopS/LoopV instruction until its `done` slot is true. A
// body's inputs are its parameters, in slots 0 .. first_constant (a number or
// bool one slot, a vector three), its constants after them; `next[j]` is the
// slot whose value input slot j takes for the next run. Bodies nest (a body may
// run loops of its own) at most kMaxLoopNesting deep.
//
// Limits: kMaxSlots slots and kMaxCode instructions per program; the compiler
// rejects a function that needs more, so the interpreter never allocates.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace snell::ir {

enum class ProgramOp : std::uint8_t {
#define SNELL_OP(name, spelling, d, a, b, c) name,
#include "runtime/ir/program_ops.def"
};

// How an instruction reads one of its slots.
enum class OperandKind : std::uint8_t { None, Scalar, Vector };

struct ProgramOpInfo {
  std::string_view name;  // the enumerator, as in program_ops.def
  std::string_view spelling;
  OperandKind operand[4];  // destination, then A, B, C
};

int program_op_count();
const ProgramOpInfo& program_op_info(ProgramOp op);

inline constexpr int kMaxSlots = 256;
inline constexpr int kMaxCode = 1024;
inline constexpr std::uint8_t kPointSlot = 0;
inline constexpr std::uint8_t kNormalSlot = 3;
inline constexpr std::uint8_t kFirstConstantSlot = 6;
inline constexpr int kMaxLoopNesting = 8;
// §4's bound on recursion: calls nested deeper than this stop. A loop body's run
// is one call of its function, so run r of a loop whose first call is at depth D
// is at depth D + r (D counts the calls around it: the shading function's own, a
// helper's, an outer loop's runs), and past kMaxCallDepth the loop gives NaN
// where the evaluator stops with RecursionLimit: the same count, so a value the
// evaluator has is the render's too (compile::kMaxCallDepth is this number).
inline constexpr int kMaxCallDepth = 10000;
// The work of one evaluation at one point, in instructions run (a noise octave
// counts kNoiseWork, cells two): past it every loop still running gives NaN, so a
// hit costs at most about a millisecond. Loops inside loops would otherwise
// multiply their bounds (10 000^8 runs at one hit), and a body of 32-octave fbm
// calls took seconds per hit under a bound on runs alone. An escape-time fractal
// of 10 000 iterations needs ~150 000.
inline constexpr std::int64_t kMaxWork = std::int64_t(1) << 20;
inline constexpr int kNoiseWork = 16;

struct Instr {
  ProgramOp op = ProgramOp::AddS;
  std::uint8_t dst = 0, a = 0, b = 0, c = 0;
  bool operator==(const Instr&) const = default;
};

struct Program {
  std::vector<Instr> code;
  std::vector<double> constants;  // slots kFirstConstantSlot, kFirstConstantSlot + 1, ...
  std::uint16_t slots = kFirstConstantSlot;  // register file size the code touches
  std::uint8_t result = 0;                   // the scalar slot holding the value
  bool reads_point = false;
  bool reads_normal = false;
  // Loop bodies run by this program's LoopS/LoopV instructions, and for a body
  // itself: where its constants start (its inputs before), its done slot (a
  // bool), and the slot each input takes its next value from.
  std::vector<Program> loops;
  std::uint8_t first_constant = kFirstConstantSlot;
  std::uint8_t done = 0;
  // A loop body: the call depth of its first run, counted from the frame that
  // starts the loop (1: the loop's function called directly from it).
  std::uint16_t depth0 = 1;
  std::vector<std::uint8_t> next;
  bool operator==(const Program&) const = default;
};

// Empty when `p` is well formed (every operand inside `slots`, `slots` and the
// code within the limits, constants inside the file); otherwise what is wrong.
// The interpreter relies on it; the compiler's output always passes.
std::string check(const Program& p);

// The --dump-ir form: one line per constant and instruction, e.g.
//   program: 2 instructions, 0 constants, 8 slots, reads p; result r7
//     r6 = floor p.y
//     r7 = sub p.y r6
std::string to_string(const Program& p);

}  // namespace snell::ir
