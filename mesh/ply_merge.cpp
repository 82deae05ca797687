#include "mesh/ply_merge.h"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/exclusive_file.h"
#include "core/stdio_streambuf.h"

namespace sb {

namespace {

constexpr size_t kVertexBytes = 6 * 4;     // x y z nx ny nz, float32
constexpr size_t kFaceBytes = 1 + 3 * 4;  // uchar 3, uint32 x 3
constexpr size_t kChunkItems = 1 << 14;    // vertices or faces per read

struct Part {
  std::string path;
  size_t vertices = 0, faces = 0;
  std::streamoff body = 0;  // where the vertex data starts
};

Part readHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("map part '" + path + "' cannot be opened: " + std::strerror(errno));
  Part part;
  part.path = path;
  std::string line, properties;
  bool binary = false;
  while (std::getline(in, line)) {
    if (line == "end_header") break;
    std::istringstream words(line);
    std::string word, element;
    words >> word;
    if (word == "format") binary = line == "format binary_little_endian 1.0";
    if (word == "element") {
      size_t count = 0;
      words >> element >> count;
      (element == "vertex" ? part.vertices : part.faces) = count;
    }
    if (word == "property") properties += line.substr(9) + ";";
  }
  const char* expected =
      "float x;float y;float z;float nx;float ny;float nz;list uchar uint vertex_indices;";
  if (!in || !binary || properties != expected)
    throw Error("map part '" + path + "' is not a binary PLY with normals as writePly writes it; delete it");
  part.body = in.tellg();
  return part;
}

void putU32(std::string& buf, uint32_t v) {
  for (int b = 0; b < 4; ++b) buf.push_back(static_cast<char>((v >> (8 * b)) & 0xffu));
}
void putF32(std::string& buf, float f) {
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  putU32(buf, bits);
}
uint32_t getU32(const char* p) {
  uint32_t v = 0;
  for (int b = 0; b < 4; ++b) v |= uint32_t(static_cast<uint8_t>(p[b])) << (8 * b);
  return v;
}

// Copies `count` items of `bytes` from `in` (at its position) to `out`; faces get `offset` added to indices.
void copyItems(std::ifstream& in, std::ostream& out, size_t count, size_t bytes, bool faces, uint32_t offset,
               const std::string& path) {
  std::string buf;
  for (size_t done = 0; done < count;) {
    const size_t n = std::min(kChunkItems, count - done);
    buf.resize(n * bytes);
    if (!in.read(&buf[0], static_cast<std::streamsize>(buf.size())))
      throw Error("map part '" + path + "' ends early (a write was cut short?); delete it");
    if (faces)
      for (size_t i = 0; i < n; ++i) {
        char* f = &buf[i * bytes + 1];
        for (int k = 0; k < 3; ++k) {
          const uint32_t v = getU32(f + 4 * k) + offset;
          for (int b = 0; b < 4; ++b) f[4 * k + b] = static_cast<char>((v >> (8 * b)) & 0xffu);
        }
      }
    out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
    done += n;
  }
}

}  // namespace

size_t writeMergedPly(const std::string& path, const std::vector<std::string>& partPaths, const Mesh& last) {
  std::vector<Part> parts;
  size_t vertices = last.vertices.size(), faces = last.triangles.size();
  for (const std::string& p : partPaths) {
    parts.push_back(readHeader(p));
    vertices += parts.back().vertices;
    faces += parts.back().faces;
  }
  if (vertices > UINT32_MAX) throw Error("writeMergedPly '" + path + "': more than 2^32 vertices");
  // A new file of its own (core/exclusive_file.h), renamed over `path` once whole.
  TemporaryFile aside(path, ".partial");
  StdioStreamBuf buffer(aside.stream());
  std::ostream out(&buffer);
  out << "ply\nformat binary_little_endian 1.0\n"
      << "comment SLAMBooster TSDF surface (marching tetrahedra), world frame, metres: " << parts.size()
      << " slabs of a moving volume and the final volume\n"
      << "element vertex " << vertices << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "property float nx\nproperty float ny\nproperty float nz\n"
      << "element face " << faces << "\n"
      << "property list uchar uint vertex_indices\nend_header\n";
  std::vector<std::ifstream> inputs;
  for (const Part& p : parts) {
    inputs.emplace_back(p.path, std::ios::binary);
    inputs.back().seekg(p.body);
    copyItems(inputs.back(), out, p.vertices, kVertexBytes, false, 0, p.path);
  }
  std::string buf;  // `last` goes out in pieces of kChunkItems: never held twice (as a mesh and as bytes)
  const auto flush = [&](bool always) {
    if (!always && buf.size() < kChunkItems * kVertexBytes) return;
    out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
    buf.clear();
  };
  const bool normals = last.normals.size() == last.vertices.size();
  for (size_t i = 0; i < last.vertices.size(); ++i) {
    for (int a = 0; a < 3; ++a) putF32(buf, last.vertices[i][a]);
    for (int a = 0; a < 3; ++a) putF32(buf, normals ? last.normals[i][a] : 0.0f);
    flush(false);
  }
  flush(true);
  uint32_t offset = 0;
  for (size_t i = 0; i < parts.size(); ++i) {
    copyItems(inputs[i], out, parts[i].faces, kFaceBytes, true, offset, parts[i].path);
    offset += static_cast<uint32_t>(parts[i].vertices);
  }
  for (const auto& tri : last.triangles) {
    buf.push_back(static_cast<char>(3));
    for (uint32_t idx : tri) putU32(buf, idx + offset);
    flush(false);
  }
  flush(true);
  out.flush();
  if (!out) throw Error("writing '" + aside.path() + "' failed (disk full?); free space and retry");
  aside.commit();
  return faces;
}

}  // namespace sb
