// PLY output: header and body parsed back independently of the writer; a mesh written in pieces on a
// small disk.
#include "mesh/ply_writer.h"

#include <sys/mount.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include "core/disk_full.h"
#include "core/error.h"
#include "mesh/mesh_pieces.h"
#include "tests/support/test_data.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
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

TEST_CASE(
    "a mesh written in pieces takes its file's size on disk, not twice; a full disk leaves the old file",
    "[mesh][ply][disk]") {
  // Issue 53 (finding 8): PlyPieceWriter kept the vertices and faces aside whole while it copied them under
  // the header into the file, so a write took twice the file on disk (a 9.5 MB map slab did not fit in
  // 13 MiB free). A real small disk: a tmpfs (root only).
  if (::geteuid() != 0) {
    if (std::getenv("CI")) FAIL("not root: this test needs a tmpfs (mount)");
    WARN("skipped: not root, no tmpfs for a small disk");
    return;
  }
  sb::Mesh mesh;  // 120,000 vertices and faces in 6 pieces: 2.88 MB + 1.56 MB
  std::vector<sb::Mesh> pieces(6);
  for (uint32_t i = 0; i < 120000; ++i) {
    const Eigen::Vector3f v(0.001f * float(i), 0.25f * float(i % 13), -0.5f * float(i % 7));
    const Eigen::Vector3f n(0.0f, float(i % 2), float((i + 1) % 2));
    const std::array<uint32_t, 3> t{i, i == 0 ? 0 : i - 1, i / 2};
    mesh.vertices.push_back(v);
    mesh.normals.push_back(n);
    mesh.triangles.push_back(t);
    sb::Mesh& piece = pieces[i / 20000];
    piece.vertices.push_back(v);
    piece.normals.push_back(n);
    piece.triangles.push_back(t);
  }
  const std::string scratch = sb::test::scratchDir("ply_pieces_disk");
  sb::writePly(scratch + "/whole.ply", mesh);
  const std::string whole = readAll(scratch + "/whole.ply");
  const uint64_t size = whole.size();

  const std::string dir = scratch + "/disk";
  std::filesystem::create_directories(dir);
  REQUIRE(::mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=16m") == 0);
  struct Unmount {
    std::string dir;
    ~Unmount() { ::umount2(dir.c_str(), MNT_DETACH); }
  } unmount{dir};
  const auto freeBytes = [&] {
    struct statvfs fs {};
    return ::statvfs(dir.c_str(), &fs) == 0 ? uint64_t(fs.f_bavail) * fs.f_frsize : 0;
  };
  std::ofstream(dir + "/map.ply") << "the last good file";
  const auto fillTo = [&](uint64_t leave) {  // the filler grows or shrinks until about `leave` bytes are free
    std::filesystem::resize_file(dir + "/filler", 0);
    std::FILE* f = std::fopen((dir + "/filler").c_str(), "ab");
    REQUIRE(f);
    const std::string block(4096, 'x');
    while (freeBytes() > leave + block.size() &&
           std::fwrite(block.data(), 1, block.size(), f) == block.size() && std::fflush(f) == 0) {
    }
    std::fclose(f);
  };
  const auto write = [&] {
    sb::PlyPieceWriter ply(dir + "/map.ply");
    for (const sb::Mesh& piece : pieces) ply.add(piece);
    ply.finish();
  };
  const auto names = [&] {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(dir))
      out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  };
  std::ofstream(dir + "/filler").close();

  // Half the file free: the write fails for lack of space, the file before stays whole, nothing left aside.
  fillTo(size / 2);
  CHECK_THROWS_AS(write(), sb::DiskFullError);
  CHECK(readAll(dir + "/map.ply") == "the last good file");
  CHECK(names() == std::vector<std::string>{"filler", "map.ply"});

  // The file's size and 256 KiB free (less than 1.1 times the file): written, byte for byte writePly's.
  fillTo(size + (256 << 10));
  INFO("file " << size << " bytes, free " << freeBytes());
  REQUIRE(freeBytes() < size + size / 10);
  write();
  CHECK(readAll(dir + "/map.ply") == whole);
  CHECK(names() == std::vector<std::string>{"filler", "map.ply"});
}
