// The mesh: shading normals per corner or per vertex, validation, memory layout.
#include "scene/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "integrator/render.h"
#include "scene_builders.h"

namespace whitted {
namespace {

using testing::add_object;
using testing::looking_down;
using testing::quad;

// Two triangles over four shared vertices.
const float kPositions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
const uint32_t kTriangles[] = {0, 1, 2, 1, 3, 2};

TEST(Mesh, AFlatMeshHasNoCornerNormals) {
  const Mesh mesh = quad(-1, 1, -1, 1, 0);
  EXPECT_FALSE(mesh.has_normals());
  Vec3 n0(7.0f), n1(7.0f), n2(7.0f);
  EXPECT_FALSE(mesh.corner_normals(1, &n0, &n1, &n2));
  EXPECT_EQ(n0, Vec3(7.0f));  // untouched
}

TEST(Mesh, CornerNormalsAreStoredPerTriangleCorner) {
  std::vector<float> normals(18);
  for (size_t i = 0; i < normals.size(); ++i) normals[i] = static_cast<float>(i);
  const Mesh mesh = make_mesh(kPositions, 4, kTriangles, 2, normals.data(), nullptr);
  Vec3 n0, n1, n2;
  ASSERT_TRUE(mesh.corner_normals(1, &n0, &n1, &n2));
  EXPECT_EQ(n0, Vec3(9, 10, 11));
  EXPECT_EQ(n1, Vec3(12, 13, 14));
  EXPECT_EQ(n2, Vec3(15, 16, 17));
}

TEST(Mesh, VertexNormalsAreIndexedLikePositions) {
  const float vertex_normals[] = {0, 0, 1, 0, 1, 0, 1, 0, 0, 0, 0.6f, 0.8f};
  const Mesh mesh =
      make_mesh(kPositions, 4, kTriangles, 2, nullptr, nullptr, nullptr, vertex_normals);
  EXPECT_TRUE(mesh.has_normals());
  EXPECT_TRUE(mesh.normals.empty());
  Vec3 n0, n1, n2;
  ASSERT_TRUE(mesh.corner_normals(1, &n0, &n1, &n2));  // vertices 1, 3, 2
  EXPECT_EQ(n0, Vec3(0, 1, 0));
  EXPECT_EQ(n1, Vec3(0, 0.6f, 0.8f));
  EXPECT_EQ(n2, Vec3(1, 0, 0));
}

TEST(Mesh, TakesCornerOrVertexNormalsNotBoth) {
  const std::vector<float> corner(18, 0.5f);
  const std::vector<float> vertex(12, 0.5f);
  EXPECT_THROW(
      make_mesh(kPositions, 4, kTriangles, 2, corner.data(), nullptr, nullptr, vertex.data()),
      std::invalid_argument);
}

TEST(Mesh, NonFiniteNormalsAndUvsBecomeZero) {
  const float nan = std::nanf("");
  const float inf = INFINITY;
  const float vertex_normals[] = {nan, 0, 1, 0, inf, 0, 1, 0, 0, 0, 0, 1};
  std::vector<float> uvs(12, 0.25f);
  uvs[5] = nan;
  const Mesh mesh =
      make_mesh(kPositions, 4, kTriangles, 2, nullptr, nullptr, uvs.data(), vertex_normals);
  EXPECT_EQ(mesh.vertex_normals, (std::vector<float>{0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1}));
  EXPECT_EQ(mesh.uvs[5], 0.0f);
  EXPECT_EQ(mesh.uvs[4], 0.25f);
}

// The padding float Embree reads is reserved up front: pushing it does not double the
// array (which would cost 12 bytes a vertex for nothing).
TEST(Mesh, PositionsHoldNoSpareCapacity) {
  const Mesh mesh = make_mesh(kPositions, 4, kTriangles, 2, nullptr, nullptr);
  EXPECT_EQ(mesh.positions.size(), 13u);
  EXPECT_EQ(mesh.positions.capacity(), 13u);
  EXPECT_EQ(mesh.vertex_count(), 4u);
}

// A coarse UV sphere with shared vertices: positions, triangles and, on a unit sphere,
// vertex normals equal to the positions.
struct IndexedSphere {
  std::vector<float> positions;
  std::vector<uint32_t> triangles;
};

IndexedSphere indexed_sphere(int rings, int segments) {
  IndexedSphere s;
  for (int r = 0; r <= rings; ++r) {
    for (int k = 0; k < segments; ++k) {
      const float theta = kPi * static_cast<float>(r) / static_cast<float>(rings);
      const float phi = 2.0f * kPi * static_cast<float>(k) / static_cast<float>(segments);
      s.positions.insert(s.positions.end(), {std::sin(theta) * std::cos(phi),
                                             std::sin(theta) * std::sin(phi), std::cos(theta)});
    }
  }
  const auto index = [&](int r, int k) {
    return static_cast<uint32_t>(r * segments + k % segments);
  };
  for (int r = 0; r < rings; ++r) {
    for (int k = 0; k < segments; ++k) {
      const uint32_t a = index(r, k), b = index(r + 1, k), c = index(r + 1, k + 1),
                     d = index(r, k + 1);
      if (r > 0) s.triangles.insert(s.triangles.end(), {a, b, d});          // not at the north pole
      if (r < rings - 1) s.triangles.insert(s.triangles.end(), {b, c, d});  // nor the south
    }
  }
  return s;
}

std::vector<float> render_sphere(Mesh mesh) {
  Scene scene;
  Material white;
  white.ambient = 0.0f;
  white.specular = Color(0.3f);
  add_object(&scene, "sphere", std::move(mesh), white);
  Light sun;
  sun.type = LightType::kSun;
  sun.color = Color(3.0f);
  sun.direction = glm::normalize(Vec3(-1.0f, 0.2f, -0.15f));  // grazing: the terminator lift
  scene.set_light("sun", sun);
  scene.camera = looking_down(Vec3(0.0f, 0.0f, 6.0f), 0.2f);
  Settings settings;
  settings.width = 48;
  settings.height = 48;
  RenderJob job(scene, settings, scene.camera);
  testing::run_to_end(job);
  return job.film().pixels();
}

// A smooth mesh stored with one normal per vertex renders bit for bit as the same mesh
// with those normals copied to every corner: shading, and the shadow-terminator lift.
TEST(Mesh, VertexNormalsShadeExactlyAsTheSameCornerNormals) {
  const IndexedSphere s = indexed_sphere(6, 10);
  const size_t vertices = s.positions.size() / 3;
  const size_t triangles = s.triangles.size() / 3;
  std::vector<float> corners;
  for (uint32_t v : s.triangles) {
    corners.insert(corners.end(), s.positions.begin() + 3 * v, s.positions.begin() + 3 * v + 3);
  }
  const std::vector<float> by_corner = render_sphere(make_mesh(
      s.positions.data(), vertices, s.triangles.data(), triangles, corners.data(), nullptr));
  const std::vector<float> by_vertex =
      render_sphere(make_mesh(s.positions.data(), vertices, s.triangles.data(), triangles, nullptr,
                              nullptr, nullptr, s.positions.data()));
  const std::vector<float> flat = render_sphere(
      make_mesh(s.positions.data(), vertices, s.triangles.data(), triangles, nullptr, nullptr));
  EXPECT_EQ(by_vertex, by_corner);
  EXPECT_NE(flat, by_corner);  // the normals do shade
}

// A unit cube's six quads: every corner has three right angles, so each vertex normal is
// the normalised sum of its three faces' normals, the direction of the vertex itself.
TEST(MeshVertexNormals, ACubeCornerIsTheMeanOfItsThreeFaces) {
  std::vector<float> positions;
  for (int v = 0; v < 8; ++v) {
    positions.insert(positions.end(),
                     {v & 1 ? 1.0f : -1.0f, v & 2 ? 1.0f : -1.0f, v & 4 ? 1.0f : -1.0f});
  }
  const std::vector<uint32_t> loops = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4,
                                       2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
  const std::vector<uint32_t> starts = {0, 4, 8, 12, 16, 20};
  const std::vector<uint32_t> totals(6, 4);
  const std::vector<float> faces = {0, 0, -1, 0, 0, 1, 0, -1, 0, 0, 1, 0, -1, 0, 0, 1, 0, 0};
  const std::vector<float> normals = vertex_normals(positions.data(), 8, loops.data(), 24,
                                                    starts.data(), totals.data(), faces.data(), 6);
  ASSERT_EQ(normals.size(), 24u);
  for (size_t i = 0; i < 24; ++i) {
    EXPECT_NEAR(normals[i], positions[i] / std::sqrt(3.0f), 1e-7f) << i;
  }
}

// Two faces meet at vertex 0 with corner angles of 90 and 45 degrees: their normals are
// weighted 2:1 (Blender's weighting by angle, not by area or count).
TEST(MeshVertexNormals, FacesAreWeightedByTheirCornerAngle) {
  const float positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1};
  // Face 0: (0, 1, 2) in z = 0, right angle at vertex 0. Face 1: (0, 3, 4) in x = 0, 45
  // degrees at vertex 0.
  const uint32_t loops[] = {0, 1, 2, 0, 3, 4};
  const uint32_t starts[] = {0, 3};
  const uint32_t totals[] = {3, 3};
  const float faces[] = {0, 0, 1, 1, 0, 0};
  const std::vector<float> n = vertex_normals(positions, 5, loops, 6, starts, totals, faces, 2);
  const float length = std::sqrt(0.25f + 1.0f / 16.0f);
  EXPECT_NEAR(n[0], 0.25f / length, 1e-6f);  // x: face 1 with pi/4
  EXPECT_NEAR(n[1], 0.0f, 1e-7f);
  EXPECT_NEAR(n[2], 0.5f / length, 1e-6f);  // z: face 0 with pi/2
}

// One closed mesh, its faces listed in shuffled orders (Blender's UV sphere operator hands
// over the same faces in a new order each time): every normal keeps its bits.
TEST(MeshVertexNormals, TheSameFacesInAnyOrderGiveTheSameBits) {
  // A 24 x 12 UV sphere of quads, its vertices jittered so the corner angles all differ.
  constexpr uint32_t kSegments = 24, kRings = 12;
  std::mt19937 random(5);
  std::uniform_real_distribution<float> jitter(-0.02f, 0.02f);
  std::vector<float> positions;
  for (uint32_t i = 0; i <= kRings; ++i) {
    for (uint32_t j = 0; j < kSegments; ++j) {
      const double theta = kPi * i / kRings, phi = 2.0 * kPi * j / kSegments;
      positions.insert(positions.end(),
                       {static_cast<float>(std::sin(theta) * std::cos(phi)) + jitter(random),
                        static_cast<float>(std::sin(theta) * std::sin(phi)) + jitter(random),
                        static_cast<float>(std::cos(theta)) + jitter(random)});
    }
  }
  std::vector<std::array<uint32_t, 4>> quads;
  for (uint32_t i = 0; i < kRings; ++i) {
    for (uint32_t j = 0; j < kSegments; ++j) {
      const uint32_t a = i * kSegments + j, b = i * kSegments + (j + 1) % kSegments;
      quads.push_back({a, a + kSegments, b + kSegments, b});
    }
  }
  const auto normals_in = [&](const std::vector<std::array<uint32_t, 4>>& order) {
    std::vector<uint32_t> loops, starts, totals(order.size(), 4);
    std::vector<float> faces;
    for (const auto& quad : order) {
      starts.push_back(static_cast<uint32_t>(loops.size()));
      loops.insert(loops.end(), quad.begin(), quad.end());
      // The face normal of the quad's diagonals, as Blender's is its own per face.
      const auto at = [&](int k) {
        return glm::vec3(positions[3 * quad[k]], positions[3 * quad[k] + 1],
                         positions[3 * quad[k] + 2]);
      };
      const glm::vec3 n = glm::normalize(glm::cross(at(2) - at(0), at(3) - at(1)));
      faces.insert(faces.end(), {n.x, n.y, n.z});
    }
    return vertex_normals(positions.data(), positions.size() / 3, loops.data(), loops.size(),
                          starts.data(), totals.data(), faces.data(), order.size());
  };
  const std::vector<float> expected = normals_in(quads);
  for (int trial = 0; trial < 8; ++trial) {
    std::shuffle(quads.begin(), quads.end(), random);
    ASSERT_EQ(normals_in(quads), expected) << trial;
  }
}

TEST(MeshVertexNormals, AVertexOfNoFaceGetsZero) {
  const float positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5};
  const uint32_t loops[] = {0, 1, 2};
  const uint32_t starts[] = {0};
  const uint32_t totals[] = {3};
  const float faces[] = {0, 0, 1};
  const std::vector<float> n = vertex_normals(positions, 4, loops, 3, starts, totals, faces, 1);
  EXPECT_EQ(n[2], 1.0f);
  EXPECT_EQ(n[9], 0.0f);
  EXPECT_EQ(n[10], 0.0f);
  EXPECT_EQ(n[11], 0.0f);
}

TEST(MeshVertexNormals, IndicesOutOfRangeThrow) {
  const float positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint32_t bad_vertex[] = {0, 1, 3};
  const uint32_t loops[] = {0, 1, 2};
  const uint32_t starts[] = {0};
  const uint32_t totals[] = {3};
  const uint32_t too_many[] = {4};
  const float faces[] = {0, 0, 1};
  EXPECT_THROW(vertex_normals(positions, 3, bad_vertex, 3, starts, totals, faces, 1),
               std::invalid_argument);
  EXPECT_THROW(vertex_normals(positions, 3, loops, 3, starts, too_many, faces, 1),
               std::invalid_argument);
}

TEST(MeshZeroArea, OnlyTrianglesWhoseEdgeCrossProductIsExactlyZero) {
  const float nan = std::nanf("");
  const float positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, nan, 0, 0, 1e-30f, 1e-30f, 0};
  const uint32_t triangles[] = {
      0, 1, 2,  // a right triangle
      0, 1, 3,  // collinear
      0, 0, 2,  // a repeated corner
      0, 1, 4,  // a NaN corner: not zero area (dropped as non-finite instead)
      0, 1, 5,  // a sliver whose cross product is tiny, not zero in double
  };
  const std::vector<uint8_t> zero = zero_area_triangles(positions, 6, triangles, 5);
  EXPECT_EQ(zero, (std::vector<uint8_t>{0, 1, 1, 0, 0}));
  const uint32_t bad[] = {0, 1, 6};
  EXPECT_THROW(zero_area_triangles(positions, 6, bad, 1), std::invalid_argument);
}

}  // namespace
}  // namespace whitted
