// Number formatting shared by the IR's dump, validation and feature reasons.
#pragma once

#include <string>

namespace snell::ir {

// Shortest round-trip text of a double ("0" for ±0): dumps are stable and exact.
std::string num(double v);

}  // namespace snell::ir
