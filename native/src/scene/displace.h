// True displacement (Cycles' Displacement Only and Displacement and Bump without adaptive
// subdivision): a mesh's vertices moved by a program run once per vertex, before its BVH
// is built.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>

#include "scene/mesh.h"
#include "scene/texture.h"
#include "shader/program.h"

namespace whitted {

// What moves the vertices of the triangles of one material slot: a program whose register
// `output` holds the world displacement at a vertex, its texture slots resolved to images
// (null: not an image), and whether the normals of the moved faces' vertices are made
// again from the moved faces (Displacement Only; Displacement and Bump keeps them, as its
// bump bends them).
struct SlotDisplacement {
  std::shared_ptr<const Program> program;
  std::vector<const ImageTexture*> images;
  uint32_t output = 0;
  bool renormal = false;
};

// Moves `mesh`'s vertices (object space, its deformation steps too) by the displacement of
// each triangle's slot (`slots[k]` null or past the end: slot k moves none), as Cycles
// does: each vertex once, at its corner of the first triangle (in order) that uses it and
// moves, with that triangle's corner layers there, the vertex's normal as the shading
// normal and as the incoming direction, and `to_world` as the object's transform; the world
// displacement goes back to object space by its inverse, a non-finite one is 0. Then, with
// vertex normals, those of the vertices of Displacement Only faces are made again: the
// normalised sum of the unit normals of the moved faces around them (Cycles 3.x to 5.x);
// with corner normals (sharp edges, custom normals) every corner is bent by how its
// vertex's normal (the normalised sum of the unit normals of all faces around it) turned,
// and a flat face (its three corners one normal) takes its moved face's normal (Cycles
// 4.5+). The first displacement keeps the vertices it found (Mesh::undisplaced). Returns
// how many vertices moved. A program that traces (AMBIENT_OCCLUSION, BEVEL) reads as where
// nothing is traced; throws std::invalid_argument for an output past its registers.
size_t displace(Mesh* mesh, std::span<const SlotDisplacement* const> slots,
                const glm::mat4& to_world);

}  // namespace whitted
