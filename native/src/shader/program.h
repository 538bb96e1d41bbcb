// A shader program: a node graph lowered by the add-on into a flat list of instructions
// over a small file of float4 registers (the contract: docs/notes/shader_program.md).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec4.hpp>

#include "core/math.h"
#include "scene/texture.h"
#include "shader/ops.h"

namespace whitted {

// What a hit offers the ops that trace rays (AMBIENT_OCCLUSION, BEVEL): rays from and near
// the hit point, and the points of [0, 1)^2 they are drawn from. Made by the scene where the
// integrator traces (scene/surface.cpp); a program evaluated where nothing is traced (the world, a
// shadow feeler's walk, a medium) has none.
class HitRays {
 public:
  // Whether anything lies within `distance` of the hit along unit `direction`: anything a
  // shadow ray sees, or with `local` anything of the hit's own object. Counted as an
  // ambient occlusion ray.
  virtual bool occluded(const Vec3& direction, float distance, bool local) const = 0;
  // Where a segment meets the hit's own object: the point, its geometric normal and its
  // shading normal (world, as the mesh winds them).
  struct Surface {
    Vec3 position, geometric_normal, normal;
  };
  static constexpr int kMaxSurfaces = 8;
  // The points where the segment from `origin` along unit `direction`, `length` long,
  // meets the hit's own object, nearest first, at most kMaxSurfaces of them into `out`;
  // how many. Each query counted as a bevel ray.
  virtual int surfaces(const Vec3& origin, const Vec3& direction, float length,
                       Surface* out) const = 0;
  // Point k of the `count` points an evaluation at this hit draws from: stratified over
  // the pixel's camera samples, a function of the pixel, its sample and the depth only.
  virtual glm::vec2 point(int k, int count) const = 0;

 protected:
  ~HitRays() = default;
};

// What a program reads at one hit besides its registers.
struct ProgramHit {
  // The value of each of Program::inputs(), in that order.
  const glm::vec4* inputs = nullptr;
  Vec3 incoming{0.0f, 0.0f, 1.0f};  // unit, from the hit towards the ray's origin
  Vec3 normal{0.0f, 0.0f, 1.0f};    // unit shading normal on the incoming side (Blender's N)
  bool backfacing = false;          // the ray meets the back of the geometric normal
  glm::mat3 to_world{1.0f};         // linear part of the object's transform
  glm::mat3 normal_to_world{1.0f};  // its inverse transpose
  const ImageTexture* const* images = nullptr;  // one per texture slot (null: not an image)
  // The two offsets of the hit along the surface (world) at which inputs with the
  // kInputBumpX / kInputBumpY bit are read, and which BUMP differentiates along.
  Vec3 bump_dx{0.0f};
  Vec3 bump_dy{0.0f};
  // Rays from the hit, for a program that traces(); null: AMBIENT_OCCLUSION gives 1 and
  // BEVEL the normal, as Cycles' nodes where they cannot trace.
  const HitRays* rays = nullptr;
};

class Program {
 public:
  static constexpr uint32_t kUnused = kUnusedOperand;
  // A register file this big lives on the stack of one evaluation.
  static constexpr size_t kMaxRegisters = 1024;
  static constexpr size_t kMaxInputs = 64;  // distinct INPUT modes (and tangent frames)
  static constexpr size_t kColumns = 8;     // op, mode, out, a, b, c, d, e

  // Checks everything an evaluation relies on and throws std::invalid_argument naming the
  // first instruction that is wrong: `code` is `rows` x 8, `registers` `register_count` x 4.
  Program(const uint32_t* code, size_t rows, const float* registers, size_t register_count,
          std::vector<float> constants, std::vector<std::string> textures);

  size_t register_count() const { return initial_.size(); }
  size_t instruction_count() const { return steps_.size(); }
  const std::vector<std::string>& textures() const { return textures_; }
  // The input modes the program reads (Input), each once: ProgramHit::inputs follows them.
  const std::vector<uint32_t>& inputs() const { return inputs_; }
  // Whether a texture slot is sampled as an image (IMAGE, ENVIRONMENT).
  bool samples_image(size_t slot) const { return image_slots_[slot]; }
  // Whether it reads inputs at the bump offsets (then ProgramHit needs them).
  bool bumps() const { return bumps_; }
  // Whether it traces rays from the hit (AMBIENT_OCCLUSION, BEVEL: then ProgramHit::rays).
  bool traces() const { return traces_; }

  // Runs the instructions; `registers` has room for kMaxRegisters + 1 values and holds
  // the register file afterwards.
  void run(const ProgramHit& hit, glm::vec4* registers) const;

  // The constant compiler's folding: the value of one `op` (not one that reads the hit,
  // kOpTable) of `operands` (one per register operand of the op, null: unused), its
  // COLOR_RAMP or CURVE table in `constants`, computed by run() itself. nullopt for an
  // op that reads the hit; std::invalid_argument for an instruction run() would refuse.
  static std::optional<glm::vec4> fold(uint32_t op, uint32_t mode,
                                       std::span<const std::optional<glm::vec4>> operands,
                                       std::vector<float> constants);

 private:
  // An instruction as the interpreter reads it: unused register operands point at the
  // always-zero register past the file; INPUT's `e`, and tangent NORMAL_MAP's `e` (the
  // tangent) and `d` (the object normal), are slots of inputs_.
  struct Step {
    Op op;
    uint32_t mode, out, a, b, c, d, e;
    bool b_given;  // FRESNEL, LAYER_WEIGHT: a normal was given (else the shading normal)
  };
  uint32_t input_slot(uint32_t mode);

  std::vector<Step> steps_;
  std::vector<glm::vec4> initial_;
  std::vector<float> constants_;
  std::vector<std::string> textures_;
  std::vector<bool> image_slots_;
  std::vector<uint32_t> inputs_;
  bool bumps_ = false;
  bool traces_ = false;
};

}  // namespace whitted
