// `slambooster eval EST GT`: ATE (Horn-aligned, TUM convention), the SLAMBooster paper's unaligned mean
// error and RPE of an estimated TUM trajectory against ground truth; a table by default, JSON with --json.

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {
namespace {

constexpr double kCmPerM = 100.0;

struct EvalArgs {
  std::string estimatePath, groundTruthPath, iteCsvPath;
  bool json = false;
  double maxDtS = AssociationOptions{}.maxTimeDifference;
  double offsetS = 0.0;
  double rpeDelta = 1.0;
  bool rpePerSecond = false;
  std::vector<std::string> frameOf;  // EST1 GT1: the alignment fitted on them, not on EST / GT
  std::optional<double> fromS;       // only the estimate's poses at or after this time
};

// One RPE measurement: its delta and unit, and the result or why there is none.
struct RpeRow {
  double delta = 1.0;
  bool perSecond = false;
  std::optional<RpeResult> result;
  std::string unavailable;
};

nlohmann::json rpeJson(const RpeRow& row) {
  nlohmann::json j = {{row.perSecond ? "delta_s" : "delta_frames", row.delta}};
  if (!row.result) {
    j["error"] = row.unavailable;
    return j;
  }
  const RpeResult& r = *row.result;
  j["pairs"] = r.pairs;
  j["translation_rmse_m"] = r.translationRmse;
  j["translation_mean_m"] = r.translationMean;
  j["rotation_rmse_deg"] = r.rotationRmse;
  j["rotation_mean_deg"] = r.rotationMean;
  return j;
}

nlohmann::json toJson(const EvalArgs& a, const AteResult& ate, const RpeRow& frames, const RpeRow& seconds) {
  const Eigen::Matrix3d R = ate.alignment.linear();
  const Eigen::Vector3d t = ate.alignment.translation();
  nlohmann::json j;
  j["class"] = "EVAL";
  j["estimate"] = a.estimatePath;
  j["ground_truth"] = a.groundTruthPath;
  j["max_dt_s"] = a.maxDtS;
  j["offset_s"] = a.offsetS;
  j["matches"] = ate.matches;
  j["ate"] = {{"rmse_m", ate.rmse}, {"mean_m", ate.mean}, {"median_m", ate.median}, {"max_m", ate.max}};
  j["unaligned_mean_m"] = ate.unalignedMean;
  j["alignment"] = {
      {"rotation", {{R(0, 0), R(0, 1), R(0, 2)}, {R(1, 0), R(1, 1), R(1, 2)}, {R(2, 0), R(2, 1), R(2, 2)}}},
      {"translation_m", {t.x(), t.y(), t.z()}}};
  j["rpe_frames"] = rpeJson(frames);
  j["rpe_seconds"] = rpeJson(seconds);
  if (a.frameOf.size() == 2) j["frame_of"] = a.frameOf;
  if (a.fromS) j["from_s"] = *a.fromS;
  j["ite_csv"] = a.iteCsvPath.empty() ? nlohmann::json(nullptr) : nlohmann::json(a.iteCsvPath);
  return j;
}

void printRpeRow(const RpeRow& row) {
  char label[64];
  std::snprintf(label, sizeof label, "RPE over %g %s", row.delta,
                row.perSecond ? "s" : (row.delta == 1 ? "frame" : "frames"));
  if (!row.result) {
    std::printf("%-24s n/a (%s)\n", label, row.unavailable.c_str());
    return;
  }
  const RpeResult& r = *row.result;
  std::printf("%-24s trans rmse %8.3f cm  mean %8.3f cm | rot rmse %7.3f deg  mean %7.3f deg  (%zu pairs)\n",
              label, r.translationRmse * kCmPerM, r.translationMean * kCmPerM, r.rotationRmse, r.rotationMean,
              r.pairs);
}

void printTable(const EvalArgs& a, const AteResult& ate, const RpeRow& frames, const RpeRow& seconds) {
  std::printf("estimate      %s\nground truth  %s\n", a.estimatePath.c_str(), a.groundTruthPath.c_str());
  std::printf("matches       %zu (max dt %g s, offset %g s)\n", ate.matches, a.maxDtS, a.offsetS);
  std::printf("ATE (aligned) rmse %8.3f cm  mean %8.3f cm  median %8.3f cm  max %8.3f cm\n",
              ate.rmse * kCmPerM, ate.mean * kCmPerM, ate.median * kCmPerM, ate.max * kCmPerM);
  std::printf(
      "unaligned     mean %8.3f cm (relative to the first matched pose, as in the SLAMBooster paper)\n",
      ate.unalignedMean * kCmPerM);
  printRpeRow(frames);
  printRpeRow(seconds);
  if (!a.iteCsvPath.empty()) std::printf("per-frame errors written to %s\n", a.iteCsvPath.c_str());
}

// The requested RPE (delta in the chosen unit) must succeed; the other unit (delta 1) is reported when
// possible.
RpeRow measureRpe(const Trajectory& est, const Trajectory& gt, double delta, bool perSecond,
                  const AssociationOptions& o, bool required) {
  RpeRow row;
  row.delta = delta;
  row.perSecond = perSecond;
  try {
    row.result = computeRpe(est, gt, delta, perSecond, o);
  } catch (const Error& e) {
    if (required) throw;
    row.unavailable = e.what();
  }
  return row;
}

void runEval(const EvalArgs& a) {
  Trajectory est = readTumTrajectory(a.estimatePath);
  const Trajectory gt = readTumTrajectory(a.groundTruthPath);
  if (a.fromS)
    est.erase(std::remove_if(est.begin(), est.end(), [&](const TimedPose& p) { return p.timestamp < *a.fromS; }),
              est.end());
  AssociationOptions o;
  o.maxTimeDifference = a.maxDtS;
  o.timeOffset = a.offsetS;
  const std::string where = "evaluating '" + a.estimatePath + "' against '" + a.groundTruthPath + "': ";
  try {
    std::optional<Eigen::Isometry3d> frame;
    if (a.frameOf.size() == 2) {  // the first run's frame (fitted on its whole poses), applied here unchanged
      const Trajectory est1 = readTumTrajectory(a.frameOf[0]), gt1 = readTumTrajectory(a.frameOf[1]);
      frame = alignFrames(est1, gt1, o);
    }
    const AteResult ate = computeAte(est, gt, o, frame ? &*frame : nullptr);
    const RpeRow frames = measureRpe(est, gt, a.rpePerSecond ? 1.0 : a.rpeDelta, false, o, !a.rpePerSecond);
    const RpeRow seconds = measureRpe(est, gt, a.rpePerSecond ? a.rpeDelta : 1.0, true, o, a.rpePerSecond);
    if (!a.iteCsvPath.empty()) writeIteCsv(a.iteCsvPath, ate);
    if (a.json) {
      std::cout << toJson(a, ate, frames, seconds).dump() << "\n";
    } else {
      printTable(a, ate, frames, seconds);
    }
  } catch (const Error& e) {
    throw Error(where + e.what());
  }
}

}  // namespace

void addEvalCommand(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  auto* sub = app.add_subcommand(
      "eval", "ATE / unaligned error / RPE of an estimated TUM trajectory vs ground truth");
  sub->add_option("EST", args->estimatePath, "estimated trajectory (TUM format)")->required();
  sub->add_option("GT", args->groundTruthPath, "ground-truth trajectory (TUM format)")->required();
  sub->add_flag("--json", args->json, "print one JSON object instead of the table");
  sub->add_option("--frame-of", args->frameOf,
                  "EST1 GT1: measure EST in the frame fitted on another run (EST1 against GT1, whole poses: positions\n"
                  "and orientations) instead of fitting it: a run started in a kept map (--map-store), in the frame\n"
                  "of the run that made the map")
      ->expected(2);
  sub->add_option("--from-s", args->fromS, "only the estimate's poses at or after this time (seconds)");
  sub->add_option("--ite-csv", args->iteCsvPath,
                  "write per-frame errors: timestamp,ate_error_m,unaligned_error_m");
  sub->add_option("--max-dt", args->maxDtS, "max timestamp difference for a match (s)")
      ->capture_default_str();
  sub->add_option("--offset", args->offsetS, "seconds added to the estimate's timestamps before matching")
      ->capture_default_str();
  sub->add_option("--rpe-delta", args->rpeDelta, "RPE delta in frames (or seconds with --rpe-per-second)")
      ->capture_default_str();
  sub->add_flag("--rpe-per-second", args->rpePerSecond,
                "measure --rpe-delta in seconds (the other RPE row then uses 1 frame)");
  sub->callback([args] { runEval(*args); });
}

}  // namespace sb::cli
