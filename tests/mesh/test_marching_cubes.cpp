// Known-answer tests of extractMesh on analytic signed distance fields (sphere, plane), and the same mesh in
// pieces (mesh/mesh_pieces.h).
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <utility>

#include "core/error.h"
#include "core/thread_pool.h"
#include "mesh/marching_cubes.h"
#include "mesh/mesh_pieces.h"
#include "mesh/ply_writer.h"
#include "tests/mesh/analytic_volume.h"
#include "tests/support/test_data.h"

using sb::test::AnalyticVolume;

namespace {

constexpr int kResolution = 64;
constexpr float kSizeMeters = 2.0f;
constexpr double kMuMeters = 0.1;
constexpr int16_t kWeight = 10;
constexpr double kPi = 3.14159265358979323846;
const Eigen::Vector3d kSphereCentre(1.013, 0.988, 1.007);  // off the voxel grid on purpose
constexpr double kSphereRadius = 0.6;

double sphereSdf(const Eigen::Vector3d& p) { return (p - kSphereCentre).norm() - kSphereRadius; }

AnalyticVolume sphereVolume() {
  AnalyticVolume v(kResolution, kSizeMeters);
  v.fill(sphereSdf, kMuMeters, kWeight);
  return v;
}

double triangleArea(const sb::Mesh& m, const std::array<uint32_t, 3>& t) {
  const Eigen::Vector3d a = m.vertices[t[0]].cast<double>(), b = m.vertices[t[1]].cast<double>(),
                        c = m.vertices[t[2]].cast<double>();
  return 0.5 * (b - a).cross(c - a).norm();
}

// Signed volume enclosed by the mesh (divergence theorem); positive when triangles face outwards.
double enclosedVolume(const sb::Mesh& m) {
  double v = 0.0;
  for (const auto& t : m.triangles)
    v += m.vertices[t[0]].cast<double>().dot(m.vertices[t[1]].cast<double>().cross(m.vertices[t[2]].cast<double>())) / 6.0;
  return v;
}

bool sameMesh(const sb::Mesh& a, const sb::Mesh& b) {
  return a.vertices == b.vertices && a.normals == b.normals && a.triangles == b.triangles;
}

}  // namespace

TEST_CASE("sphere: vertices on the surface, outward normals", "[mesh]") {
  const AnalyticVolume vol = sphereVolume();
  const sb::Mesh mesh = sb::extractMesh(vol.view());
  REQUIRE(mesh.vertices.size() > 1000);
  REQUIRE(mesh.normals.size() == mesh.vertices.size());
  double worstDistance = 0.0, worstNormalDot = 1.0;
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d p = mesh.vertices[i].cast<double>();
    worstDistance = std::max(worstDistance, std::abs(sphereSdf(p)));
    worstNormalDot = std::min(worstNormalDot, mesh.normals[i].cast<double>().dot((p - kSphereCentre).normalized()));
  }
  // Linear interpolation of a curved SDF along an edge errs by O(voxel^2 / radius).
  CHECK(worstDistance < 0.1 * vol.voxel());
  CHECK(worstNormalDot > 0.99);
  // Every triangle faces outwards too.
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>(), b = mesh.vertices[t[1]].cast<double>(),
                          c = mesh.vertices[t[2]].cast<double>();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() > 1e-12) REQUIRE(n.dot(a - kSphereCentre) > 0.0);
  }
}

TEST_CASE("sphere: closed, welded, genus 0, area and volume match", "[mesh]") {
  const AnalyticVolume vol = sphereVolume();
  const sb::Mesh mesh = sb::extractMesh(vol.view());
  REQUIRE(!mesh.triangles.empty());
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const auto& t : mesh.triangles) {
    REQUIRE(t[0] != t[1]);
    REQUIRE(t[1] != t[2]);
    REQUIRE(t[0] != t[2]);
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  }
  // Closed and consistently oriented: every directed edge once, and its reverse exactly once.
  size_t undirectedEdges = 0;
  for (const auto& [edge, count] : directed) {
    REQUIRE(count == 1);
    REQUIRE(directed.count({edge.second, edge.first}) == 1);
    if (edge.first < edge.second) ++undirectedEdges;
  }
  // Welded: Euler characteristic of a sphere (V - E + F = 2) only holds if shared vertices are shared.
  const long euler = long(mesh.vertices.size()) - long(undirectedEdges) + long(mesh.triangles.size());
  CHECK(euler == 2);

  double area = 0.0;
  for (const auto& t : mesh.triangles) area += triangleArea(mesh, t);
  const double r = kSphereRadius;
  CHECK(area == Approx(4.0 * kPi * r * r).epsilon(0.02));
  CHECK(enclosedVolume(mesh) == Approx(4.0 / 3.0 * kPi * r * r * r).epsilon(0.02));
}

TEST_CASE("plane: exact vertices and normals for a linear SDF", "[mesh]") {
  const Eigen::Vector3d n = Eigen::Vector3d(1.0, 2.0, -2.0).normalized();
  const Eigen::Vector3d onPlane(1.04, 0.97, 1.01);
  auto planeSdf = [&](const Eigen::Vector3d& p) { return n.dot(p - onPlane); };
  AnalyticVolume vol(kResolution, kSizeMeters);
  vol.fill(planeSdf, kMuMeters, kWeight);
  const sb::Mesh mesh = sb::extractMesh(vol.view());
  REQUIRE(mesh.vertices.size() > 1000);
  double worstDistance = 0.0, worstNormalDot = 1.0;
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    worstDistance = std::max(worstDistance, std::abs(planeSdf(mesh.vertices[i].cast<double>())));
    worstNormalDot = std::min(worstNormalDot, mesh.normals[i].cast<double>().dot(n));
  }
  CHECK(worstDistance < 1e-3 * vol.voxel());
  CHECK(worstNormalDot > 0.9999);
  // The plane crosses the whole cube: the mesh area is the area of that cross-section minus a border of
  // at most one cell, so it lies between the area of the cut through the inner cube of voxel centres and
  // the full cube's cut; a loose lower bound of half the full cube face is enough to catch missing parts.
  double area = 0.0;
  for (const auto& t : mesh.triangles) area += triangleArea(mesh, t);
  CHECK(area > 0.5 * kSizeMeters * kSizeMeters);
}

TEST_CASE("unobserved voxels produce no surface", "[mesh]") {
  SECTION("all weights 0") {
    AnalyticVolume vol(kResolution, kSizeMeters);
    vol.fill(sphereSdf, kMuMeters, 0);
    const sb::Mesh mesh = sb::extractMesh(vol.view());
    CHECK(mesh.vertices.empty());
    CHECK(mesh.triangles.empty());
  }
  SECTION("half observed: surface only where every cell corner was observed") {
    const int half = kResolution / 2;
    AnalyticVolume vol(kResolution, kSizeMeters);
    vol.fill(sphereSdf, kMuMeters, kWeight, [&](int x, int, int) { return x >= half; });
    const sb::Mesh mesh = sb::extractMesh(vol.view());
    REQUIRE(!mesh.triangles.empty());
    const float minX = (half + 0.5f) * vol.voxel();
    for (const auto& v : mesh.vertices) REQUIRE(v.x() >= minX - 1e-6f);
  }
  SECTION("minWeight drops voxels observed too few times") {
    const int half = kResolution / 2;
    AnalyticVolume low(kResolution, kSizeMeters), cut(kResolution, kSizeMeters);
    low.fill(sphereSdf, kMuMeters, 3);
    low.fill(sphereSdf, kMuMeters, 20, [&](int x, int, int) { return x >= half; });
    cut.fill(sphereSdf, kMuMeters, 20, [&](int x, int, int) { return x >= half; });
    sb::MeshOptions options;
    options.minWeight = 5;
    const sb::Mesh a = sb::extractMesh(low.view(), options);
    const sb::Mesh b = sb::extractMesh(cut.view());
    REQUIRE(!a.triangles.empty());
    CHECK(sameMesh(a, b));
    CHECK(sb::extractMesh(low.view()).triangles.size() > a.triangles.size());
  }
}

TEST_CASE("output is identical for 1 and 3 threads", "[mesh]") {
  const AnalyticVolume vol = sphereVolume();
  sb::ThreadPool one(1), three(3);
  const sb::Mesh a = sb::extractMesh(vol.view(), {}, one);
  const sb::Mesh b = sb::extractMesh(vol.view(), {}, three);
  REQUIRE(!a.triangles.empty());
  CHECK(sameMesh(a, b));
}

TEST_CASE("invalid volume views are rejected with sb::Error", "[mesh]") {
  const AnalyticVolume vol(4, 1.0f);
  sb::VolumeView v = vol.view();
  v.data = nullptr;
  CHECK_THROWS_AS(sb::extractMesh(v), sb::Error);
  v = vol.view();
  v.resolution = 1;
  CHECK_THROWS_AS(sb::extractMesh(v), sb::Error);
  v = vol.view();
  v.size = 0.0f;
  CHECK_THROWS_AS(sb::extractMesh(v), sb::Error);
}

TEST_CASE("transformMesh moves vertices and rotates normals", "[mesh]") {
  sb::Mesh mesh;
  mesh.vertices = {{1.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}};
  mesh.normals = {{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  mesh.triangles = {{{0, 1, 0}}};
  // 90 degrees about z, then +(10, 20, 30): (x, y, z) -> (-y + 10, x + 20, z + 30).
  const Eigen::Isometry3f T = Eigen::Translation3f(10.0f, 20.0f, 30.0f) *
                              Eigen::AngleAxisf(float(kPi / 2.0), Eigen::Vector3f::UnitZ());
  sb::transformMesh(mesh, T);
  CHECK((mesh.vertices[0] - Eigen::Vector3f(10.0f, 21.0f, 30.0f)).norm() < 1e-5f);
  CHECK((mesh.vertices[1] - Eigen::Vector3f(8.0f, 20.0f, 30.0f)).norm() < 1e-5f);
  CHECK((mesh.normals[0] - Eigen::Vector3f(0.0f, 1.0f, 0.0f)).norm() < 1e-6f);
  CHECK((mesh.normals[1] - Eigen::Vector3f(-1.0f, 0.0f, 0.0f)).norm() < 1e-6f);
  CHECK(mesh.triangles[0] == std::array<uint32_t, 3>{0, 1, 0});
}

TEST_CASE("a mesh in pieces is extractMesh's mesh, and written in pieces writePly's file, byte for byte",
          "[mesh]") {
  const AnalyticVolume vol = sphereVolume();
  const std::string dir = sb::test::scratchDir("mesh_pieces");
  std::filesystem::create_directories(dir);
  const auto bytesOf = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  sb::ThreadPool one(1), three(3);
  const sb::Mesh whole = sb::extractMesh(vol.view(), {}, one);
  REQUIRE(!whole.triangles.empty());
  sb::writePly(dir + "/whole.ply", whole);
  for (sb::ThreadPool* pool : {&one, &three}) {
    INFO(pool->threadCount() << " threads");
    sb::Mesh joined;
    size_t pieces = 0;
    sb::PlyPieceWriter ply(dir + "/pieces.ply");
    sb::extractMeshPieces(vol.view(), {}, *pool, [&](sb::Mesh& piece) {
      ++pieces;
      for (const auto& t : piece.triangles)
        for (uint32_t i : t) CHECK(i < joined.vertices.size() + piece.vertices.size());
      joined.vertices.insert(joined.vertices.end(), piece.vertices.begin(), piece.vertices.end());
      joined.normals.insert(joined.normals.end(), piece.normals.begin(), piece.normals.end());
      joined.triangles.insert(joined.triangles.end(), piece.triangles.begin(), piece.triangles.end());
      ply.add(piece);
    });
    CHECK(pieces > 2);  // 16 z-slabs in batches of 2 (1 thread) or 6 (3 threads)
    CHECK(sameMesh(joined, whole));
    CHECK(ply.triangles() == whole.triangles.size());
    ply.finish();
    CHECK(bytesOf(dir + "/pieces.ply") == bytesOf(dir + "/whole.ply"));
    CHECK_FALSE(std::filesystem::exists(dir + "/pieces.ply.vertices.tmp"));
    CHECK_FALSE(std::filesystem::exists(dir + "/pieces.ply.faces.tmp"));
  }
  // A piece whose triangle uses a vertex not yet written is refused, naming the file.
  sb::PlyPieceWriter bad(dir + "/bad.ply");
  sb::Mesh piece;
  piece.vertices.assign(3, Eigen::Vector3f::Zero());
  piece.normals.assign(3, Eigen::Vector3f::UnitZ());
  piece.triangles = {{0, 1, 3}};
  CHECK_THROWS_WITH(bad.add(piece), Catch::Contains("bad.ply") && Catch::Contains("uses vertex 3"));
}
