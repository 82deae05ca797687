// `slambooster run`: replays a sequence through the KinectFusion pipeline under a controller (default: fixed
// knobs) and writes the trajectory, a per-frame log, a summary (with ATE when the sequence has ground truth),
// a rendered model and, on request, a mesh. The frame loop and the outputs are runtime/'s.

#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "controller/registry.h"
#include "core/config_reader.h"
#include "core/error.h"
#include "core/thread_pool.h"
#include "core/trajectory.h"
#include "drivers/sequence.h"
#include "eval/trajectory_eval.h"
#include "pipeline/config.h"
#include "pipeline/pipeline.h"
#include "power/power_config.h"
#include "runtime/energy_account.h"
#include "odometry/odometry_input.h"
#include "runtime/run.h"
#include "runtime/run_setup.h"
#include "tools/slambooster/commands.h"
#include "tools/slambooster/navmap_options.h"
#include "tools/slambooster/stop_signals.h"

namespace sb::cli {

namespace {

namespace fs = std::filesystem;

struct RunOptions {
  std::string sequence;
  std::string out;
  std::string configPath;
  std::string knobs;
  std::string preset;
  std::string controller;
  std::optional<double> volumeSize;
  std::optional<int> volumeResolution;
  std::string initialPosition;
  size_t frames = 0;
  double stopAfterMs = 0;  // > 0: stop once the frames' computation time sums past it (dse's pruning)
  unsigned threads = 0;
  std::string powerConfig;
  bool mesh = false;
  bool fixedVolume = false;  // the paper's fixed volume whatever the config says (volume_mode "fixed")
  bool quiet = false;
  NavMapOptions navmap;  // the navigation map (issue 45)
  std::string modelView = "last";  // viewpoint of model.png: "last" camera pose or "overview"
  std::string depthTopic;          // ROS bag input: the depth image topic (empty: the bag's only one)
  std::string odometry;            // an odometry.txt (or .bag); empty: the sequence's own (odometry/odometry_input.h)
  bool noOdometry = false;
  BagOdometryOptions bagOdometry;  // ROS bag input: --odom-topic, --camera-mount
  std::string mapStore;            // the kept map's directory (runtime/map_store.h); empty: none
  uint64_t mapStoreKeepMib = 0;
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

struct RunSetup {
  PipelineConfig pipeline;
  ControllerSettings controller;
  odometry::OdometryConfig odometry;
};

// defaults < sequence volume hints < config file < command-line flags (runtime/run_setup.h).
RunSetup buildSetup(const RunOptions& o, const SequenceInfo& info) {
  SettingsFile file;
  if (!o.configPath.empty()) file = readSettingsFile(o.configPath);
  PipelineConfig c = pipelineConfigFor(info, file.pipeline, o.configPath);
  if (!o.preset.empty()) c.knobs = knobPreset(o.preset);
  if (!o.knobs.empty()) c.knobs = parseKnobs(o.knobs, c.knobs);
  if (o.volumeSize) {
    c.volumeSize = static_cast<float>(*o.volumeSize);
    c.volumeHinted.size = false;
  }
  if (o.volumeResolution) c.volumeResolution = *o.volumeResolution;
  if (!o.initialPosition.empty()) c.initialPosition = parsePosition(o.initialPosition);
  // The product follows the camera unless the config or --fixed-volume says otherwise (docs/moving-volume.md).
  if (o.fixedVolume) c.volumeMode = VolumeMode::fixed;
  finishPipelineConfig(c, "run options");
  const std::string where = !file.controller.is_null() ? o.configPath + ": controller"
                            : o.controller.empty()     ? "controller"
                                                       : "--controller";
  return RunSetup{c, controllerSettingsFrom(file.controller, o.controller, true, ControllerContext{c.knobs}, where),
                  odometry::odometryConfigFrom(file.odometry, o.configPath)};
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

// How the frame loop ended.
struct LoopEnd {
  bool stopped = false;  // --stop-after-ms
  int signal = 0;        // the stop signal received, 0 = none
  double cpuMs = 0.0;    // process CPU time of the loop
};

// Steps `run` through the frames of `source` until they end, a stop signal, or --stop-after-ms. A bad frame
// or a failed write stops the run: the outputs keep every frame before it, the summary says why (best effort:
// on a full disk it may not be written), and the error is thrown naming how many frames the outputs cover.
LoopEnd runFrames(const RunOptions& o, FrameSource& source, Run& run, size_t total) {
  const bool progress = !o.quiet && isatty(STDERR_FILENO);
  const SummarySink& summary = run.summary();
  const double cpuStartMs = processCpuMs();
  LoopEnd end;
  StopSignals signals;  // Ctrl-C / SIGTERM: finish the frame in hand, then write every output
  try {
    while (!signals.received()) {
      auto frame = source.next();
      if (!frame) break;
      run.step(*frame);
      if (progress) printProgress(run.runner().frames(), total, summary.stats().computationMsPerFrame());
      if (o.stopAfterMs > 0 && summary.stats().stageSums.computationMs() > o.stopAfterMs) {
        end.stopped = true;
        break;
      }
    }
  } catch (const Error& e) {
    if (progress) std::cerr << "\n";
    // Run::step said why already (with the output that failed and a slab's failure meanwhile); a frame the
    // source could not read is said here.
    if (run.summary().header().error.empty()) run.summary().header().error = e.what();
    run.summary().header().complete = false;
    try {
      run.flush();
    } catch (const Error&) {
    }
    throw Error(std::string(e.what()) + " (stopped after " + std::to_string(summary.stats().frames) +
                " frames; the outputs in " + o.out + " cover them)");
  }
  if (progress) std::cerr << "\n";
  end.signal = signals.received();
  end.cpuMs = processCpuMs() - cpuStartMs;
  return end;
}

// The end of the run: the summary's last fields, then every end-of-run output (Run::finish).
void finishRun(const RunOptions& o, Run& run, const LoopEnd& loop, ThreadPool& pool) {
  const RunStats& stats = run.summary().stats();
  const size_t count = stats.frames;
  if (count == 0 && loop.signal)
    throw Interrupted(loop.signal, "interrupted by " + StopSignals::name(loop.signal) + " before the first frame");
  if (count == 0) throw Error("sequence '" + o.sequence + "' has no frames");
  RunSummary& ending = run.summary().header();
  // Process CPU time per frame over all threads (includes decoding the input): less sensitive than the wall
  // times to other load on the machine.
  ending.cpuMsPerFrame = loop.cpuMs / count;
  if (loop.stopped)  // complete as asked, but not the whole sequence: its ATE and times cover the frames run
    ending.stopped = StoppedSummary{count, o.stopAfterMs, stats.stageSums.computationMs()};
  if (loop.signal) ending.interrupted = InterruptedSummary{StopSignals::name(loop.signal), count};
  RunEnd end;
  end.modelView = o.modelView;
  end.mesh = o.mesh;
  end.complete = loop.signal == 0;  // an interrupted run runs again under bench / dse / profile
  run.finish(end, pool);
}

// What the run did, on stdout, from its summary.
void printRun(const RunOptions& o, const SummarySink& summary, const LoopEnd& loop, unsigned threads) {
  const RunStats& stats = summary.stats();
  const RunSummary& written = summary.summary();
  const size_t count = stats.frames;
  std::cout << std::fixed << std::setprecision(1);
  if (loop.stopped)
    std::cout << "stopped after frame " << count << ": computation " << stats.stageSums.computationMs()
              << " ms is over --stop-after-ms " << o.stopAfterMs << "\n";
  std::cout << "controller " << written.controller << ", frames " << count << ", tracked " << stats.tracked << "/"
            << stats.trackingAttempted << " (" << stats.trackedPercent() << "%), integrated " << stats.integrated
            << ", corrected " << stats.corrected << "\n";
  std::cout << "computation " << stats.computationMsPerFrame() << " ms/frame (";
  for (int s = 0; s < kStageCount; ++s) {
    if (static_cast<Stage>(s) == Stage::render) continue;
    std::cout << (s ? ", " : "") << stageName(static_cast<Stage>(s)) << " " << std::setprecision(2)
              << stats.stageSums.ms[s] / count;
  }
  std::cout << "), process CPU " << std::setprecision(1) << loop.cpuMs / count << " ms/frame over " << threads
            << " threads\n" << std::setprecision(2);
  if (const std::optional<AteResult>& ate = summary.ate())
    std::cout << "ATE rmse " << ate->rmse * 100 << " cm, mean " << ate->mean * 100 << " cm, max " << ate->max * 100
              << " cm, unaligned mean " << ate->unalignedMean * 100 << " cm (" << ate->matches << " matches)\n";
  else if (!written.ateError.empty())
    std::cout << "ATE not computed: " << written.ateError << "\n";
  if (const std::optional<EnergySummary>& e = written.energy) {
    std::cout << "energy (" << e->meter << "): " << e->knownFrames << "/" << e->frames << " frames known";
    if (std::isfinite(e->joulesPerFrame))
      std::cout << ", " << e->joulesPerFrame << " J/frame, " << e->meanWatts << " W mean";
    std::cout << "; per frame in energy.jsonl, raw trace in power.csv\n";
  }
  std::cout << "outputs in " << o.out << "\n";
}

// Plan (the sequence, the setup, the run and its energy account), run the frames, finish, report.
void runCommand(const RunOptions& o) {
  SequenceOptions seqOptions;
  seqOptions.maxFrames = o.frames;
  seqOptions.depthTopic = o.depthTopic;
  std::unique_ptr<FrameSource> source = openSequence(o.sequence, seqOptions);
  const SequenceInfo info = source->info();
  const RunSetup setup = buildSetup(o, info);
  ThreadPool pool(o.threads);
  auto pipeline = Pipeline::create(setup.pipeline, info.intrinsics, pool);
  auto controller = createController(setup.controller, ControllerContext{setup.pipeline.knobs});
  const Knobs initial = controller->initialKnobs();
  const OdometryInput odometry =
      openOdometry(o.noOdometry ? "none" : o.odometry.empty() ? "auto" : o.odometry, o.sequence, o.bagOdometry);
  RunSummary header =
      runSummaryHeader("run", o.sequence, setup.controller, *controller, *pipeline, setup.odometry,
                       pool.threadCount());
  header.odometry = odometry.summary();
  // Energy: the run borrows the account of a sampler this command owns.
  std::unique_ptr<power::PowerSampler> sampler;
  std::optional<EnergyAccount> energy;
  if (!o.powerConfig.empty()) {
    fs::create_directories(o.out);
    sampler = openSampler(power::loadPowerConfig(o.powerConfig), o.out);
    if (sampler) {
      sampler->start();
      energy.emplace(*sampler);
    }
  }
  RunOutputs outputs;  // one file per output, no slab limit, no retention store (a replay)
  outputs.dir = o.out;
  outputs.groundTruthPath = info.groundTruthPath;
  outputs.summary = header;
  outputs.comment = "slambooster run " + o.sequence + " controller " + setup.controller.name + " initial knobs " +
                    formatKnobs(initial) + " (volume frame)";
  outputs.mapSlabs = o.mesh;
  outputs.mapSink = makeNavMapSink(o.navmap, setup.pipeline, info, odometry.track != nullptr);
  outputs.mapStore = o.mapStore;
  outputs.mapStoreOptions.keepSlabBytes = o.mapStoreKeepMib << 20;
  Run run(std::move(pipeline), std::move(controller), info.depthScale, setup.odometry, outputs,
          energy ? &*energy : nullptr);
  if (odometry.track) {
    run.runner().setOdometry(odometry.track);
    if (!o.quiet)
      std::cerr << "odometry: " << odometry.track->size() << " samples from " << odometry.source << "\n";
  }

  const size_t total = o.frames > 0 && info.frameCount > 0 ? std::min(o.frames, info.frameCount) : info.frameCount;
  const LoopEnd loop = runFrames(o, *source, run, total);
  finishRun(o, run, loop, pool);
  printRun(o, run.summary(), loop, pool.threadCount());
  // The HTML report is a convenience: a run whose outputs are written is not failed by it.
  try {
    std::cout << "report " << run.writeReport() << "\n";
  } catch (const Error& e) {
    std::cerr << "slambooster run: report not written: " << e.what() << "\n";
  }
  if (loop.signal)
    throw Interrupted(loop.signal, "interrupted by " + StopSignals::name(loop.signal) + " after frame " +
                                       std::to_string(run.summary().stats().frames) + "; the outputs in " +
                                       o.out + " cover the frames run");
}

}  // namespace

void addRunCommand(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  auto* sub = app.add_subcommand("run", "Replay a sequence through KinectFusion under a controller");
  sub->add_option("sequence", options->sequence,
                  "Sequence directory (TUM layout), .raw file or ROS .bag (needs slambooster-ros)")
      ->required();
  sub->add_option("--depth-topic", options->depthTopic,
                  "ROS bag: the depth sensor_msgs/Image topic (default: the bag's only 16UC1/32FC1 image topic)");
  auto* odometryFile = sub->add_option(
      "--odometry", options->odometry,
      "The robot's odometry: a TUM-format file of the camera's poses in the odometry frame (default: the\n"
      "sequence's odometry.txt when present, or a bag's only nav_msgs/Odometry topic)");
  sub->add_flag("--no-odometry", options->noOdometry, "Ignore the sequence's odometry")->excludes(odometryFile);
  sub->add_option("--odom-topic", options->bagOdometry.topic,
                  "ROS bag: the nav_msgs/Odometry topic (default: the bag's only one)");
  sub->add_option("--camera-mount", options->bagOdometry.cameraMount,
                  "ROS bag: the depth camera's optical frame in the odometry's base frame, \"x y z qx qy qz qw\"\n"
                  "(default: from the bag's /tf_static)");
  sub->add_option("--out", options->out, "Output directory")->required();
  sub->add_option("--config", options->configPath, "Pipeline config (JSON)");
  sub->add_option("--knobs", options->knobs, "Knobs, e.g. csr=2,icp=1e-4,pd=8:5:4,tr=1,ir=2 (on top of the preset)");
  sub->add_option("--preset", options->preset, "Knob preset (the knobs of the fixed controller)")
      ->check(CLI::IsMember({"default", "accurate"}));
  sub->add_option("--controller", options->controller,
                  "Controller (wins over the config file's controller.name; default: fixed):\n" + controllerHelp());
  sub->add_option("--volume-size", options->volumeSize, "Volume side (metres)");
  sub->add_option("--volume-resolution", options->volumeResolution, "Voxels per side (multiple of 8)");
  sub->add_option("--initial-position", options->initialPosition,
                  "First camera position as fractions of the volume side: fx,fy,fz");
  sub->add_option("--frames", options->frames, "Process at most this many frames (0 = all)");
  sub->add_option("--stop-after-ms", options->stopAfterMs,
                  "Stop once the computation time summed over the frames so far exceeds this many ms (0 = never;\n"
                  "summary.json then says \"stopped\"; `slambooster dse` uses it to drop settings already slower\n"
                  "than the best one)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--threads", options->threads, "Worker threads (0 = all cores)");
  sub->add_option("--power", options->powerConfig,
                  "Power meter config (config/power.json keys): joules per frame in energy.jsonl and the summary,\n"
                  "raw trace in power.csv (meter \"none\": no energy accounting)");
  sub->add_flag("--mesh", options->mesh,
                "Also write mesh.ply (marching cubes of the final volume; with the moving volume, of the whole run:\n"
                "every slab that left, written to map_slabs/ as it leaves, and the final volume)");
  sub->add_flag("--fixed-volume", options->fixedVolume,
                "The paper's fixed volume (volume_mode fixed): the volume never follows the camera\n"
                "(bench, dse and profile runs always pass it)");
  sub->add_option(
         "--model-view", options->modelView,
         "Viewpoint of model.png: last (the last camera pose) or overview (above and behind the volume "
         "centre, looking at it)")
      ->check(CLI::IsMember({"last", "overview"}));
  sub->add_option("--map-store", options->mapStore,
                  "Keep the map across runs in this directory (docs/map-store.md): created when absent; when it holds\n"
                  "an earlier run's map the run first localises in it (state lost until a view is confirmed), then\n"
                  "its poses are in the store's frame and it maps on into the store");
  sub->add_option("--map-store-keep-mib", options->mapStoreKeepMib,
                  "The store's slab files together at most this many MiB, the oldest removed first (0: no limit)")
      ->check(CLI::Range(uint64_t{0}, uint64_t{1} << 30));
  sub->add_flag("--quiet", options->quiet, "No progress bar");
  addNavMapOptions(sub, options->navmap);
  sub->callback([options] { runCommand(*options); });
}

}  // namespace sb::cli
