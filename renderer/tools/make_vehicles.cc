// make_vehicles: builds the stock vehicle models (tank, truck, car) from boxes
// and cylinders and writes them as small binary glTF files.
//
//   make_vehicles OUT_DIR      (the repository's copies live in assets/vehicles/)
//
// Models follow the project's model convention (mesh.h): +x forward, +y left,
// +z up, metres, origin at the centre of the base. Colours are multiplied by a
// per-target tint at render time, so tintable body panels are near white and
// running gear / glass is dark.

#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include "hcpf/renderer/mesh.h"

namespace {

using hcpf::renderer::MeshBuilder;
using hcpf::renderer::MeshData;
using V = Eigen::Vector3f;

const V kBody{1.0f, 1.0f, 1.0f};
const V kBodyShade{0.85f, 0.85f, 0.85f};
const V kRunningGear{0.16f, 0.16f, 0.16f};
const V kGlass{0.22f, 0.27f, 0.33f};
const V kMetal{0.6f, 0.6f, 0.6f};
constexpr int kWheelSegments = 12;

// Moves the mesh so its bounds are centred in x and y and start at z = 0.
MeshData Recentre(MeshData mesh) {
  const Eigen::AlignedBox3f b = mesh.Bounds();
  const V offset(-0.5f * (b.min().x() + b.max().x()), -0.5f * (b.min().y() + b.max().y()),
                 -b.min().z());
  mesh.Transform(V::Ones(), offset);
  return mesh;
}

MeshData Tank() {
  MeshBuilder b;
  b.AddBox({-3.4f, 1.1f, 0.0f}, {3.4f, 1.8f, 1.0f}, kRunningGear);    // left track
  b.AddBox({-3.4f, -1.8f, 0.0f}, {3.4f, -1.1f, 1.0f}, kRunningGear);  // right track
  b.AddBox({-3.3f, -1.1f, 0.35f}, {3.2f, 1.1f, 1.0f}, kBodyShade);    // lower hull
  b.AddBox({-3.4f, -1.8f, 1.0f}, {3.3f, 1.8f, 1.35f}, kBody);         // upper hull + fenders
  b.AddBox({-1.8f, -1.25f, 1.35f}, {0.8f, 1.25f, 2.1f}, kBody);       // turret
  b.AddCylinder({-0.8f, 0.5f, 2.1f}, {-0.8f, 0.5f, 2.3f}, 0.35f, kWheelSegments, kBodyShade);
  b.AddCylinder({0.8f, 0.0f, 1.75f}, {3.5f, 0.0f, 1.75f}, 0.1f, kWheelSegments, kMetal);
  return Recentre(b.Take());
}

MeshData Truck() {
  MeshBuilder b;
  b.AddBox({-4.0f, -1.1f, 0.6f}, {4.0f, 1.1f, 1.0f}, kRunningGear);  // chassis
  for (float x : {-2.8f, -1.6f, 2.8f}) {
    b.AddCylinder({x, 0.85f, 0.5f}, {x, 1.25f, 0.5f}, 0.5f, kWheelSegments, kRunningGear);
    b.AddCylinder({x, -1.25f, 0.5f}, {x, -0.85f, 0.5f}, 0.5f, kWheelSegments, kRunningGear);
  }
  b.AddBox({2.2f, -1.25f, 1.0f}, {3.95f, 1.25f, 3.0f}, kBody);       // cab
  b.AddBox({3.95f, -1.0f, 2.1f}, {4.0f, 1.0f, 2.8f}, kGlass);        // windscreen
  b.AddBox({-4.0f, -1.25f, 1.0f}, {2.0f, 1.25f, 3.2f}, kBodyShade);  // cargo box
  return Recentre(b.Take());
}

MeshData Car() {
  MeshBuilder b;
  b.AddBox({-2.25f, -0.9f, 0.3f}, {2.25f, 0.9f, 0.85f}, kBody);  // lower body
  b.AddBox({-1.1f, -0.8f, 0.85f}, {0.8f, 0.8f, 1.45f}, kGlass);  // cabin (glass)
  b.AddBox({-1.0f, -0.78f, 1.45f}, {0.6f, 0.78f, 1.5f}, kBody);  // roof
  for (float x : {-1.4f, 1.4f}) {
    b.AddCylinder({x, 0.7f, 0.32f}, {x, 0.92f, 0.32f}, 0.32f, kWheelSegments, kRunningGear);
    b.AddCylinder({x, -0.92f, 0.32f}, {x, -0.7f, 0.32f}, 0.32f, kWheelSegments, kRunningGear);
  }
  return Recentre(b.Take());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_vehicles OUT_DIR\n");
    return 2;
  }
  try {
    const std::filesystem::path out(argv[1]);
    std::filesystem::create_directories(out);
    const std::pair<const char*, MeshData> models[] = {
        {"tank", Tank()}, {"truck", Truck()}, {"car", Car()}};
    for (const auto& [name, mesh] : models) {
      const std::string path = (out / fmt::format("{}.glb", name)).string();
      hcpf::renderer::WriteGlb(mesh, path);
      const Eigen::Vector3d d = hcpf::renderer::MeshDimensions(mesh);
      std::printf("%s: %zu vertices, %zu triangles, %.2f x %.2f x %.2f m (l x w x h)\n",
                  path.c_str(), mesh.vertex_count(), mesh.triangle_count(), d.x(), d.y(), d.z());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_vehicles: %s\n", e.what());
    return 1;
  }
  return 0;
}
