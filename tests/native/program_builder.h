// Shader programs for the native tests, written a row to an instruction instead of the
// 8-column code array Program's constructor reads (shader/program.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "shader/program.h"

namespace whitted::testing {

inline constexpr uint32_t kU = Program::kUnused;

// One instruction: op, mode, out, and the operands a..e (unused unless given).
struct Row {
  Op op;
  uint32_t mode = 0, out = 0, a = kU, b = kU, c = kU, d = kU, e = kU;
};

inline Program make(const std::vector<Row>& rows, const std::vector<glm::vec4>& registers,
                    std::vector<float> constants = {}, std::vector<std::string> textures = {}) {
  std::vector<uint32_t> code;
  for (const Row& r : rows) {
    code.insert(code.end(), {static_cast<uint32_t>(r.op), r.mode, r.out, r.a, r.b, r.c, r.d, r.e});
  }
  const float* values = registers.empty() ? nullptr : &registers[0].x;
  return Program(code.data(), rows.size(), values, registers.size(), std::move(constants),
                 std::move(textures));
}

}  // namespace whitted::testing
