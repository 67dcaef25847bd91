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

// A slot as the dump names it: the inputs by name, the rest as registers.
std::string slot_name(int slot, OperandKind k) {
  static const char* const kComponent[] = {"x", "y", "z"};
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

std::string check(const Program& p) {
  if (p.slots > kMaxSlots) return "uses " + std::to_string(p.slots) + " slots";
  if (p.code.size() > kMaxCode) return "has " + std::to_string(p.code.size()) + " instructions";
  if (kFirstConstantSlot + p.constants.size() > p.slots) return "constants outside the slots";
  if (p.result >= p.slots) return "result outside the slots";
  for (std::size_t i = 0; i < p.code.size(); ++i) {
    const Instr& in = p.code[i];
    if (static_cast<int>(in.op) >= program_op_count())
      return "instruction " + std::to_string(i) + " has no operation";
    const ProgramOpInfo& info = program_op_info(in.op);
    const std::uint8_t slot[4] = {in.dst, in.a, in.b, in.c};
    for (int k = 0; k < 4; ++k)
      if (slot[k] + width(info.operand[k]) > p.slots)
        return "instruction " + std::to_string(i) + " reads or writes outside the slots";
    if (in.dst < kFirstConstantSlot + p.constants.size())
      return "instruction " + std::to_string(i) + " writes an input or a constant";
  }
  return {};
}

std::string to_string(const Program& p) {
  std::string s = "program: " + std::to_string(p.code.size()) + " instructions, " +
                  std::to_string(p.constants.size()) + " constants, " + std::to_string(p.slots) +
                  " slots, reads";
  if (p.reads_point) s += " p";
  if (p.reads_normal) s += " n";
  if (!p.reads_point && !p.reads_normal) s += " nothing";
  s += "; result " + slot_name(p.result, S) + "\n";
  for (std::size_t i = 0; i < p.constants.size(); ++i)
    s += "  " + slot_name(static_cast<int>(kFirstConstantSlot + i), S) + " = " +
         number(p.constants[i]) + "\n";
  for (const Instr& in : p.code) {
    const ProgramOpInfo& info = program_op_info(in.op);
    s += "  " + slot_name(in.dst, info.operand[0]) + " = " + std::string(info.spelling);
    const std::uint8_t slot[3] = {in.a, in.b, in.c};
    for (int k = 0; k < 3; ++k)
      if (info.operand[k + 1] != N) s += " " + slot_name(slot[k], info.operand[k + 1]);
    s += "\n";
  }
  return s;
}

}  // namespace snell::ir
