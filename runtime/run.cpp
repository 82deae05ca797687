#include "runtime/run.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <functional>
#include <vector>

#include "core/disk_full.h"
#include "core/error.h"
#include "core/png_io.h"
#include "mesh/marching_cubes.h"
#include "mesh/ply_writer.h"
#include "power/energy_json.h"
#include "report/run_report.h"

namespace sb {

namespace {

// Writes the file's data through to its disk or file server (fsync; the page cache is the host's, so any
// process of this host may do it for another's writes).
void syncFile(const std::string& path) {
  const int fd = open(path.c_str(), O_RDONLY);
  if (fd < 0) throw Error("cannot open '" + path + "' to sync it: " + std::strerror(errno));
  const int failed = fsync(fd);
  close(fd);
  if (failed != 0) throw Error("cannot sync '" + path + "' to disk: " + std::strerror(errno));
}

// A failed write's file as summary.json's "error_file": relative to the run's directory when inside it.
std::string outputName(const Error& e, const std::string& dir) {
  const auto* write = dynamic_cast<const WriteError*>(&e);
  if (!write || write->file().empty()) return "";
  const std::filesystem::path relative = std::filesystem::path(write->file()).lexically_relative(dir);
  if (relative.empty() || *relative.begin() == "..") return write->file();
  return relative.generic_string();
}

}  // namespace

// Above and behind the volume centre at 45 degrees, looking at the centre along the first camera's +z (volume
// +y is down). The raycast reaches only far_plane_m along each ray, so the camera sits within half of it from
// the centre (and within 0.6 of the volume side).
Eigen::Isometry3d overviewPose(const PipelineConfig& c) {
  const Eigen::Vector3d centre = Eigen::Vector3d::Constant(0.5 * c.volumeSize);
  const double distance = std::min(0.6 * c.volumeSize, 0.5 * c.farPlane);  // metres
  const Eigen::Vector3d forward = Eigen::Vector3d(0, 1, 1).normalized();
  const Eigen::Vector3d right = Eigen::Vector3d::UnitY().cross(forward).normalized();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear().col(0) = right;
  pose.linear().col(1) = forward.cross(right);  // down in the image
  pose.linear().col(2) = forward;
  pose.translation() = centre - distance * forward;
  return pose;
}

Run::Run(std::unique_ptr<Pipeline> pipeline, std::unique_ptr<Controller> controller, double depthScale,
         const odometry::OdometryConfig& motion, const RunOutputs& outputs, EnergyAccount* energy)
    : pipeline_(std::move(pipeline)),
      runner_(*pipeline_, std::move(controller), depthScale, motion),
      dir_(outputs.dir),
      outputs_(addStandardOutputs(runner_, outputs.dir, outputs.groundTruthPath, outputs.summary,
                                  outputs.comment, outputs.segments)),
      energy_(energy) {
  if (energy_)
    energyLog_ =
        std::make_unique<RotatingFile>(dir_, "energy.jsonl", "per-frame energy log", "", outputs.segments);
  mapSink_ = outputs.mapSink;
  startMapStore(outputs);
  if (VolumeWindow* window = pipeline_->volumeWindow(); window && (outputs.mapSlabs || mapSink_ || mapStore_)) {
    if (outputs.mapSlabs) {
      MapSlabs::Options options;
      options.keepBytes = outputs.keepSlabBytes;
      options.store = outputs.slabRetention;
      mapSlabs_ = std::make_unique<MapSlabs>(dir_, options);
    }
    window->setSlabListener([this](VolumeSlab&& slab) {
      // One copy (the window's), shared by the navigation map's worker and the mesh's: never copied again.
      auto shared = std::make_shared<const VolumeSlab>(std::move(slab));
      if (mapSink_) mapSink_->onSlab(shared);
      if (mapStore_) mapStore_->addSlab(shared);
      if (mapSlabs_) mapSlabs_->add(std::move(shared));
    });
  }
}

FrameRecord Run::step(const DepthFrame& frame) {
  // The odometry's counts in the summary, before the frame's sinks write it.
  RunSummary& header = outputs_.summary->header();
  if (const odometry::OdometryTrack* track = runner_.odometry(); track && header.odometry) {
    countOdometryFrame(*track, frame.timestamp, *header.odometry, lastOdometryPose_);
    noteCalibration(runner_.motion(), *header.odometry);
  }
  try {
    FrameRecord rec = runner_.step(frame);
    if (mapSlabs_) mapSlabs_->check();  // a slab the worker failed to write ends the run here
    if (mapStore_) stepMapStore(rec);
    if (mapSink_) mapSink_->onFrame(rec, frame, *pipeline_);
    if (energy_) record(energy_->add(rec));
    return rec;
  } catch (const Error& e) {
    // A bad frame or the first failed write, whichever output it was (trajectory, frames.jsonl, summary.json,
    // a map slab, energy.jsonl), ends the run: summary.json says so for both front ends ("complete": false,
    // "error", "error_file"), written into the room kept aside for it when the disk is full (issue 53
    // finding 8: it kept the last frame's snapshot, without "complete", when frames.jsonl met the full disk).
    RunSummary& summary = outputs_.summary->header();
    summary.error = e.what();
    summary.errorFile = outputName(e, dir_);
    if (mapSlabs_) {
      try {
        mapSlabs_->check();  // the slab worker's own failure meanwhile, said too
      } catch (const Error& slab) {
        summary.error += std::string("; and ") + slab.what();
      }
    }
    summary.complete = false;
    try {
      flush();
    } catch (const Error& unsaid) {
      throw Error(summary.error + "; and summary.json could not say so: " + unsaid.what());
    }
    throw;
  }
}

void Run::record(const std::vector<power::FrameEnergy>& results) {
  for (const power::FrameEnergy& e : results) {
    energyLog_->append(power::frameEnergyJson(e).dump() + "\n");  // one write: a crash leaves whole lines
    // The controller sees the newest known frame energy (budget mode in joules per frame needs it).
    if (e.known) runner_.setLatestJoules(e.joules);
    if (listener_) listener_(e);
  }
}

void Run::flush() {
  if (energy_) outputs_.summary->header().energy = energy_->totals();
  runner_.flush();
}

void Run::finish(const RunEnd& end, ThreadPool& pool) {
  if (energy_) {
    // The energy of the last frames needs the samples after their end: waits up to the drain timeout.
    if (end.drainEnergy) record(energy_->drain());
    outputs_.summary->header().energy = energy_->totals();
  }
  RunSummary& summary = outputs_.summary->header();
  summary.complete = false;  // until the outputs are on disk (below)
  if (!end.modelView.empty() && end.modelView != "last" && end.modelView != "overview")
    throw Error("model view '" + end.modelView + "': expected last or overview");
  // Each output is attempted even when an earlier one failed (a full disk): the summary is written last,
  // with "complete": false and every failure in "error", and the first failure is thrown after it.
  std::vector<std::string> failures;
  if (!end.error.empty()) failures.push_back(end.error);
  const auto attempt = [&](const std::function<void()>& write) {
    try {
      write();
    } catch (const Error& e) {
      if (failures.empty()) summary.errorFile = outputName(e, dir_);  // the file of "error"'s first failure
      failures.push_back(e.what());
    }
  };
  const std::filesystem::path out(dir_);
  if (mapSlabs_) attempt([&] { mapSlabs_->drain(); });  // every slab on disk (a failed one is reported here)
  if (mapStore_)
    attempt([&] {  // the final volume, the keyframes, the map's and the wheels' state into the store
      mapStore_->finish(*pipeline_->volumeWindow(), pipeline_->backend(), runner_.monitor().relocaliser().keyframes());
      keepStoreState(/*final=*/true);
      summary.mapStore = mapStore_->summaryJson();
    });
  if (!end.modelView.empty())
    attempt([&] {
      const Image<uint8_t> model = end.modelView == "overview"
                                       ? pipeline_->renderModel(movingVolumeOverview(*pipeline_), 1)
                                       : pipeline_->renderModel(1);
      summary.modelView = end.modelView;
      writePng8((out / "model.png").string(), model);  // whole or not at all (temporary file + rename)
    });
  if (end.mesh)
    attempt([&] {
      if (mapStore_ && mapStore_->writing() && !mapStore_->inMemory()) {
        // Writing a store: everything it holds (every run's slabs and final volumes, this run's kept by finish()
        // above), in its frame, not only what this run's volume saw.
        const auto start = std::chrono::steady_clock::now();
        size_t slabs = 0;
        const Mesh mesh = mapStore_->mesh(pool, &slabs);
        writePly((out / "mesh.ply").string(), mesh);  // whole or not at all (temporary file + rename)
        summary.meshTriangles = mesh.triangles.size();
        summary.meshSlabs = slabs;
        summary.mapStore["mesh_slabs"] = slabs;
        summary.mapStore["mesh_ms"] =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        return;
      }
      // The final volume and, with a moving volume, every slab that left (runtime/map_slabs.h).
      writeRunMesh((out / "mesh.ply").string(), *pipeline_, mapSlabs_.get(), pool, *outputs_.summary);
    });
  if (mapSink_)
    attempt([&] {
      mapSink_->write(dir_, *pipeline_);  // map.pgm, map.yaml, map.bt (navmap/), each atomically
      summary.navmap = mapSink_->summaryJson();
    });
  if (const VolumeWindow* window = pipeline_->volumeWindow())
    summary.movingVolume = movingVolumeSummary(*window, mapSlabs_.get());
  // "complete" last, once the trajectory and the frame log are on disk (on a shared file system: on the
  // server). `slambooster bench` / dse / profile count (and skip) only complete runs; an interrupted one runs
  // again.
  attempt([&] {
    runner_.flush();
    for (const RotatingFile* file : {&outputs_.trajectory->file(), &outputs_.frameLog->file()})
      syncFile(file->path());
  });
  if (!failures.empty()) {
    std::string error = failures.front();
    for (size_t i = 1; i < failures.size(); ++i) error += "; " + failures[i];
    summary.error = error;
  }
  summary.complete = end.complete && failures.empty();
  try {
    outputs_.summary->flush();
  } catch (const Error& e) {
    if (failures.empty()) throw;
    throw Error(failures.front() + "; and the summary: " + e.what());
  }
  if (!failures.empty())
    throw Error(failures.size() == 1 ? failures.front()
                                     : failures.front() + " (and " + std::to_string(failures.size() - 1) +
                                           " more; summary.json \"error\" lists them)");
}

std::string Run::writeReport() const { return writeRunReport(dir_).path; }

}  // namespace sb
