#include "mesh/ply_writer.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <memory>

#include "core/atomic_file.h"
#include "core/disk_full.h"
#include "core/error.h"
#include "core/exclusive_file.h"
#include "core/stdio_streambuf.h"
#include "mesh/mesh_pieces.h"

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

std::string header(size_t vertices, size_t faces, bool normals, PlyFormat format) {
  std::string h = "ply\nformat ";
  h += format == PlyFormat::Ascii ? "ascii 1.0\n" : "binary_little_endian 1.0\n";
  h += "comment SLAMBooster TSDF surface (marching tetrahedra), volume frame, metres\n";
  h += "element vertex " + std::to_string(vertices) + "\n";
  h += "property float x\nproperty float y\nproperty float z\n";
  if (normals) h += "property float nx\nproperty float ny\nproperty float nz\n";
  h += "element face " + std::to_string(faces) + "\n";
  h += "property list uchar uint vertex_indices\nend_header\n";
  return h;
}

std::string header(const Mesh& mesh, PlyFormat format) {
  return header(mesh.vertices.size(), mesh.triangles.size(), !mesh.normals.empty(), format);
}

// The reason of a failed write of `file` (the PLY being made), as the error to throw (DiskFullError when the
// disk is full: the caller may make room).
[[noreturn]] void throwWriteError(const std::string& what, int error, const std::string& file) {
  throwWriteFailure(what + ": " + std::strerror(error ? error : EIO) +
                        "; the previous file (if any) is left as it was (free disk space and run again)",
                    file, error ? error : EIO);
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
  writeFileAtomically(path, [&](std::FILE* file, const std::string&) {
    StdioStreamBuf buffer(file);
    std::ostream out(&buffer);
    errno = 0;
    out << header(mesh, format);
    if (format == PlyFormat::Ascii)
      writeAsciiBody(out, mesh);
    else
      writeBinaryBody(out, mesh);
    int error = errno;  // the failed write's reason (the stream keeps only a flag)
    out.flush();
    if (!error) error = errno;
    if (!out || std::ferror(file)) throwWriteError("writePly: writing '" + path + "' failed", error, path);
  });
}

namespace {

std::pair<std::string, std::string> splitPlyPath(const std::string& path) {
  const size_t slash = path.rfind('/');
  if (slash == std::string::npos) return {".", path};
  return {slash == 0 ? "/" : path.substr(0, slash), path.substr(slash + 1)};
}

}  // namespace

PlyPieceWriter::PlyPieceWriter(const std::string& path)
    : PlyPieceWriter(openDirectory(splitPlyPath(path).first).get(), splitPlyPath(path).first,
                     splitPlyPath(path).second) {}

PlyPieceWriter::PlyPieceWriter(int dir, const std::string& dirPath, const std::string& name)
    : dir_(::fcntl(dir, F_DUPFD_CLOEXEC, 0)),
      dirPath_(dirPath),
      name_(name),
      path_(dirPath == "." ? name : dirPath + "/" + name) {
  if (!dir_.valid()) throw Error("writePly: cannot use the directory '" + dirPath + "': " + std::strerror(errno));
  verticesFile_ = std::make_unique<TemporaryFile>(dir_.get(), dirPath_, name_, ".vertices.tmp");
  facesFile_ = std::make_unique<TemporaryFile>(dir_.get(), dirPath_, name_, ".faces.tmp");
}

PlyPieceWriter::~PlyPieceWriter() = default;  // the files aside are removed by their TemporaryFile

void PlyPieceWriter::put(std::FILE* file, const std::string& bytes, const std::string& name) {
  errno = 0;
  if (std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size())
    throwWriteError("writePly: writing '" + name + "' failed", errno, path_);
}

void PlyPieceWriter::add(const Mesh& piece) {
  if (!verticesFile_ || !facesFile_)
    throw Error("writePly '" + path_ + "': a piece after finish(); write the mesh with a new writer");
  if (piece.normals.size() != piece.vertices.size())
    throw Error("writePly '" + path_ + "': a piece has " + std::to_string(piece.vertices.size()) +
                " vertices but " + std::to_string(piece.normals.size()) +
                " normals; give one normal per vertex");
  const size_t total = vertices_ + piece.vertices.size();
  if (total > std::numeric_limits<uint32_t>::max())
    throw Error("writePly '" + path_ + "': " + std::to_string(total) +
                " vertices exceed the uint32 index range");
  std::FILE* vertices = verticesFile_->stream();
  std::FILE* faces = facesFile_->stream();
  std::string buf;
  buf.reserve(kWriteChunkBytes + 64);
  for (size_t i = 0; i < piece.vertices.size(); ++i) {
    for (int a = 0; a < 3; ++a) putF32(buf, piece.vertices[i][a]);
    for (int a = 0; a < 3; ++a) putF32(buf, piece.normals[i][a]);
    if (buf.size() >= kWriteChunkBytes) {
      put(vertices, buf, verticesFile_->path());
      buf.clear();
    }
  }
  put(vertices, buf, verticesFile_->path());
  buf.clear();
  for (size_t t = 0; t < piece.triangles.size(); ++t) {
    buf.push_back(static_cast<char>(kTriangleCorners));
    for (uint32_t idx : piece.triangles[t]) {
      if (idx >= total)
        throw Error("writePly '" + path_ + "': triangle " + std::to_string(triangles_ + t) + " uses vertex " +
                    std::to_string(idx) + " but the mesh has only " + std::to_string(total) +
                    " vertices so far");
      putU32(buf, idx);
    }
    if (buf.size() >= kWriteChunkBytes) {
      put(faces, buf, facesFile_->path());
      buf.clear();
    }
  }
  put(faces, buf, facesFile_->path());
  vertices_ = total;
  triangles_ += piece.triangles.size();
}

namespace {

// Writes `n` bytes at `at` of `fd` (at `path`; a short write goes on; a failure throws naming `file`, the PLY
// being made, DiskFullError when full).
void writeAt(int fd, const char* data, size_t n, uint64_t at, const std::string& path,
             const std::string& file) {
  size_t done = 0;
  while (done < n) {
    errno = 0;
    const ssize_t put = ::pwrite(fd, data + done, n - done, static_cast<off_t>(at + done));
    if (put <= 0) throwWriteError("writePly: writing '" + path + "' failed", errno, file);
    done += static_cast<size_t>(put);
  }
}

// Moves `src`'s `bytes` bytes to `dst` at `at`, last chunk first, cutting `src` behind each chunk copied: the
// two files together take at most `bytes` plus one chunk on a file system with sparse files (the chunks of
// `dst` not yet written are holes). `src` is emptied; a failure leaves both to be removed by the caller and
// names `file` (the PLY being made).
void moveTail(int src, const std::string& srcPath, uint64_t bytes, int dst, uint64_t at,
              const std::string& dstPath, const std::string& file, std::string& buf) {
  uint64_t end = bytes;
  while (end > 0) {
    const uint64_t start = (end - 1) / buf.size() * buf.size();  // chunk-aligned, so the cuts are too
    const size_t n = static_cast<size_t>(end - start);
    const ssize_t got = ::pread(src, &buf[0], n, static_cast<off_t>(start));
    if (got != static_cast<ssize_t>(n))
      throw Error("writePly: cannot read back '" + srcPath + "': " +
                  (got < 0 ? std::strerror(errno) : "the file is shorter than written"));
    writeAt(dst, buf.data(), n, at + start, dstPath, file);
    if (::ftruncate(src, static_cast<off_t>(start)) != 0)
      throw Error("writePly: cannot shorten '" + srcPath + "': " + std::strerror(errno));
    end = start;
  }
}

}  // namespace

void PlyPieceWriter::finish() {
  if (!verticesFile_ || !facesFile_)
    throw Error("writePly '" + path_ + "': the writer was finished already (or its finish failed); write the "
                "mesh again with a new writer");
  // Taken out: whatever happens below, the files aside are removed and this writer takes no more pieces.
  const std::unique_ptr<TemporaryFile> vertices = std::move(verticesFile_), faces = std::move(facesFile_);
  uint64_t sizes[2] = {0, 0};
  int i = 0;
  for (TemporaryFile* aside : {vertices.get(), faces.get()}) {
    std::FILE* file = aside->stream();
    errno = 0;
    const bool failed = std::fflush(file) != 0 || std::ferror(file);
    if (failed) throwWriteError("writePly: writing '" + aside->path() + "' failed", errno, path_);
    struct stat st {};
    if (::fstat(aside->fd(), &st) != 0)
      throw Error("writePly: cannot read back '" + aside->path() + "': " + std::strerror(errno));
    sizes[i++] = static_cast<uint64_t>(st.st_size);
  }
  // The file is put together from its end (issue 53, finding 8): the faces, then the vertices, each moved
  // chunk by chunk with the file aside cut behind it, then the header. So the write takes the file's size
  // plus a chunk on disk at its peak, not twice the file (the asides whole beside a whole copy); a slab of
  // 9.5 MB on a disk with 13 MiB free is written. The asides are emptied as they go: a failed finish() is
  // not retried on this writer (the caller writes the mesh again with a new one).
  const std::string head = header(vertices_, triangles_, true, PlyFormat::BinaryLittleEndian);
  TemporaryFile target(dir_.get(), dirPath_, name_, ".tmp");
  std::string buf(kWriteChunkBytes, '\0');
  moveTail(faces->fd(), faces->path(), sizes[1], target.fd(), head.size() + sizes[0], target.path(), path_,
           buf);
  moveTail(vertices->fd(), vertices->path(), sizes[0], target.fd(), head.size(), target.path(), path_,
           buf);
  writeAt(target.fd(), head.data(), head.size(), 0, target.path(), path_);
  target.commit();
}

}  // namespace sb
