// Mesh import/export without GL (label unit).

#include "hcpf/renderer/mesh.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "hcpf/core/error.h"
#include "support/crafted_glb.h"

namespace hcpf::renderer {
namespace {

// This process's scratch folder, by pid: ctest runs each test in its own
// process, two at a time (it was named by gtest's random seed, which two
// processes started in the same millisecond share, and never removed: every
// test run left one in /tmp).
std::filesystem::path TempDirPath() {
  return std::filesystem::temp_directory_path() / fmt::format("hcpf_mesh_test_{}", ::getpid());
}

std::filesystem::path TempDir() {
  const auto dir = TempDirPath();
  std::filesystem::create_directories(dir);
  return dir;
}

// Removes the scratch folder when the process's tests have run.
class RemoveTempDir : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(TempDirPath(), ec);
  }
};
[[maybe_unused]] ::testing::Environment* const kRemoveTempDir =
    ::testing::AddGlobalTestEnvironment(new RemoveTempDir);

std::string Asset(const std::string& name) {
  return std::string(HCPF_SOURCE_DIR) + "/assets/vehicles/" + name;
}

// Writes an OBJ in the y-up file convention, written here independently of
// the library: file (X, Y, Z) = model (y, z, x).
void WriteObj(const MeshData& mesh, const std::string& path) {
  std::ofstream out(path);
  for (const Eigen::Vector3f& p : mesh.positions) {
    out << fmt::format("v {:.7g} {:.7g} {:.7g}\n", p.y(), p.z(), p.x());
  }
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    out << fmt::format("f {} {} {}\n", mesh.indices[t] + 1, mesh.indices[t + 1] + 1,
                       mesh.indices[t + 2] + 1);
  }
}

MeshData Box4x2x15() {
  // 4 m long (x), 2 m wide (y), 1.5 m high (z), standing on z = 0.
  return MeshBuilder().AddBox({-2.0f, -1.0f, 0.0f}, {2.0f, 1.0f, 1.5f}, {1, 1, 1}).Take();
}

TEST(MeshBuilder, BoxHasTwelveTrianglesAndOutwardWinding) {
  const MeshData box = Box4x2x15();
  EXPECT_EQ(box.triangle_count(), 12u);  // 6 faces x 2
  EXPECT_EQ(box.vertex_count(), 24u);    // 4 per face (flat normals)
  for (size_t t = 0; t < box.indices.size(); t += 3) {
    const Eigen::Vector3f& a = box.positions[box.indices[t]];
    const Eigen::Vector3f g =
        (box.positions[box.indices[t + 1]] - a).cross(box.positions[box.indices[t + 2]] - a);
    const Eigen::Vector3f centre(0.0f, 0.0f, 0.75f);
    // Counter-clockwise seen from outside: the geometric normal points away
    // from the box centre, and agrees with the stored normal.
    EXPECT_GT(g.dot(a - centre), 0.0f);
    EXPECT_GT(g.dot(box.normals[box.indices[t]]), 0.0f);
  }
}

TEST(MeshBuilder, CylinderWindingIsOutward) {
  const MeshData c = MeshBuilder().AddCylinder({0, 0, 0}, {0, 0, 2}, 1.0f, 8, {1, 1, 1}).Take();
  // 8 side quads (16 triangles) + two octagon fans (6 triangles each).
  EXPECT_EQ(c.triangle_count(), 28u);
  for (size_t t = 0; t < c.indices.size(); t += 3) {
    const Eigen::Vector3f& a = c.positions[c.indices[t]];
    const Eigen::Vector3f g =
        (c.positions[c.indices[t + 1]] - a).cross(c.positions[c.indices[t + 2]] - a);
    EXPECT_GT(g.dot(c.normals[c.indices[t]]), 0.0f);
  }
}

TEST(MeshData, ClosedMeansEveryEdgeIsMatchedByItsReverse) {
  // Boxes and capped cylinders bound solids (their faces share corner
  // positions, not vertices: the weld joins them), and so do several of them.
  EXPECT_TRUE(Box4x2x15().IsClosed());
  EXPECT_TRUE(
      MeshBuilder().AddCylinder({0, 0, 0}, {0, 0, 2}, 1.0f, 8, {1, 1, 1}).Take().IsClosed());
  MeshData two = Box4x2x15();
  two.Append(MeshBuilder().AddBox({5.0f, 0.0f, 0.0f}, {6.0f, 1.0f, 3.0f}, {1, 1, 1}).Take());
  EXPECT_TRUE(two.IsClosed());
  EXPECT_TRUE(MeshData().IsClosed());
  // A box without its top face has a hole; one with a face wound inwards
  // has edges that run the same way as their neighbours'.
  MeshData open = Box4x2x15();
  for (size_t t = 0; t < open.indices.size(); t += 3) {
    const auto top = [&](size_t k) { return open.positions[open.indices[t + k]].z() > 1.4f; };
    if (top(0) && top(1) && top(2)) {
      open.indices.erase(open.indices.begin() + static_cast<ptrdiff_t>(t),
                         open.indices.begin() + static_cast<ptrdiff_t>(t + 3));
      t -= 3;
    }
  }
  EXPECT_EQ(open.triangle_count(), 10u);
  EXPECT_FALSE(open.IsClosed());
  MeshData flipped = Box4x2x15();
  std::swap(flipped.indices[1], flipped.indices[2]);
  std::swap(flipped.indices[4], flipped.indices[5]);
  EXPECT_FALSE(flipped.IsClosed());
  // Corners a millimetre apart on a 4 m box are a gap, not rounding.
  MeshData gap = Box4x2x15();
  for (size_t t = 0; t < 6; ++t) gap.positions[gap.indices[t]].z() += 1e-3f;
  EXPECT_FALSE(gap.IsClosed());
  // A single quad (a billboard, a sign) is open.
  MeshData quad;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  quad.indices = {0, 1, 2, 0, 2, 3};
  EXPECT_FALSE(quad.IsClosed());
  // Near float's range the extent overflows float (-3e38 .. 3e38): a
  // closed box stays closed and one with a gap of 1/600 of its size stays
  // open (computed in float, eps was infinite and the gap welded shut).
  MeshData huge = MeshBuilder().AddBox({-1, -1, -1}, {1, 1, 1}, {1, 1, 1}).Take();
  for (Eigen::Vector3f& p : huge.positions) p *= 3e38f;
  EXPECT_TRUE(huge.IsClosed());
  for (size_t t = 0; t < 6; ++t) huge.positions[huge.indices[t]].z() += 1e36f;
  EXPECT_FALSE(huge.IsClosed());
  // The stock vehicles are closed (so the shadow pass may cull their faces
  // turned away from the sun).
  for (const char* file : {"tank.glb", "truck.glb", "car.glb"}) {
    EXPECT_TRUE(LoadMesh(Asset(file)).IsClosed()) << file;
  }
}

TEST(MeshIo, GlbRoundTripKeepsDimensions) {
  const std::string path = (TempDir() / "box.glb").string();
  WriteGlb(Box4x2x15(), path);
  const MeshData loaded = LoadMesh(path);
  EXPECT_EQ(loaded.triangle_count(), 12u);
  const Eigen::Vector3d d = MeshDimensions(loaded);
  EXPECT_NEAR(d.x(), 4.0, 1e-6);
  EXPECT_NEAR(d.y(), 2.0, 1e-6);
  EXPECT_NEAR(d.z(), 1.5, 1e-6);
}

// A model's extents are floats; the scenario holds doubles. Widened as they
// are, 6.9f would be 6.900000095367432 in every resolved scenario (an audit
// found such dimensions in the reports); through the shortest decimal form
// they are the numbers the model was made with, and the same floats again.
TEST(MeshIo, DimensionsAreTheFloatsShortestDecimals) {
  MeshData mesh;
  mesh.positions = {{0.0f, -1.8f, 1.1f}, {6.9f, 1.8f, 3.3f}};
  const Eigen::Vector3d d = MeshDimensions(mesh);
  EXPECT_EQ(d.x(), 6.9);
  EXPECT_EQ(d.y(), 3.6);
  // 3.3f - 1.1f is 2.19999981f, and 3.3 - 1.1 in doubles 2.1999999999999997.
  ASSERT_NE(3.3f - 1.1f, 2.2f);
  EXPECT_EQ(d.z(), 2.2);
  EXPECT_EQ(static_cast<float>(d.x()), 6.9f);
  EXPECT_EQ(static_cast<float>(d.y()), 3.6f);
}

TEST(MeshIo, GlbIsWrittenYUp) {
  // Reads the GLB's JSON chunk directly: the POSITION accessor's max must be
  // (X, Y, Z)_gltf = (y, z, x)_model = (1, 1.5, 2) for the 4 x 2 x 1.5 box.
  const std::string path = (TempDir() / "box_axes.glb").string();
  WriteGlb(Box4x2x15(), path);
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 20u);
  uint32_t json_length = 0;
  std::memcpy(&json_length, bytes.data() + 12, 4);  // header 12 bytes, then chunk length
  ASSERT_LE(20u + json_length, bytes.size());
  const auto json = nlohmann::json::parse(std::string(bytes.data() + 20, json_length));
  const int pos = json["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
  const auto& max = json["accessors"][pos]["max"];
  EXPECT_NEAR(max[0].get<double>(), 1.0, 1e-6);
  EXPECT_NEAR(max[1].get<double>(), 1.5, 1e-6);
  EXPECT_NEAR(max[2].get<double>(), 2.0, 1e-6);
}

TEST(MeshIo, SameModelAsGlbAndObjHasSameTrianglesAndBounds) {
  const MeshData glb = LoadMesh(Asset("tank.glb"));
  const std::string obj_path = (TempDir() / "tank.obj").string();
  WriteObj(glb, obj_path);
  const MeshData obj = LoadMesh(obj_path);
  EXPECT_EQ(obj.triangle_count(), glb.triangle_count());
  const Eigen::AlignedBox3f a = glb.Bounds();
  const Eigen::AlignedBox3f b = obj.Bounds();
  // The OBJ stores 7 significant digits: 1e-5 m covers the rounding.
  EXPECT_TRUE(a.min().isApprox(b.min(), 1e-5f))
      << a.min().transpose() << " vs " << b.min().transpose();
  EXPECT_TRUE(a.max().isApprox(b.max(), 1e-5f))
      << a.max().transpose() << " vs " << b.max().transpose();
}

TEST(MeshIo, StockVehiclesHaveTheirDesignedDimensions) {
  // Worked out from the part lists in renderer/tools/make_vehicles.cc:
  // tank  x: track rear -3.4 .. barrel tip 3.5 = 6.9; y: tracks +-1.8 = 3.6;
  //       z: track bottom 0 .. hatch top 2.3.
  // truck x: -4.0 .. 4.0 = 8.0; y: cab/cargo +-1.25 = 2.5; z: wheel bottom
  //       0.5 - 0.5 = 0 .. cargo top 3.2.
  // car   x: +-2.25 = 4.5; y: wheels +-0.92 = 1.84; z: wheel bottom 0 .. roof 1.5.
  struct Case {
    const char* file;
    Eigen::Vector3d dims;
  };
  for (const Case& c : {Case{"tank.glb", {6.9, 3.6, 2.3}}, Case{"truck.glb", {8.0, 2.5, 3.2}},
                        Case{"car.glb", {4.5, 1.84, 1.5}}}) {
    const MeshData mesh = LoadMesh(Asset(c.file));
    const Eigen::Vector3d d = MeshDimensions(mesh);
    EXPECT_NEAR(d.x(), c.dims.x(), 1e-5) << c.file;
    EXPECT_NEAR(d.y(), c.dims.y(), 1e-5) << c.file;
    EXPECT_NEAR(d.z(), c.dims.z(), 1e-5) << c.file;
    // Origin at the centre of the base.
    const Eigen::AlignedBox3f b = mesh.Bounds();
    EXPECT_NEAR(b.min().z(), 0.0, 1e-5) << c.file;
    EXPECT_NEAR(b.center().x(), 0.0, 1e-5) << c.file;
    EXPECT_NEAR(b.center().y(), 0.0, 1e-5) << c.file;
  }
}

TEST(MeshIo, MissingFileIsAnInputErrorNamingTheFile) {
  try {
    LoadMesh("/nonexistent/model.glb");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/model.glb"), std::string::npos);
  }
}

TEST(MeshIo, CorruptFilesAndUnknownExtensionsAreInputErrors) {
  const auto dir = TempDir();
  for (const char* name : {"bad.glb", "bad.gltf", "bad.obj", "bad.xyz"}) {
    const std::string path = (dir / name).string();
    std::ofstream(path) << "this is not a model";
    try {
      LoadMesh(path);
      FAIL() << "expected InputError for " << name;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

// Issue 15, item 1: accessor fields chosen so that the old bounds arithmetic
// (begin + (count - 1) * stride + element size, in 64 bits) wrapped to a small
// number and passed, then read far outside the buffer (SIGSEGV) or 4 bytes
// before it. Each must be an InputError naming the file and the accessor.
TEST(MeshIo, CraftedGlbAccessorsThatWrapTheBoundsAreInputErrors) {
  const auto dir = TempDir();
  // Control: the crafted writer makes a valid triangle with sane fields, so
  // the failures below come from the fields alone.
  const std::string good = (dir / "good.glb").string();
  testing::WriteTriangleGlb(good, 3, 0);
  EXPECT_EQ(LoadMesh(good).triangle_count(), 1u);

  struct Case {
    const char* name;
    uint64_t count;
    uint64_t byte_offset;
  };
  for (const Case& c : {Case{"count_wraps.glb", 6148914691236517206ull, 0},    // ~2^64 / 3
                        Case{"offset_wraps.glb", 1, 18446744073709551612ull},  // 2^64 - 4
                        Case{"offset_past_view.glb", 1, 36}, Case{"one_too_many.glb", 4, 0}}) {
    const std::string path = (dir / c.name).string();
    testing::WriteTriangleGlb(path, c.count, c.byte_offset);
    try {
      LoadMesh(path);
      FAIL() << "expected InputError for " << c.name;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path), std::string::npos) << what;
      EXPECT_NE(what.find("POSITION accessor 0"), std::string::npos) << what;
      EXPECT_NE(what.find("reads past the end of buffer view 0"), std::string::npos) << what;
    }
  }
}

// fuzz_gltf found this: a BIN chunk whose length counts its own 8-byte header
// passes tinygltf 2.7's check, which then copies 8 bytes past the end of the
// file it read (heap-buffer-overflow under ASan; silently garbage without).
// It must be an InputError naming the file and the chunk.
TEST(MeshIo, GlbBinChunkRunningPastTheFileIsAnInputError) {
  const std::string path = (TempDir() / "bin_past_end.glb").string();
  testing::WriteTriangleGlb(path, 3, 0, 44);  // 36 bytes follow the header
  try {
    LoadMesh(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find("the BIN chunk claims 44 bytes but only 36 follow its header"),
              std::string::npos)
        << what;
  }
}

}  // namespace
}  // namespace hcpf::renderer
