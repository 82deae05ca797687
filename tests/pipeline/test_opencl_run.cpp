// Whole runs on the OpenCL backend against the CPU backend: a 100-frame synthetic sequence (the synth library's
// living room along its built-in handheld trajectory, noise-free, 160x120, 128^3 volume) whose trajectory
// must stay within 1 mm of the CPU backend's; the same with half storage, and with the precision switched in
// the middle of the run; and ([data]) the 7-Scenes kitchen.

#include <catch2/catch.hpp>
#include <memory>

#include "core/trajectory.h"
#include "drivers/sequence.h"
#include "eval/trajectory_eval.h"
#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/opencl/opencl_backend.h"
#include "pipeline/pipeline.h"
#include "synth/builtin_trajectory.h"
#include "synth/renderer.h"
#include "synth/scene_generator.h"
#include "synth/synth_sequence.h"
#include "synth/volume_hints.h"
#include "tests/pipeline/test_opencl_support.h"
#include "tests/support/test_data.h"

namespace {

constexpr size_t kFrames = 100;

struct SynthRun {
  sb::Intrinsics k;
  std::vector<sb::DepthFrame> frames;
  sb::Trajectory truth;
  sb::PipelineConfig config;
};

const SynthRun& synthRun() {
  static const SynthRun run = [] {
    SynthRun r;
    const sb::synth::Scene scene = sb::synth::generateScene("livingroom", 7);
    r.truth = sb::synth::builtinTrajectory(kFrames);
    r.k = sb::synth::iclNuimIntrinsics().scaled(4);  // 160x120
    // Noise-free depth (the range limits and the incidence cut-off stay): a well-conditioned run, so that
    // a difference between the backends is not amplified by tracking at the edge of failure. The stage
    // tests cover noisy input.
    sb::synth::SensorModel sensor;
    sensor.noise = false;
    const sb::synth::VolumeHints hints = sb::synth::estimateVolumeHints(scene, r.truth, r.k, sensor);
    const sb::synth::Renderer renderer(scene, r.k);
    for (size_t i = 0; i < r.truth.size(); ++i) {
      sb::DepthMeters metres;
      renderer.render(r.truth[i].T_camera_to_world, sensor, sb::synth::frameSeed(7, i), metres);
      sb::DepthFrame frame;
      frame.index = i;
      frame.timestamp = r.truth[i].timestamp;
      sb::synth::toRaw(metres, sb::synth::kIclDepthScale, frame.depth);
      r.frames.push_back(std::move(frame));
    }
    r.config.volumeResolution = 128;
    // ACCURATE knobs (icp = 0): every frame runs all ICP iterations. With an early-stop threshold, an update
    // norm within 1e-7 of it stops one backend an iteration before the other, which moved the DEFAULT run's
    // trajectories apart by up to ~1 mm here; with all iterations the backends stay within ~0.2 mm.
    r.config.knobs = sb::knobPreset("accurate");
    r.config.volumeSize = static_cast<float>(hints.sizeM);
    for (int a = 0; a < 3; ++a) r.config.initialPosition[a] = static_cast<float>(hints.initialPosition[a]);
    return r;
  }();
  return run;
}

struct RunResult {
  sb::Trajectory trajectory;
  size_t tracked = 0, attempted = 0;
  sb::StageTimes times;  // summed over the run
};

// `halfFrames`: half storage for frames in [first, last).
RunResult runPipeline(std::unique_ptr<sb::ComputeBackend> backend, const SynthRun& run,
                      std::pair<size_t, size_t> halfFrames = {0, 0}) {
  sb::Pipeline pipeline(run.config, run.k, std::move(backend));
  RunResult result;
  for (const sb::DepthFrame& frame : run.frames) {
    if (halfFrames.second > halfFrames.first)
      pipeline.backend().setHalfPrecision(frame.index >= halfFrames.first && frame.index < halfFrames.second);
    const sb::FrameResult r = pipeline.processFrame(frame, sb::synth::kIclDepthScale, run.config.knobs);
    result.trajectory.push_back({r.timestamp, r.T_camera_to_world});
    result.tracked += r.tracked;
    result.attempted += r.trackingAttempted;
    for (int s = 0; s < sb::kStageCount; ++s) {
      result.times.ms[s] += r.times.ms[s];
      result.times.deviceMs[s] += r.times.deviceMs[s];
    }
  }
  return result;
}

double maxPositionDifference(const sb::Trajectory& a, const sb::Trajectory& b) {
  double worst = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i)
    worst = std::max(worst, (a[i].position() - b[i].position()).norm());
  return worst;
}

const RunResult& cpuRun() {
  static const RunResult result = [] {
    sb::ThreadPool& pool = sb::ThreadPool::global();
    return runPipeline(std::make_unique<sb::CpuBackend>(synthRun().config, synthRun().k, pool), synthRun());
  }();
  return result;
}

std::unique_ptr<sb::ComputeBackend> openclBackend(bool half) {
  sb::PipelineConfig config = synthRun().config;
  config.openclHalfStorage = half;
  return std::make_unique<sb::OpenClBackend>(config, synthRun().k, sb::test::openclTestDevice());
}

const RunResult& openclFloatRun() {
  static const RunResult result = runPipeline(openclBackend(false), synthRun());
  return result;
}

}  // namespace

TEST_CASE("OpenCL: a 100-frame synthetic run stays within 1 mm of the CPU backend", "[opencl][run]") {
  const RunResult& cpu = cpuRun();
  const RunResult& cl = openclFloatRun();
  REQUIRE(cl.trajectory.size() == kFrames);
  const double difference = maxPositionDifference(cl.trajectory, cpu.trajectory);
  const sb::AteResult ate = sb::computeAte(cl.trajectory, synthRun().truth);
  const sb::AteResult cpuAte = sb::computeAte(cpu.trajectory, synthRun().truth);
  INFO("max position difference to the CPU backend " << difference * 1000 << " mm; ATE opencl " << ate.rmse * 100
       << " cm, cpu " << cpuAte.rmse * 100 << " cm; tracked " << cl.tracked << "/" << cl.attempted);
  CHECK(difference < 0.001);
  CHECK(cl.tracked == cpu.tracked);
  CHECK(cpu.tracked == cpu.attempted);
  CHECK(ate.rmse < 0.05);
  // Every computation stage ran on the device and was timed by profiling events.
  for (int s = 0; s < sb::kStageCount; ++s)
    if (static_cast<sb::Stage>(s) != sb::Stage::render) {
      INFO(sb::stageName(static_cast<sb::Stage>(s)));
      CHECK(cl.times.deviceMs[s] > 0);
    }
}

TEST_CASE("OpenCL: half storage tracks the synthetic run, also when switched on and off mid-run", "[opencl][run][half]") {
  const RunResult& cpu = cpuRun();
  const RunResult half = runPipeline(openclBackend(true), synthRun());
  const RunResult switched = runPipeline(openclBackend(false), synthRun(), {30, 60});
  const sb::AteResult halfAte = sb::computeAte(half.trajectory, synthRun().truth);
  const sb::AteResult cpuAte = sb::computeAte(cpu.trajectory, synthRun().truth);
  INFO("half storage: ATE " << halfAte.rmse * 100 << " cm (cpu " << cpuAte.rmse * 100 << " cm), max difference to cpu "
       << maxPositionDifference(half.trajectory, cpu.trajectory) * 1000 << " mm, tracked " << half.tracked << "/"
       << half.attempted << "; switched mid-run: max difference "
       << maxPositionDifference(switched.trajectory, cpu.trajectory) * 1000 << " mm, tracked " << switched.tracked);
  CHECK(half.tracked == half.attempted);
  CHECK(halfAte.rmse < cpuAte.rmse + 0.01);
  CHECK(maxPositionDifference(half.trajectory, cpu.trajectory) < 0.02);
  CHECK(switched.tracked == switched.attempted);
  CHECK(maxPositionDifference(switched.trajectory, cpu.trajectory) < 0.02);
  // Float frames before the switch are the float run's.
  for (size_t i = 0; i < 30; ++i) CHECK(switched.trajectory[i].position() == openclFloatRun().trajectory[i].position());
}

TEST_CASE("OpenCL: 7-Scenes redkitchen, 60 frames at ACCURATE knobs, within 1 mm of the CPU backend", "[data][opencl]") {
  sb::SequenceOptions options;
  options.maxFrames = 60;
  const std::string path = sb::test::sharedDataDir() + "/7scenes-redkitchen-a";
  sb::PipelineConfig config;  // 5 m, 256^3: the setup
  config.knobs = sb::knobPreset("accurate");  // no early stop (see the synthetic run)
  sb::Trajectory trajectories[2];
  for (int b = 0; b < 2; ++b) {
    auto source = sb::openSequence(path, options);
    const sb::SequenceInfo info = source->info();
    std::unique_ptr<sb::ComputeBackend> backend;
    if (b == 0) backend = std::make_unique<sb::CpuBackend>(config, info.intrinsics, sb::ThreadPool::global());
    else backend = std::make_unique<sb::OpenClBackend>(config, info.intrinsics, sb::test::openclTestDevice());
    sb::Pipeline pipeline(config, info.intrinsics, std::move(backend));
    while (auto frame = source->next()) {
      const sb::FrameResult r = pipeline.processFrame(*frame, info.depthScale, config.knobs);
      trajectories[b].push_back({r.timestamp, r.T_camera_to_world});
    }
  }
  REQUIRE(trajectories[1].size() == 60);
  const double difference = maxPositionDifference(trajectories[1], trajectories[0]);
  INFO("max position difference " << difference * 1000 << " mm");
  CHECK(difference < 0.001);
}
