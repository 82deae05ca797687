// `slambooster run`: replays a sequence through the KinectFusion pipeline with fixed knobs and writes the
// trajectory, a per-frame log, a summary (with ATE when the sequence has ground truth), a rendered model and,
// on request, a mesh.

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "core/error.h"
#include "core/png_io.h"
#include "core/thread_pool.h"
#include "core/trajectory.h"
#include "drivers/sequence.h"
#include "eval/trajectory_eval.h"
#include "mesh/marching_cubes.h"
#include "mesh/ply_writer.h"
#include "pipeline/config.h"
#include "pipeline/pipeline.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {

namespace {

namespace fs = std::filesystem;

struct RunOptions {
  std::string sequence;
  std::string out;
  std::string configPath;
  std::string knobs;
  std::string preset;
  std::optional<double> volumeSize;
  std::optional<int> volumeResolution;
  std::string initialPosition;
  size_t frames = 0;
  unsigned threads = 0;
  bool mesh = false;
  bool quiet = false;
};

std::array<float, 3> parsePosition(const std::string& text) {
  std::array<float, 3> p{};
  std::istringstream in(text);
  char comma1 = 0, comma2 = 0;
  if (!(in >> p[0] >> comma1 >> p[1] >> comma2 >> p[2]) || comma1 != ',' || comma2 != ',' || !in.eof())
    throw Error("--initial-position '" + text + "' must be three fractions like 0.5,0.5,0.3");
  for (float v : p)
    if (!(v >= 0.0f && v <= 1.0f))
      throw Error("--initial-position '" + text + "': each fraction must be in [0, 1] (position inside the volume)");
  return p;
}

// defaults < sequence volume hints < config file < command-line flags.
PipelineConfig buildConfig(const RunOptions& o, const SequenceInfo& info) {
  PipelineConfig c;
  if (info.volumeSize) c.volumeSize = static_cast<float>(*info.volumeSize);
  if (info.volumeInitialPosition)
    for (int i = 0; i < 3; ++i) c.initialPosition[i] = static_cast<float>((*info.volumeInitialPosition)[i]);
  if (!o.configPath.empty()) c = loadConfigFile(o.configPath, c);
  if (!o.preset.empty()) c.knobs = knobPreset(o.preset);
  if (!o.knobs.empty()) c.knobs = parseKnobs(o.knobs, c.knobs);
  if (o.volumeSize) c.volumeSize = static_cast<float>(*o.volumeSize);
  if (o.volumeResolution) c.volumeResolution = *o.volumeResolution;
  if (!o.initialPosition.empty()) c.initialPosition = parsePosition(o.initialPosition);
  try {
    validateConfig(c);
  } catch (const Error& e) {
    throw Error(std::string("run options: ") + e.what());
  }
  return c;
}

nlohmann::json knobsJson(const Knobs& k) {
  return {{"csr", k.csr},
          {"icp", k.icpThreshold},
          {"pd", {k.pyramidIterations[0], k.pyramidIterations[1], k.pyramidIterations[2]}},
          {"tr", k.trackingRate},
          {"ir", k.integrationRate}};
}

nlohmann::json frameJson(const FrameResult& r) {
  nlohmann::json stages = nlohmann::json::object();
  for (int s = 0; s < kStageCount; ++s) stages[stageName(static_cast<Stage>(s))] = r.times.ms[s];
  return {{"frame", r.frame},
          {"timestamp", r.timestamp},
          {"knobs", knobsJson(r.knobs)},
          {"ms", stages},
          {"computation_ms", r.times.computationMs()},
          {"tracking_attempted", r.trackingAttempted},
          {"tracked", r.tracked},
          {"integrated", r.integrated},
          {"icp_iterations", r.icpIterations},
          {"residual_m", r.residual},
          {"inliers", r.inlierFraction},
          {"velocity_m_per_frame", r.velocity}};
}

// CPU time (user + system) of the process so far, milliseconds.
double processCpuMs() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return (usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) * 1e3 + (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e3;
}

void printProgress(size_t done, size_t total, double msPerFrame) {
  const int width = 40;
  const double fraction = total > 0 ? std::min(1.0, double(done) / total) : 0.0;
  const int filled = static_cast<int>(fraction * width);
  std::cerr << "\r[" << std::string(filled, '#') << std::string(width - filled, ' ') << "] " << done;
  if (total > 0) std::cerr << "/" << total;
  std::cerr << "  " << std::fixed << std::setprecision(1) << msPerFrame << " ms/frame" << std::flush;
}

void runCommand(const RunOptions& o) {
  SequenceOptions seqOptions;
  seqOptions.maxFrames = o.frames;
  std::unique_ptr<FrameSource> source = openSequence(o.sequence, seqOptions);
  const SequenceInfo info = source->info();
  const PipelineConfig config = buildConfig(o, info);

  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (!fs::is_directory(o.out)) throw Error("cannot create output directory '" + o.out + "': " + ec.message());
  const fs::path out(o.out);
  std::ofstream frames(out / "frames.jsonl");
  if (!frames) throw Error("cannot write '" + (out / "frames.jsonl").string() + "'");

  ThreadPool pool(o.threads);
  auto pipeline = Pipeline::createCpu(config, info.intrinsics, pool);
  const bool progress = !o.quiet && isatty(STDERR_FILENO);
  const size_t total = o.frames > 0 && info.frameCount > 0 ? std::min(o.frames, info.frameCount) : info.frameCount;

  Trajectory trajectory;
  StageTimes sum;
  const double cpuStartMs = processCpuMs();
  size_t count = 0, attempted = 0, tracked = 0, integrated = 0;
  while (auto frame = source->next()) {
    FrameResult r = pipeline->processFrame(*frame, info.depthScale, config.knobs);
    trajectory.push_back(TimedPose{r.timestamp, r.T_camera_to_world});
    frames << frameJson(r).dump() << "\n";
    for (int s = 0; s < kStageCount; ++s) sum.ms[s] += r.times.ms[s];
    ++count;
    attempted += r.trackingAttempted;
    tracked += r.tracked;
    integrated += r.integrated;
    if (progress) printProgress(count, total, sum.computationMs() / count);
  }
  const double cpuMs = processCpuMs() - cpuStartMs;
  if (progress) std::cerr << "\n";
  if (count == 0) throw Error("sequence '" + o.sequence + "' has no frames");
  frames.close();
  writeTumTrajectory((out / "trajectory.tum").string(), trajectory,
                     "slambooster run " + o.sequence + " knobs " + formatKnobs(config.knobs) + " (volume frame)");

  nlohmann::json summary;
  summary["sequence"] = o.sequence;
  summary["frames"] = count;
  summary["tracking_attempted"] = attempted;
  summary["tracked"] = tracked;
  summary["tracked_percent"] = attempted > 0 ? 100.0 * tracked / attempted : 0.0;
  summary["integrated"] = integrated;
  summary["knobs"] = knobsJson(config.knobs);
  summary["config"] = configToJson(config);
  summary["threads"] = pool.threadCount();
  summary["computation_ms_per_frame"] = sum.computationMs() / count;
  // Process CPU time per frame over all threads (includes decoding the input): less sensitive than the wall
  // times to other load on the machine.
  summary["cpu_ms_per_frame"] = cpuMs / count;
  nlohmann::json stages = nlohmann::json::object();
  for (int s = 0; s < kStageCount; ++s) stages[stageName(static_cast<Stage>(s))] = sum.ms[s] / count;
  summary["stage_ms_per_frame"] = stages;
  std::optional<AteResult> ate;
  if (!info.groundTruthPath.empty()) {
    try {
      ate = computeAte(trajectory, readTumTrajectory(info.groundTruthPath));
      summary["ate"] = {{"rmse_m", ate->rmse},   {"mean_m", ate->mean},
                        {"max_m", ate->max},     {"median_m", ate->median},
                        {"matches", ate->matches}, {"unaligned_mean_m", ate->unalignedMean}};
    } catch (const Error& e) {
      summary["ate_error"] = e.what();
    }
  }

  const Image<uint8_t> model = pipeline->renderModel(1);
  writePng8((out / "model.png").string(), model);
  if (o.mesh) {
    const VolumeView view{pipeline->volumeData(), config.volumeResolution, config.volumeSize};
    const Mesh mesh = extractMesh(view, MeshOptions{}, pool);
    writePly((out / "mesh.ply").string(), mesh);
    summary["mesh_triangles"] = mesh.triangles.size();
  }
  std::ofstream(out / "summary.json") << summary.dump(2) << "\n";

  std::cout << std::fixed << std::setprecision(1);
  std::cout << "frames " << count << ", tracked " << tracked << "/" << attempted << " ("
            << summary["tracked_percent"].get<double>() << "%), integrated " << integrated << "\n";
  std::cout << "computation " << sum.computationMs() / count << " ms/frame (";
  for (int s = 0; s < kStageCount; ++s) {
    if (static_cast<Stage>(s) == Stage::render) continue;
    std::cout << (s ? ", " : "") << stageName(static_cast<Stage>(s)) << " " << std::setprecision(2) << sum.ms[s] / count;
  }
  std::cout << "), process CPU " << std::setprecision(1) << cpuMs / count << " ms/frame over " << pool.threadCount()
            << " threads\n" << std::setprecision(2);
  if (ate)
    std::cout << "ATE rmse " << ate->rmse * 100 << " cm, mean " << ate->mean * 100 << " cm, max " << ate->max * 100
              << " cm, unaligned mean " << ate->unalignedMean * 100 << " cm (" << ate->matches << " matches)\n";
  else if (summary.contains("ate_error"))
    std::cout << "ATE not computed: " << summary["ate_error"].get<std::string>() << "\n";
  std::cout << "outputs in " << out.string() << "\n";
}

}  // namespace

void addRunCommand(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  auto* sub = app.add_subcommand("run", "Replay a sequence through KinectFusion with fixed knobs");
  sub->add_option("sequence", options->sequence, "Sequence directory (TUM layout) or .raw file")->required();
  sub->add_option("--out", options->out, "Output directory")->required();
  sub->add_option("--config", options->configPath, "Pipeline config (JSON)");
  sub->add_option("--knobs", options->knobs, "Knobs, e.g. csr=2,icp=1e-4,pd=8:5:4,tr=1,ir=2 (on top of the preset)");
  sub->add_option("--preset", options->preset, "Knob preset")->check(CLI::IsMember({"default", "accurate"}));
  sub->add_option("--volume-size", options->volumeSize, "Volume side (metres)");
  sub->add_option("--volume-resolution", options->volumeResolution, "Voxels per side (multiple of 8)");
  sub->add_option("--initial-position", options->initialPosition,
                  "First camera position as fractions of the volume side: fx,fy,fz");
  sub->add_option("--frames", options->frames, "Process at most this many frames (0 = all)");
  sub->add_option("--threads", options->threads, "Worker threads (0 = all cores)");
  sub->add_flag("--mesh", options->mesh, "Also write mesh.ply (marching cubes of the final volume)");
  sub->add_flag("--quiet", options->quiet, "No progress bar");
  sub->callback([options] { runCommand(*options); });
}

}  // namespace sb::cli
