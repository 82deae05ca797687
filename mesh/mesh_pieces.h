#pragma once
// A mesh in pieces, for meshes that need not be held whole (a slab of the moving volume's map, written as it
// is extracted): extractMeshPieces hands the mesh of extractMesh over in z order, piece by piece, and
// PlyPieceWriter writes the pieces as one PLY, byte for byte writePly's file of the whole mesh, holding only
// a piece at a time (the vertices and the faces go to two files aside, joined under the header at the end,
// from the file's end backwards with the files aside cut as they are copied: on disk the write takes the
// file's size plus 64 KiB at its peak, not twice the file).

#include <cstddef>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

#include "core/exclusive_file.h"
#include "mesh/marching_cubes.h"

namespace sb {

// A piece: the vertices (and normals) after those of earlier pieces, and triangles that index the whole mesh
// (a triangle may use vertices of earlier pieces). The sink may change the piece (e.g. transformMesh).
using MeshPieceSink = std::function<void(Mesh& piece)>;

// The mesh of extractMesh(volume, options, pool), in pieces of a few z-slabs each (about two per thread of
// `pool`): concatenated, the pieces are that mesh exactly. Throws sb::Error as extractMesh does.
void extractMeshPieces(const VolumeView& volume, const MeshOptions& options, ThreadPool& pool,
                       const MeshPieceSink& sink);

// Writes the pieces of a mesh with normals as one binary PLY at `path` (whole or not at all: a temporary
// sibling renamed over it; the files aside and the temporary are new files of core/exclusive_file.h, never a
// name made beforehand). Not thread-safe.
class PlyPieceWriter {
 public:
  explicit PlyPieceWriter(const std::string& path);
  // The file `name` in the open directory `dir` (at `dirPath`, for messages).
  PlyPieceWriter(int dir, const std::string& dirPath, const std::string& name);
  ~PlyPieceWriter();  // removes the files aside (a writer never finished leaves nothing)
  PlyPieceWriter(const PlyPieceWriter&) = delete;
  PlyPieceWriter& operator=(const PlyPieceWriter&) = delete;

  // Throws sb::Error naming the file (sb::DiskFullError when the disk is full), and when the piece is
  // inconsistent (normals missing, an index past the vertices so far).
  void add(const Mesh& piece);
  size_t vertices() const { return vertices_; }
  size_t triangles() const { return triangles_; }
  // Writes `path` (header, vertices, faces), taking at most the file's size plus 64 KiB on disk at any time
  // (with the files aside; on a file system with sparse files). Throws as add(); once called, whether it
  // succeeded or not, the writer takes no more pieces and its files aside are gone.
  void finish();

 private:
  void put(std::FILE* file, const std::string& bytes, const std::string& name);

  UniqueFd dir_;
  std::string dirPath_, name_, path_;
  std::unique_ptr<TemporaryFile> verticesFile_, facesFile_;
  size_t vertices_ = 0, triangles_ = 0;
};

}  // namespace sb
