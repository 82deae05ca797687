// PLY output: header and body parsed back independently of the writer.
#include "mesh/ply_writer.h"

#include "core/error.h"
#include "tests/support/test_data.h"

#include <catch2/catch.hpp>

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace {

// A small mesh with distinct, non-round values: a tetrahedron.
sb::Mesh tetrahedron() {
  sb::Mesh m;
  m.vertices = {{0.125f, -0.5f, 1.75f}, {1.1f, 0.2f, 0.3f}, {-0.7f, 0.9f, 0.05f}, {0.33f, 0.44f, -1.5f}};
  m.normals = {{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, {0.6f, 0.8f, 0.0f}};
  m.triangles = {{{0, 1, 2}}, {{0, 3, 1}}, {{1, 3, 2}}, {{2, 3, 0}}};
  return m;
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Splits the file into header lines (up to and including end_header) and the body bytes.
std::vector<std::string> splitHeader(const std::string& file, std::string& body) {
  std::vector<std::string> lines;
  size_t pos = 0;
  for (;;) {
    const size_t eol = file.find('\n', pos);
    REQUIRE(eol != std::string::npos);
    lines.push_back(file.substr(pos, eol - pos));
    pos = eol + 1;
    if (lines.back() == "end_header") break;
  }
  body = file.substr(pos);
  return lines;
}

uint32_t le32(const std::string& s, size_t at) {
  uint32_t v = 0;
  for (int b = 3; b >= 0; --b) v = (v << 8) | static_cast<unsigned char>(s.at(at + size_t(b)));
  return v;
}

float leFloat(const std::string& s, size_t at) {
  const uint32_t bits = le32(s, at);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

bool hasLine(const std::vector<std::string>& lines, const std::string& line) {
  return std::find(lines.begin(), lines.end(), line) != lines.end();
}

}  // namespace

TEST_CASE("binary PLY round trip", "[mesh][ply]") {
  const sb::Mesh mesh = tetrahedron();
  const std::string path = sb::test::scratchDir("mesh_ply_binary") + "/tetra.ply";
  sb::writePly(path, mesh);
  std::string body;
  const auto header = splitHeader(readAll(path), body);
  REQUIRE(header.at(0) == "ply");
  CHECK(header.at(1) == "format binary_little_endian 1.0");
  CHECK(hasLine(header, "element vertex 4"));
  CHECK(hasLine(header, "property float nz"));
  CHECK(hasLine(header, "element face 4"));
  CHECK(hasLine(header, "property list uchar uint vertex_indices"));

  constexpr size_t kVertexBytes = 6 * 4, kFaceBytes = 1 + 3 * 4;
  REQUIRE(body.size() == 4 * kVertexBytes + 4 * kFaceBytes);
  for (size_t i = 0; i < 4; ++i)
    for (int a = 0; a < 3; ++a) {
      CHECK(leFloat(body, i * kVertexBytes + size_t(a) * 4) == mesh.vertices[i][a]);
      CHECK(leFloat(body, i * kVertexBytes + 12 + size_t(a) * 4) == mesh.normals[i][a]);
    }
  for (size_t f = 0; f < 4; ++f) {
    const size_t at = 4 * kVertexBytes + f * kFaceBytes;
    CHECK(static_cast<unsigned char>(body[at]) == 3);
    for (size_t k = 0; k < 3; ++k) CHECK(le32(body, at + 1 + 4 * k) == mesh.triangles[f][k]);
  }
}

TEST_CASE("ASCII PLY round trip, and a mesh without normals", "[mesh][ply]") {
  sb::Mesh mesh = tetrahedron();
  mesh.normals.clear();
  const std::string path = sb::test::scratchDir("mesh_ply_ascii") + "/tetra.ply";
  sb::writePly(path, mesh, sb::PlyFormat::Ascii);
  std::string body;
  const auto header = splitHeader(readAll(path), body);
  CHECK(header.at(1) == "format ascii 1.0");
  CHECK(!hasLine(header, "property float nx"));
  std::istringstream in(body);
  for (const auto& v : mesh.vertices) {
    float x, y, z;
    REQUIRE(in >> x >> y >> z);
    CHECK(Eigen::Vector3f(x, y, z) == v);
  }
  for (const auto& t : mesh.triangles) {
    int n;
    uint32_t a, b, c;
    REQUIRE(in >> n >> a >> b >> c);
    CHECK(n == 3);
    CHECK(std::array<uint32_t, 3>{a, b, c} == t);
  }
  std::string rest;
  CHECK(!(in >> rest));
}

TEST_CASE("PLY errors name the file", "[mesh][ply]") {
  const std::string dir = sb::test::scratchDir("mesh_ply_errors");
  SECTION("missing directory") {
    const std::string path = dir + "/no_such_dir/out.ply";
    try {
      sb::writePly(path, tetrahedron());
      FAIL("writePly did not throw");
    } catch (const sb::Error& e) {
      CHECK(std::string(e.what()).find(path) != std::string::npos);
    }
  }
  SECTION("inconsistent mesh") {
    sb::Mesh bad = tetrahedron();
    bad.triangles.push_back({{0, 1, 7}});
    CHECK_THROWS_AS(sb::writePly(dir + "/bad.ply", bad), sb::Error);
    bad = tetrahedron();
    bad.normals.pop_back();
    CHECK_THROWS_AS(sb::writePly(dir + "/bad.ply", bad), sb::Error);
  }
}
