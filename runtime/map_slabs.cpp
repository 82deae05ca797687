#include "runtime/map_slabs.h"

#include <cstdio>
#include <filesystem>

#include "core/error.h"
#include "mesh/ply_merge.h"
#include "mesh/ply_writer.h"
#include "runtime/run.h"

namespace sb {

MapSlabs::MapSlabs(std::string dir) : dir_(std::move(dir)) {}

void MapSlabs::add(const VolumeSlab& slab) {
  const std::filesystem::path folder = std::filesystem::path(dir_) / "map_slabs";
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) throw Error("cannot create '" + folder.string() + "': " + ec.message());
  // The slab read in place through the cyclic offset (no copy of its voxels).
  VolumeView view;
  view.data = slab.volume;
  view.resolution = slab.resolution;
  view.size = slab.voxelSize * static_cast<float>(slab.resolution);
  view.offset = slab.offset;
  view.first = slab.first;
  view.extent = slab.extent;
  Mesh mesh = extractMesh(view, MeshOptions{});
  if (mesh.triangles.empty()) return;  // nothing observed left (e.g. the space behind the first view)
  transformMesh(mesh, Eigen::Isometry3f(Eigen::Translation3f(slab.corner.cast<float>())));
  char name[32];
  std::snprintf(name, sizeof name, "slab-%06zu.ply", slab.shift);
  const std::string path = (folder / name).string();
  writePly(path + ".partial", mesh);
  if (std::rename((path + ".partial").c_str(), path.c_str()) != 0)
    throw Error("cannot rename '" + path + ".partial' to '" + path + "'");
  files_.push_back(path);
  triangles_ += mesh.triangles.size();
}

size_t MapSlabs::writeMap(const std::string& path, const Mesh& finalVolume) const {
  return writeMergedPly(path, files_, finalVolume);
}

void writeRunMesh(const std::string& path, Pipeline& pipeline, const MapSlabs* slabs, ThreadPool& pool,
                  SummarySink& summary) {
  const PipelineConfig& config = pipeline.config();
  VolumeView view{pipeline.volumeData(), config.volumeResolution, config.volumeSize};
  const VolumeWindow* window = pipeline.volumeWindow();
  if (window) view.offset = window->offset();
  Mesh mesh = extractMesh(view, MeshOptions{}, pool);
  if (window && !window->cornerVoxels().isZero())  // to the world frame (a volume that never moved is in it)
    transformMesh(mesh, Eigen::Isometry3f(Eigen::Translation3f(window->cornerMetres().cast<float>())));
  if (slabs && !slabs->files().empty()) {
    summary.setExtra("mesh_triangles", slabs->writeMap(path, mesh));
    summary.setExtra("mesh_slabs", slabs->files().size());
  } else {
    writePly(path, mesh);  // whole or not at all (temporary file + rename)
    summary.setExtra("mesh_triangles", mesh.triangles.size());
  }
}

nlohmann::json movingVolumeJson(const VolumeWindow& window) {
  const VolumeWindowStats& s = window.stats();
  const Eigen::Vector3d corner = window.cornerMetres();
  return {{"shifts", s.shifts},
          {"shift_ms", s.shiftMs},
          {"slab_ms", s.slabMs},
          {"corner_m", {corner.x(), corner.y(), corner.z()}}};
}

Eigen::Isometry3d movingVolumeOverview(Pipeline& pipeline) {
  Eigen::Isometry3d pose = overviewPose(pipeline.config());
  if (const VolumeWindow* window = pipeline.volumeWindow()) pose.pretranslate(window->cornerMetres());
  return pose;
}

}  // namespace sb
