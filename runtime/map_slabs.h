#pragma once
// The whole run's map with a moving volume (issue 30): every slab that leaves the volume
// (pipeline/volume_window.h) is meshed and written at once to DIR/map_slabs/slab-NNNNNN.ply, a complete file
// (written aside, then renamed), so memory stays bounded on the board and a killed run keeps the slabs
// written so far. At the end mesh.ply holds every slab and the final volume, in the world frame.

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/thread_pool.h"
#include "mesh/marching_cubes.h"
#include "pipeline/pipeline.h"
#include "pipeline/volume_window.h"
#include "runtime/summary_sink.h"

namespace sb {

class MapSlabs {
 public:
  // Slabs go to `dir`/map_slabs (created at the first slab).
  explicit MapSlabs(std::string dir);

  // Meshes `slab` (world frame) and writes it (nothing when it holds no surface). Throws sb::Error naming the
  // file that cannot be written.
  void add(const VolumeSlab& slab);
  // Writes `path` from the slabs so far and `finalVolume` (world frame); returns its triangles.
  size_t writeMap(const std::string& path, const Mesh& finalVolume) const;

  const std::vector<std::string>& files() const { return files_; }
  size_t triangles() const { return triangles_; }

 private:
  std::string dir_;
  std::vector<std::string> files_;
  size_t triangles_ = 0;
};

// mesh.ply of a run (Run::finish): the final volume (read through a moving volume's cyclic offset and moved to
// the world frame) after every slab of `slabs` (nullptr or none: the volume alone, as a fixed volume always
// was). Sets the summary's "mesh_triangles" (and "mesh_slabs"). Throws sb::Error naming a file.
void writeRunMesh(const std::string& path, Pipeline& pipeline, const MapSlabs* slabs, ThreadPool& pool,
                  SummarySink& summary);

// The summary's "moving_volume": shifts, their cost (ms), the final corner (world, metres).
nlohmann::json movingVolumeJson(const VolumeWindow& window);

// overviewPose (run.h) of the volume where it is now (the world frame when it never moved).
Eigen::Isometry3d movingVolumeOverview(Pipeline& pipeline);

}  // namespace sb
