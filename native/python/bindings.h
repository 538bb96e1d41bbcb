// Shared declarations of the binding files: one file per bound concept.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "core/math.h"
#include "integrator/passes.h"

namespace py = pybind11;

// Colours, points and directions (3) and a shader program's registers (4: a value in all
// four, a vector or colour in xyz) cross the boundary as sequences of N floats.
namespace pybind11::detail {
template <glm::length_t N, glm::qualifier Q>
requires(N == 3 || N == 4) struct type_caster<glm::vec<N, float, Q>> {
  using Vec = glm::vec<N, float, Q>;
  PYBIND11_TYPE_CASTER(Vec, const_name<N == 3>("tuple[float, float, float]",
                                               "tuple[float, float, float, float]"));
  bool load(handle src, bool) {
    if (!isinstance<sequence>(src) || isinstance<str>(src)) return false;
    auto seq = reinterpret_borrow<sequence>(src);
    if (seq.size() != N) return false;
    for (glm::length_t i = 0; i < N; ++i) value[i] = seq[static_cast<size_t>(i)].cast<float>();
    return true;
  }
  static handle cast(const Vec& v, return_value_policy, handle) {
    py::tuple out(N);
    for (glm::length_t i = 0; i < N; ++i) out[static_cast<size_t>(i)] = py::float_(v[i]);
    return out.release();
  }
};
}  // namespace pybind11::detail

namespace whitted {
struct CompiledScene;
struct Mesh;
struct RayTree;
}  // namespace whitted

namespace whitted::python {

void bind_camera(py::module_& m);
void bind_mesh(py::module_& m);
void bind_settings(py::module_& m);
void bind_panorama(py::module_& m);
void bind_light(py::module_& m);
void bind_material(py::module_& m);
void bind_program(py::module_& m);
void bind_scene(py::module_& m);
void bind_texture(py::module_& m);
void bind_render(py::module_& m);
void bind_denoise(py::module_& m);
void bind_volume_object(py::module_& m);

// The inspector's tree as {"pixel", "alpha", "rays": [...]} (native/python/ray_tree.cpp).
py::dict ray_tree_dict(const RayTree& tree, const CompiledScene& scene);

// 4x4 row-major numpy matrices <-> glm (column-major) matrices.
glm::mat4 matrix_from_numpy(const py::handle& h);
py::array_t<double> matrix_to_numpy(const glm::mat4& m);

// numpy arrays as the bindings take them: C-contiguous, converted to the type if need be.
using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
using UintArray = py::array_t<uint32_t, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;

// Raises ValueError unless `a` has `shape` (-1: any length on that axis).
void require_shape(const py::array& a, const char* name, std::initializer_list<py::ssize_t> shape);

// A native Mesh checked and copied out of arrays (native/python/mesh.cpp: Mesh(...)).
Mesh mesh_from_arrays(const FloatArray& positions, const UintArray& triangles,
                      const std::optional<FloatArray>& normals,
                      const std::optional<IntArray>& material_slots,
                      const std::optional<FloatArray>& uvs,
                      const std::optional<FloatArray>& vertex_normals,
                      const std::vector<FloatArray>& uv_sets,
                      const std::vector<FloatArray>& attributes,
                      const std::vector<FloatArray>& tangents);

// Film passes by their names (whitted_native.FILM_PASSES; native/python/settings.cpp).
FilmPass film_pass(const std::string& name);
uint32_t pass_bits(const std::vector<std::string>& names);
std::vector<std::string> pass_names(uint32_t bits);

// Raises ValueError unless every component of a colour/vector is finite.
inline void require_finite(const Vec3& v, const char* what) {
  if (!is_finite(v)) throw std::invalid_argument(std::string(what) + " must be finite");
}

}  // namespace whitted::python
