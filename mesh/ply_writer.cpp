#include "mesh/ply_writer.h"

#include "core/atomic_file.h"
#include "core/disk_full.h"
#include "core/error.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>

namespace sb {

namespace {

constexpr int kBitsPerByte = 8;
constexpr uint8_t kTriangleCorners = 3;
constexpr int kAsciiFloatDigits = 9;  // round-trips a float exactly

void checkMesh(const std::string& path, const Mesh& mesh) {
  const size_t nv = mesh.vertices.size();
  if (!mesh.normals.empty() && mesh.normals.size() != nv)
    throw Error("writePly '" + path + "': mesh has " + std::to_string(nv) + " vertices but " +
                std::to_string(mesh.normals.size()) + " normals; give one normal per vertex or none");
  if (nv > std::numeric_limits<uint32_t>::max())
    throw Error("writePly '" + path + "': " + std::to_string(nv) + " vertices exceed the uint32 index range");
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (uint32_t idx : mesh.triangles[t])
      if (idx >= nv)
        throw Error("writePly '" + path + "': triangle " + std::to_string(t) + " uses vertex " +
                    std::to_string(idx) + " but the mesh has only " + std::to_string(nv) + " vertices");
}

void putU32(std::string& buf, uint32_t v) {
  for (int b = 0; b < 4; ++b) buf.push_back(static_cast<char>((v >> (kBitsPerByte * b)) & 0xffu));
}

void putF32(std::string& buf, float f) {
  static_assert(sizeof(float) == sizeof(uint32_t), "PLY float must be 32-bit");
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  putU32(buf, bits);
}

std::string header(const Mesh& mesh, PlyFormat format) {
  std::string h = "ply\nformat ";
  h += format == PlyFormat::Ascii ? "ascii 1.0\n" : "binary_little_endian 1.0\n";
  h += "comment SLAMBooster TSDF surface (marching tetrahedra), volume frame, metres\n";
  h += "element vertex " + std::to_string(mesh.vertices.size()) + "\n";
  h += "property float x\nproperty float y\nproperty float z\n";
  if (!mesh.normals.empty()) h += "property float nx\nproperty float ny\nproperty float nz\n";
  h += "element face " + std::to_string(mesh.triangles.size()) + "\n";
  h += "property list uchar uint vertex_indices\nend_header\n";
  return h;
}

// The body goes out in pieces of about this many bytes: a mesh is never held twice (as triangles and bytes).
constexpr size_t kWriteChunkBytes = size_t(1) << 16;

void flushIfFull(std::ostream& out, std::string& buf, bool last = false) {
  if (!last && buf.size() < kWriteChunkBytes) return;
  out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
  buf.clear();
}

void writeBinaryBody(std::ostream& out, const Mesh& mesh) {
  const bool hasNormals = !mesh.normals.empty();
  std::string buf;
  buf.reserve(kWriteChunkBytes + 64);
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int a = 0; a < 3; ++a) putF32(buf, mesh.vertices[i][a]);
    if (hasNormals)
      for (int a = 0; a < 3; ++a) putF32(buf, mesh.normals[i][a]);
    flushIfFull(out, buf);
  }
  for (const auto& tri : mesh.triangles) {
    buf.push_back(static_cast<char>(kTriangleCorners));
    for (uint32_t idx : tri) putU32(buf, idx);
    flushIfFull(out, buf);
  }
  flushIfFull(out, buf, true);
}

void writeAsciiBody(std::ostream& out, const Mesh& mesh) {
  const bool hasNormals = !mesh.normals.empty();
  out << std::setprecision(kAsciiFloatDigits);
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const auto& v = mesh.vertices[i];
    out << v.x() << ' ' << v.y() << ' ' << v.z();
    if (hasNormals) out << ' ' << mesh.normals[i].x() << ' ' << mesh.normals[i].y() << ' ' << mesh.normals[i].z();
    out << '\n';
  }
  for (const auto& tri : mesh.triangles)
    out << int(kTriangleCorners) << ' ' << tri[0] << ' ' << tri[1] << ' ' << tri[2] << '\n';
}

}  // namespace

void writePly(const std::string& path, const Mesh& mesh, PlyFormat format) {
  checkMesh(path, mesh);
  // Whole or not at all: a temporary sibling renamed over `path` once every byte is written.
  writeFileAtomically(path, [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out)
      throw Error("writePly: cannot create '" + temporary + "': " + std::strerror(errno) +
                  "; check that the directory exists and is writable");
    errno = 0;
    out << header(mesh, format);
    if (format == PlyFormat::Ascii)
      writeAsciiBody(out, mesh);
    else
      writeBinaryBody(out, mesh);
    int error = errno;  // the failed write's reason (the stream keeps only a flag)
    out.close();
    if (!error) error = errno;
    if (!out) {
      const std::string message = "writePly: writing '" + path + "' failed: " + std::strerror(error ? error : EIO) +
                                  "; the previous file (if any) is left as it was (free disk space and run again)";
      if (error == ENOSPC || error == EDQUOT) throw DiskFullError(message);  // the caller may make room
      throw Error(message);
    }
  });
}

}  // namespace sb
