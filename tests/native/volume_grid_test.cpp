// Volume objects' grids (scene/vdb_file.h, volume_grid.h, volume_object.h; issue 48):
// grids written here with OpenVDB's own API, read back, and sampled: a constant block,
// trilinear interpolation between two voxels, the transform and the bounds, agreement
// with OpenVDB's BoxSampler half a voxel apart (Cycles' convention), vector grids, and
// files that cannot be read. One test measures sampling from two threads against
// OpenVDB's accessors (printed, not asserted).
#include <gtest/gtest.h>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/vdb_file.h"
#include "scene/volume_object.h"

namespace whitted {
namespace {

// A file in the test's own temporary folder, removed with it.
class VdbFile : public ::testing::Test {
 protected:
  void SetUp() override {
    openvdb::initialize();
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    folder_ = std::filesystem::temp_directory_path() /
              (std::string("whitted-vdb-") + info->name() + "-" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder_);
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  std::string write(const std::string& name, const openvdb::GridPtrVec& grids) const {
    openvdb::io::File file(path(name));
    file.write(grids);
    file.close();
    return path(name);
  }
  std::filesystem::path folder_;
};

std::shared_ptr<const VolumeGrid> read_one(const std::string& file, const std::string& name) {
  auto grids = read_vdb_grids(file, {name});
  EXPECT_EQ(grids.size(), 1u);
  return grids.at(0);
}

TEST_F(VdbFile, AConstantBlockSamplesItsValueInsideAndHalfwayAtItsFaces) {
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("density");
  // fill() stores aligned constant regions as tiles: the reader's tile path.
  grid->fill(openvdb::CoordBBox({0, 0, 0}, {15, 15, 15}), 2.0f, true);
  const auto read = read_one(write("block.vdb", {grid}), "density");
  EXPECT_EQ(read->active_voxels(), 16u * 16u * 16u);
  EXPECT_EQ(read->resolution(), glm::ivec3(16));
  for (const Vec3 p : {Vec3(0.5f), Vec3(8.0f), Vec3(15.5f), Vec3(3.2f, 11.7f, 0.9f)}) {
    EXPECT_FLOAT_EQ(read->sample(p).x, 2.0f) << p.x << " " << p.y << " " << p.z;
  }
  // The face x = 16 lies halfway between voxel 15's centre (2) and voxel 16's (0).
  EXPECT_FLOAT_EQ(read->sample(Vec3(16.0f, 8.0f, 8.0f)).x, 1.0f);
  EXPECT_FLOAT_EQ(read->sample(Vec3(0.0f, 8.0f, 8.0f)).x, 1.0f);
  EXPECT_FLOAT_EQ(read->sample(Vec3(16.5f, 8.0f, 8.0f)).x, 0.0f);
  EXPECT_FLOAT_EQ(read->sample(Vec3(-1e9f, 8.0f, 8.0f)).x, 0.0f);
  EXPECT_FLOAT_EQ(read->sample(Vec3(std::nanf(""), 8.0f, 8.0f)).x, 0.0f);
  const Box3 box = read->index_bounds();
  EXPECT_EQ(box.lower, Vec3(0.0f));
  EXPECT_EQ(box.upper, Vec3(16.0f));
}

TEST_F(VdbFile, TrilinearBetweenTwoVoxels) {
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("density");
  grid->tree().setValueOn({0, 0, 0}, 1.0f);
  grid->tree().setValueOn({1, 0, 0}, 3.0f);
  const auto read = read_one(write("two.vdb", {grid}), "density");
  EXPECT_EQ(read->active_voxels(), 2u);
  EXPECT_EQ(read->resolution(), glm::ivec3(2, 1, 1));
  for (float t : {0.0f, 0.25f, 0.5f, 0.9f, 1.0f}) {
    // From voxel 0's centre (0.5) to voxel 1's (1.5), on the line through both centres.
    EXPECT_NEAR(read->sample(Vec3(0.5f + t, 0.5f, 0.5f)).x, 1.0f + 2.0f * t, 1e-6f) << t;
  }
  // Half a voxel off the centres' line in y, the neighbours there are background (0).
  EXPECT_NEAR(read->sample(Vec3(1.0f, 1.0f, 0.5f)).x, 0.5f * 2.0f, 1e-6f);
}

TEST_F(VdbFile, ACellsVoxelsWeighedByTheirWeightsAreTheSample) {
  // Random voxels across a block's face (x = 8): cells inside one block and cells
  // straddling two. The eight weights sum to 1, their weighted voxels are the sample, and
  // a cell's voxels are the grid's voxels around the point.
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("temperature");
  std::mt19937 random(7);
  std::uniform_real_distribution<float> value(0.0f, 3.0f);
  for (int i = 4; i < 12; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) grid->tree().setValueOn({i, j, k}, value(random));
  const auto read = read_one(write("cell.vdb", {grid}), "temperature");
  std::uniform_real_distribution<float> x(3.0f, 13.0f), yz(0.0f, 4.5f);
  for (int n = 0; n < 200; ++n) {
    const Vec3 p(x(random), yz(random), yz(random));
    const VolumeGrid::Cell cell = read->cell(p);
    float weights = 0.0f, weighed = 0.0f;
    for (int c = 0; c < 8; ++c) {
      weights += cell.weight(c);
      weighed += cell.weight(c) * cell.values[c];
      const glm::ivec3 first(glm::floor(p - 0.5f));
      EXPECT_EQ(cell.values[c], read->voxel(first + glm::ivec3(c & 1, (c >> 1) & 1, c >> 2)).x);
    }
    EXPECT_NEAR(weights, 1.0f, 1e-6f);
    EXPECT_NEAR(weighed, read->sample(p).x, 1e-5f);
    EXPECT_EQ(cell.interpolated(), read->sample(p).x);
  }
  // Far away: eight backgrounds, the first at weight 1.
  const VolumeGrid::Cell far = read->cell(Vec3(-100.0f));
  EXPECT_EQ(far.values[5], 0.0f);
  EXPECT_EQ(far.weight(0), 1.0f);
}

TEST_F(VdbFile, TheTransformPlacesSamplesAndBoundsInTheWorld) {
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("density");
  grid->fill(openvdb::CoordBBox({0, 0, 0}, {7, 3, 1}), 1.0f, true);
  grid->tree().setValueOn({2, 1, 0}, 5.0f);
  // Voxels of 0.25 units, the grid moved by (1, 2, 3) in object space.
  auto transform = openvdb::math::Transform::createLinearTransform(0.25);
  transform->postTranslate(openvdb::Vec3d(1.0, 2.0, 3.0));
  grid->setTransform(transform);
  const auto read = read_one(write("placed.vdb", {grid}), "density");
  const Box3 local = read->object_bounds();
  EXPECT_NEAR(local.lower.x, 1.0f, 1e-6f);
  EXPECT_NEAR(local.upper.x, 1.0f + 8 * 0.25f, 1e-6f);
  EXPECT_NEAR(local.upper.y, 2.0f + 4 * 0.25f, 1e-6f);
  EXPECT_NEAR(local.upper.z, 3.0f + 2 * 0.25f, 1e-6f);
  // The object scaled by 2 and moved by (10, 0, 0) in the world.
  const glm::mat4 to_world = glm::scale(glm::translate(glm::mat4(1.0f), Vec3(10, 0, 0)), Vec3(2));
  VolumeObject::Grids grids;
  grids[static_cast<int>(GridRole::kDensity)] = read;
  const VolumeObject object(to_world, grids);
  const Box3 world = object.world_bounds();
  EXPECT_NEAR(world.lower.x, 10.0f + 2.0f * 1.0f, 1e-5f);
  EXPECT_NEAR(world.upper.x, 10.0f + 2.0f * 3.0f, 1e-5f);
  EXPECT_NEAR(world.lower.y, 4.0f, 1e-5f);
  EXPECT_NEAR(world.upper.z, 2.0f * 3.5f, 1e-5f);
  // Voxel (2, 1, 0)'s centre: object (1 + 2.5 * 0.25, 2 + 1.5 * 0.25, 3 + 0.5 * 0.25).
  const Vec3 centre(10.0f + 2.0f * 1.625f, 2.0f * 2.375f, 2.0f * 3.125f);
  EXPECT_NEAR(object.sample(centre).density, 5.0f, 1e-4f);
  EXPECT_NEAR(object.sample(centre + Vec3(0.0f, 0.0f, 2.0f * 0.25f)).density, 1.0f, 1e-4f);
  EXPECT_FLOAT_EQ(object.sample(Vec3(0.0f)).density, 0.0f);
  // Roles without a grid read as Principled Volume reads a missing attribute.
  EXPECT_EQ(object.sample(centre).color, Color(1.0f));
  EXPECT_FLOAT_EQ(object.sample(centre).temperature, 1.0f);
  EXPECT_FLOAT_EQ(object.sample(centre).flame, 0.0f);
}

// A smoke-like grid: a ball of density falling off to its edge over 64^3 voxels.
openvdb::FloatGrid::Ptr ball() {
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("density");
  auto accessor = grid->getAccessor();
  for (int x = 0; x < 64; ++x) {
    for (int y = 0; y < 64; ++y) {
      for (int z = 0; z < 64; ++z) {
        const float r =
            std::sqrt(float((x - 32) * (x - 32) + (y - 32) * (y - 32) + (z - 32) * (z - 32))) /
            30.0f;
        if (r < 1.0f) accessor.setValueOn({x, y, z}, (1.0f - r) * (1.0f + 0.3f * std::sin(x)));
      }
    }
  }
  return grid;
}

TEST_F(VdbFile, SamplesEqualOpenVdbsBoxSamplerHalfAVoxelApart) {
  const auto grid = ball();
  const auto read = read_one(write("ball.vdb", {grid}), "density");
  std::mt19937 random(7);
  std::uniform_real_distribution<float> u(-4.0f, 68.0f);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p(u(random), u(random), u(random));
    float expected = 0.0f;
    // OpenVDB's BoxSampler puts a voxel's value at its integer coordinates.
    openvdb::tools::BoxSampler::sample(grid->tree(),
                                       openvdb::Vec3R(p.x - 0.5, p.y - 0.5, p.z - 0.5), expected);
    ASSERT_NEAR(read->sample(p).x, expected, 1e-5f) << p.x << " " << p.y << " " << p.z;
  }
}

// Seconds for `threads` threads to sample n random points each, with `sample(p)`.
template <class Sample>
double timed(int threads, int n, const Sample& make_sampler) {
  std::vector<std::thread> workers;
  std::vector<float> sums(threads);
  const auto start = std::chrono::steady_clock::now();
  for (int t = 0; t < threads; ++t) {
    workers.emplace_back([&, t] {
      auto sample = make_sampler();
      std::mt19937 random(t);
      std::uniform_real_distribution<float> u(0.0f, 64.0f);
      float sum = 0.0f;
      for (int i = 0; i < n; ++i) sum += sample(Vec3(u(random), u(random), u(random)));
      sums[t] = sum;
    });
  }
  for (auto& worker : workers) worker.join();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

TEST_F(VdbFile, SamplingFromTwoThreadsMeasuredAgainstOpenVdbAccessors) {
  const auto grid = ball();
  const auto read = read_one(write("ball.vdb", {grid}), "density");
  constexpr int kThreads = 2;
  constexpr int kSamples = 2000000;
  const double ours =
      timed(kThreads, kSamples, [&] { return [&](const Vec3& p) { return read->sample(p).x; }; });
  // OpenVDB's fastest thread-safe way: one cached accessor per thread.
  const double accessor = timed(kThreads, kSamples, [&] {
    return [acc = grid->getConstAccessor()](const Vec3& p) mutable {
      float v = 0.0f;
      openvdb::tools::BoxSampler::sample(acc, openvdb::Vec3R(p.x - 0.5, p.y - 0.5, p.z - 0.5), v);
      return v;
    };
  });
  // Without per-thread state: the tree itself (a root-to-leaf walk per corner).
  const double tree = timed(kThreads, kSamples, [&] {
    return [&](const Vec3& p) {
      float v = 0.0f;
      openvdb::tools::BoxSampler::sample(grid->constTree(),
                                         openvdb::Vec3R(p.x - 0.5, p.y - 0.5, p.z - 0.5), v);
      return v;
    };
  });
  // Drawing the points alone, subtracted from the three.
  const double points = timed(kThreads, kSamples, [] { return [](const Vec3& p) { return p.x; }; });
  const double per = 1e9 / (double(kThreads) * kSamples);
  std::printf(
      "[ measure  ] trilinear samples of a 64^3 ball, %d threads x %d, beyond drawing the "
      "point (%.1f ns): blocks %.1f ns, OpenVDB per-thread accessor %.1f ns, OpenVDB tree "
      "%.1f ns a sample; blocks hold %zu bytes\n",
      kThreads, kSamples, points * per, (ours - points) * per, (accessor - points) * per,
      (tree - points) * per, read->bytes());
  EXPECT_GT(read->bytes(), read->active_voxels() * sizeof(float));
}

TEST_F(VdbFile, AVectorGridIsReadAsColour) {
  auto grid = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
  grid->setName("color");
  grid->fill(openvdb::CoordBBox({0, 0, 0}, {7, 7, 7}), openvdb::Vec3s(0.2f, 0.4f, 0.8f), true);
  auto density = openvdb::DoubleGrid::create(0.0);
  density->setName("density");
  density->tree().setValueOn({3, 3, 3}, 0.5);
  const std::string file = write("colour.vdb", {grid, density});
  const auto grids = vdb_grids(file);
  ASSERT_EQ(grids.size(), 2u);
  EXPECT_EQ(grids[0].name, "color");
  EXPECT_EQ(grids[0].value_type, "vec3s");
  EXPECT_TRUE(grids[0].readable);
  EXPECT_EQ(grids[1].value_type, "double");
  const auto read = read_vdb_grids(file, {"color", "density"});
  EXPECT_EQ(read[0]->channels(), 3);
  EXPECT_EQ(read[1]->channels(), 1);
  VolumeObject::Grids roles;
  roles[static_cast<int>(GridRole::kColor)] = read[0];
  roles[static_cast<int>(GridRole::kDensity)] = read[1];
  const VolumeObject object(glm::mat4(1.0f), roles);
  const VolumeSample s = object.sample(Vec3(3.5f));
  EXPECT_NEAR(s.color.x, 0.2f, 1e-6f);
  EXPECT_NEAR(s.color.z, 0.8f, 1e-6f);
  EXPECT_NEAR(s.density, 0.5f, 1e-6f);
  // A colour grid in a scalar role, and the other way round, are refused.
  VolumeObject::Grids swapped;
  swapped[static_cast<int>(GridRole::kDensity)] = read[0];
  EXPECT_THROW(VolumeObject(glm::mat4(1.0f), swapped), std::invalid_argument);
}

TEST_F(VdbFile, FilesThatCannotBeReadSayWhy) {
  const auto message = [](const auto& call) {
    try {
      call();
    } catch (const VolumeFileError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(
      message([&] { read_vdb_grids(path("missing.vdb"), {"density"}); }).find("does not exist"),
      std::string::npos);
  { std::ofstream(path("text.vdb")) << "not an OpenVDB file\n"; }
  EXPECT_NE(message([&] { vdb_grids(path("text.vdb")); }).find("not a readable OpenVDB file"),
            std::string::npos);
  auto ints = openvdb::Int32Grid::create(0);
  ints->setName("index");
  ints->tree().setValueOn({0, 0, 0}, 4);
  const std::string file = write("ints.vdb", {ints});
  EXPECT_FALSE(vdb_grids(file).at(0).readable);
  EXPECT_NE(message([&] { read_vdb_grids(file, {"index"}); }).find("holds int32 values"),
            std::string::npos);
  EXPECT_NE(message([&] { read_vdb_grids(file, {"density"}); }).find("has no grid named"),
            std::string::npos);
}

TEST_F(VdbFile, AnEmptyGridReadsAsBackgroundWithEmptyBounds) {
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("density");
  const auto read = read_one(write("empty.vdb", {grid}), "density");
  EXPECT_EQ(read->active_voxels(), 0u);
  EXPECT_EQ(read->resolution(), glm::ivec3(0));
  EXPECT_TRUE(read->object_bounds().empty());
  EXPECT_FLOAT_EQ(read->sample(Vec3(0.5f)).x, 0.0f);
  VolumeObject::Grids grids;
  grids[static_cast<int>(GridRole::kDensity)] = read;
  EXPECT_TRUE(VolumeObject(glm::mat4(1.0f), grids).world_bounds().empty());
}

}  // namespace
}  // namespace whitted
