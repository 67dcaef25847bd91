// Where an IR item was written: an index into Scene::files, line and column.
#pragma once

#include <cstdint>

namespace snell::ir {

struct SourceRef {
  std::uint32_t file = 0;
  std::uint32_t line = 0;  // 0: made in C++, not from a scene file
  std::uint32_t col = 0;
};

}  // namespace snell::ir
