#include "runtime/ir/program.hpp"

#include <cstdio>
#include <iterator>

namespace snell::ir {
namespace {

constexpr OperandKind S = OperandKind::Scalar;
constexpr OperandKind V = OperandKind::Vector;
constexpr OperandKind N = OperandKind::None;

constexpr ProgramOpInfo kOps[] = {
#define SNELL_OP(name, spelling, d, a, b, c) {#name, spelling, {d, a, b, c}},
#include "runtime/ir/program_ops.def"
};

int width(OperandKind k) {
  return k == V ? 3 : k == S ? 1 : 0;
}

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// A slot as the dump names it: the inputs by name (a loop body's as a0, a1, ...),
// the rest as registers.
std::string slot_name(int slot, OperandKind k, bool body = false) {
  static const char* const kComponent[] = {"x", "y", "z"};
  if (body) return std::string(k == V ? "v" : "r") + std::to_string(slot);
  if (slot < kFirstConstantSlot) {
    const char* base = slot < kNormalSlot ? "p" : "n";
    int c = slot % 3;
    if (k == V) return c == 0 ? base : std::string(base) + "+" + std::to_string(c);
    return std::string(base) + "." + kComponent[c];
  }
  return (k == V ? "v" : "r") + std::to_string(slot);
}

}  // namespace

int program_op_count() {
  return static_cast<int>(std::size(kOps));
}

const ProgramOpInfo& program_op_info(ProgramOp op) {
  return kOps[static_cast<int>(op)];
}

namespace {

bool is_loop(ProgramOp op) {
  return op == ProgramOp::LoopS || op == ProgramOp::LoopV;
}

// `result_width`: what the caller reads at p.result (1, or 3 for a LoopV's body).
std::string check_program(const Program& p, bool body, int depth, int result_width) {
  if (depth > kMaxLoopNesting)
    return "nests loops more than " + std::to_string(kMaxLoopNesting) + " deep";
  if (p.slots > kMaxSlots) return "uses " + std::to_string(p.slots) + " slots";
  if (p.code.size() > kMaxCode) return "has " + std::to_string(p.code.size()) + " instructions";
  if (!body && (p.first_constant != kFirstConstantSlot || !p.next.empty()))
    return "has a loop body's inputs";
  if (body && (p.next.size() != p.first_constant || p.done >= p.slots))
    return "is a loop body without its next inputs or done slot";
  for (std::uint8_t n : p.next)
    if (n >= p.slots) return "takes a next input from outside the slots";
  if (p.first_constant + p.constants.size() > p.slots) return "constants outside the slots";
  if (p.result + result_width > p.slots) return "result outside the slots";
  for (std::size_t i = 0; i < p.code.size(); ++i) {
    const Instr& in = p.code[i];
    const std::string at = "instruction " + std::to_string(i);
    if (static_cast<int>(in.op) >= program_op_count()) return at + " has no operation";
    const ProgramOpInfo& info = program_op_info(in.op);
    const std::uint8_t slot[4] = {in.dst, in.a, in.b, in.c};
    for (int k = 0; k < 4; ++k)
      if (slot[k] + width(info.operand[k]) > p.slots)
        return at + " reads or writes outside the slots";
    if (in.dst < p.first_constant + p.constants.size())
      return at + " writes an input or a constant";
    if (is_loop(in.op)) {
      if (in.a >= p.loops.size()) return at + " runs a loop that is not there";
      if (in.b + p.loops[in.a].first_constant > p.slots) return at + " reads outside the slots";
    }
  }
  for (std::size_t k = 0; k < p.loops.size(); ++k) {
    int w = 1;
    for (const Instr& in : p.code)
      if (is_loop(in.op) && in.a == k) w = in.op == ProgramOp::LoopV ? 3 : 1;
    std::string e = check_program(p.loops[k], true, depth + 1, w);
    if (!e.empty()) return "loop " + std::to_string(k) + " " + e;
  }
  return {};
}

void dump(const Program& p, bool body, const std::string& indent, std::string& s) {
  for (std::size_t i = 0; i < p.constants.size(); ++i)
    s += indent + slot_name(static_cast<int>(p.first_constant + i), S, body) + " = " +
         number(p.constants[i]) + "\n";
  for (const Instr& in : p.code) {
    const ProgramOpInfo& info = program_op_info(in.op);
    s += indent + slot_name(in.dst, info.operand[0], body) + " = " + std::string(info.spelling);
    if (is_loop(in.op)) {
      s += " L" + std::to_string(in.a) + " from r" + std::to_string(in.b) + "\n";
      continue;
    }
    const std::uint8_t slot[3] = {in.a, in.b, in.c};
    for (int k = 0; k < 3; ++k)
      if (info.operand[k + 1] != N) s += " " + slot_name(slot[k], info.operand[k + 1], body);
    s += "\n";
  }
  for (std::size_t k = 0; k < p.loops.size(); ++k) {
    const Program& b = p.loops[k];
    s += indent + "L" + std::to_string(k) + ": " + std::to_string(b.code.size()) +
         " instructions, " + std::to_string(b.constants.size()) + " constants, " +
         std::to_string(b.slots) + " slots, inputs r0..r" + std::to_string(b.first_constant - 1) +
         "; until r" + std::to_string(b.done) + ", result r" + std::to_string(b.result) +
         ", first call at depth +" + std::to_string(b.depth0) + ", next";
    for (std::uint8_t n : b.next) s += " r" + std::to_string(n);
    s += "\n";
    dump(b, true, indent + "  ", s);
  }
}

}  // namespace

std::string check(const Program& p) {
  return check_program(p, false, 0, 1);
}

std::string to_string(const Program& p) {
  std::string s = "program: " + std::to_string(p.code.size()) + " instructions, " +
                  std::to_string(p.constants.size()) + " constants, " + std::to_string(p.slots) +
                  " slots, reads";
  if (p.reads_point) s += " p";
  if (p.reads_normal) s += " n";
  if (!p.reads_point && !p.reads_normal) s += " nothing";
  s += "; result " + slot_name(p.result, S) + "\n";
  dump(p, false, "  ", s);
  return s;
}

}  // namespace snell::ir
