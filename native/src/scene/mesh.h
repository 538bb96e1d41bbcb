// A triangle mesh in object space, shared by every instance that uses it.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "core/math.h"
#include "scene/motion.h"

namespace whitted {

// Strands (hair, curves), traced as round tubes of the radius each key gives: Catmull-Rom
// curves through their keys (Embree's round curves; Cycles' Thick), each strand's first
// and last keys doubled so that a segment, which reads four keys, ends at them; or, when
// `linear`, straight cones from key to key with round joints and ends (Cycles 5.x's Thick
// Linear, which it takes for poly curves). When `flat`, the same curves are ribbons of the
// key's radius either side of the curve, turned to face each ray (Embree's flat curves;
// Cycles' Ribbons), shaded with the normals of the round tube they stand for. A segment is
// the index of its first key.
struct Curves {
  std::vector<float> keys;         // x, y, z, radius per key (object space)
  std::vector<uint32_t> segments;  // the first key of each segment
  std::vector<int32_t> slots;      // material slot of each segment, or empty for slot 0
  bool linear = false;
  bool flat = false;
  size_t segment_count() const { return segments.size(); }
};

// Points (a point cloud): spheres of a radius each.
struct Points {
  std::vector<float> spheres;  // x, y, z, radius per point (object space)
  std::vector<int32_t> slots;  // material slot of each point, or empty for slot 0
  size_t count() const { return spheres.size() / 4; }
};

// What a primitive index of a mesh is: its triangles come first, then its curves'
// segments, then its points (one index space, as the hits Embree reports are numbered).
enum class PrimitiveKind { kTriangle, kCurve, kPoint };

struct Mesh {
  std::vector<float> positions;     // 3 per vertex, plus one float of padding Embree reads
  std::vector<uint32_t> triangles;  // 3 vertex indices per triangle
  // Shading normals, at most one of the two (both empty: every face flat). Corner normals
  // for meshes with sharp edges, flat faces among smooth ones or custom normals; vertex
  // normals, indexed like positions, for smooth meshes whose corners take the vertex normal.
  std::vector<float> normals;           // 9 per triangle (corner normals), or empty
  std::vector<float> vertex_normals;    // 3 per vertex, or empty
  std::vector<int32_t> material_slots;  // 1 per triangle, or empty for slot 0
  std::vector<float> uvs;               // 6 per triangle (corner UVs), or empty
  // Corner layers for shader programs, each indexed by triangle then corner: UV sets (2
  // floats a corner; none given: `uvs` is set 0), attributes (RGBA, 4 a corner) and
  // tangents (tangent set k belongs to UV set k: object-space xyz, bitangent sign w).
  std::vector<std::vector<float>> uv_sets;
  std::vector<std::vector<float>> attributes;
  std::vector<std::vector<float>> tangents;
  // Blender's automatic texture space: generated = (p - location + size) / (2 size).
  Vec3 texspace_location{0.0f};
  Vec3 texspace_size{1.0f};
  // Where displace() (scene/displace.h) found the vertices, 3 per vertex, object space:
  // Generated coordinates read the undisplaced surface, as Cycles' attribute does. Empty
  // when nothing moved them.
  std::vector<float> undisplaced;
  // Deformation motion blur: its positions at evenly spaced times from the shutter's
  // opening to its closing, each laid out as `positions` (padding included); empty when
  // it does not deform. Embree blends neighbouring steps linearly, as vertex_at does.
  std::vector<std::vector<float>> motion_positions;

  Curves curves;  // strands of the same object (its hair, a Curves object's)
  Points points;  // spheres of the same object (a point cloud)

  size_t vertex_count() const { return positions.size() / 3; }  // the padding float rounds off
  size_t triangle_count() const { return triangles.size() / 3; }
  // Triangles, curve segments and points: what a ray can hit.
  size_t primitive_count() const {
    return triangle_count() + curves.segment_count() + points.count();
  }
  PrimitiveKind kind(uint32_t primitive) const {
    if (primitive < triangle_count()) return PrimitiveKind::kTriangle;
    return primitive < triangle_count() + curves.segment_count() ? PrimitiveKind::kCurve
                                                                 : PrimitiveKind::kPoint;
  }
  Vec3 vertex(uint32_t i) const {
    return {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]};
  }
  bool deforms() const { return !motion_positions.empty(); }
  // Vertex i at shutter time `time` in [0, 1] (vertex(i) when it does not deform).
  Vec3 vertex_at(uint32_t i, float time) const {
    if (motion_positions.empty()) return vertex(i);
    const auto [k, f] = time_segment(time, motion_positions.size());
    const float* a = &motion_positions[k][3 * size_t{i}];
    const float* b = &motion_positions[k + 1][3 * size_t{i}];
    return (1.0f - f) * Vec3(a[0], a[1], a[2]) + f * Vec3(b[0], b[1], b[2]);
  }
  // The object-space point Generated coordinates read at barycentric `b` (weights of
  // vertices 1 and 2) of primitive `primitive`, whose own point is `local`: the
  // undisplaced triangle's there, or `local` itself where nothing was displaced.
  // The Generated coordinates of object-space point `local` in the texture space above.
  Vec3 generated(const Vec3& local) const {
    return (local - texspace_location + texspace_size) / (2.0f * texspace_size);
  }
  Vec3 undisplaced_point(uint32_t primitive, glm::vec2 b, const Vec3& local) const {
    if (undisplaced.empty() || kind(primitive) != PrimitiveKind::kTriangle) return local;
    const uint32_t* tri = &triangles[3 * size_t{primitive}];
    const auto at = [&](uint32_t v) {
      return Vec3(undisplaced[3 * size_t{v}], undisplaced[3 * size_t{v} + 1],
                  undisplaced[3 * size_t{v} + 2]);
    };
    return (1.0f - b.x - b.y) * at(tri[0]) + b.x * at(tri[1]) + b.y * at(tri[2]);
  }
  // Whether triangles carry shading normals (smooth shading) rather than their face normal.
  bool has_normals() const { return !normals.empty() || !vertex_normals.empty(); }
  // The shading normals at the three corners of triangle `primitive`, as stored (not
  // renormalised; a zero one stands for the face normal); false, and nothing written, when
  // the mesh is flat.
  // The material slot of triangle `primitive`.
  size_t slot(uint32_t primitive) const {
    const size_t triangles_end = triangle_count();
    if (primitive < triangles_end) {
      return material_slots.empty() ? 0 : static_cast<size_t>(material_slots[primitive]);
    }
    const size_t curves_end = triangles_end + curves.segment_count();
    if (primitive < curves_end) {
      return curves.slots.empty() ? 0
                                  : static_cast<size_t>(curves.slots[primitive - triangles_end]);
    }
    return points.slots.empty() ? 0 : static_cast<size_t>(points.slots[primitive - curves_end]);
  }
  bool corner_normals(uint32_t primitive, Vec3* n0, Vec3* n1, Vec3* n2) const {
    if (!normals.empty()) {
      const float* n = &normals[9 * size_t{primitive}];
      *n0 = Vec3(n[0], n[1], n[2]);
      *n1 = Vec3(n[3], n[4], n[5]);
      *n2 = Vec3(n[6], n[7], n[8]);
      return true;
    }
    if (!vertex_normals.empty()) {
      const uint32_t* tri = &triangles[3 * size_t{primitive}];
      const auto at = [&](uint32_t v) {
        return Vec3(vertex_normals[3 * size_t{v}], vertex_normals[3 * size_t{v} + 1],
                    vertex_normals[3 * size_t{v} + 2]);
      };
      *n0 = at(tri[0]);
      *n1 = at(tri[1]);
      *n2 = at(tri[2]);
      return true;
    }
    return false;
  }
};

// The axis-aligned box of a mesh's vertices, strands' and points' spheres (lower above
// upper for a mesh without any).
struct Box {
  Vec3 lower{std::numeric_limits<float>::max()};
  Vec3 upper{-std::numeric_limits<float>::max()};
  bool empty() const { return lower.x > upper.x; }
};
Box bounding_box(const Mesh& mesh);

// Sets `mesh`'s texture space to the box [lo, hi], as Blender's automatic one: a flat axis
// gets size 1 and a tiny one 1e-5, so generated coordinates stay finite.
void fit_texspace(const Vec3& lo, const Vec3& hi, Mesh* mesh);

// A bounding sphere of a mesh's vertices (about its box's centre; radius 0 for a mesh
// without vertices): its extent, for estimates made before tracing (camera packets).
struct Sphere {
  Vec3 centre{0.0f};
  float radius = 0.0f;
};
Sphere bounding_sphere(const Mesh& mesh);

// 1 + the largest material slot a primitive of `mesh` uses; 0 for a mesh without any.
size_t slot_count(const Mesh& mesh);

// Corner layers handed to make_mesh, each `triangle_count` x 3 corners.
struct CornerLayers {
  std::vector<const float*> uv_sets;     // 2 floats a corner
  std::vector<const float*> attributes;  // 4 floats a corner
  std::vector<const float*> tangents;    // 4 floats a corner, at most one per UV set
};

// Builds a mesh from flat arrays, checking every index and value; throws
// std::invalid_argument naming the first problem. `normals` (9 per triangle) and
// `vertex_normals` (3 per vertex) are alternatives: at most one may be given. `uvs` (6 per
// triangle) are what image textures read, and UV set 0 of a mesh whose `layers` give none.
Mesh make_mesh(const float* positions, size_t vertex_count, const uint32_t* triangles,
               size_t triangle_count, const float* normals, const int32_t* material_slots,
               const float* uvs = nullptr, const float* vertex_normals = nullptr,
               const CornerLayers& layers = {});

// Curves from `keys` (x, y, z, radius each) of strands of `counts[i]` keys each, in
// order, and a material slot per strand (null: slot 0); Catmull-Rom or `linear`, round or
// `flat`. Strands of fewer than two keys are left out; a negative or non-finite radius is 0
// (a strand with a non-finite position throws std::invalid_argument, naming it).
Curves make_curves(const float* keys, size_t key_count, const uint32_t* counts, size_t strand_count,
                   const int32_t* slots, bool linear = false, bool flat = false);
// Points from `spheres` (x, y, z, radius each) and a slot per point (null: slot 0); a
// negative or non-finite radius is 0 (such a point is invisible), a non-finite position
// throws std::invalid_argument.
Points make_points(const float* spheres, size_t count, const int32_t* slots);

// Blender's smooth vertex normals of a polygon mesh: at each vertex, the sum of the face
// normals around it, each weighted by the face's corner angle there, normalised (a vertex
// of no face, or of zero-area faces only, gets (0, 0, 0)). Summed in fixed point, so the
// same faces in any order give the same bits (Blender sums floats in face order, and
// before 4.1 on threads in no fixed order). `loop_vertices` holds each loop's vertex; polygon p
// owns loops loop_starts[p] .. loop_starts[p] + loop_totals[p] - 1; `face_normals` 3 floats a
// polygon. Throws std::invalid_argument naming the first index out of range.
std::vector<float> vertex_normals(const float* positions, size_t vertex_count,
                                  const uint32_t* loop_vertices, size_t loop_count,
                                  const uint32_t* loop_starts, const uint32_t* loop_totals,
                                  const float* face_normals, size_t polygon_count);

// Which triangles have zero area: the cross product of their edges (p1 - p0, p2 - p0),
// in double, exactly 0 (collinear or repeated corners). A triangle with a non-finite
// corner is not (its products are NaN). Throws std::invalid_argument for an index out of
// range.
std::vector<uint8_t> zero_area_triangles(const float* positions, size_t vertex_count,
                                         const uint32_t* triangles, size_t triangle_count);

}  // namespace whitted
