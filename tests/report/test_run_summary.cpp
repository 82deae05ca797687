// report/run_summary.h: summary.json's type round-trips, refuses wrong types and newer schemas by key, and
// reads a summary from before the type.

#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "report/run_summary.h"
#include "tests/support/test_data.h"

using Catch::Matchers::Contains;
using sb::RunSummary;
using json = nlohmann::json;

namespace {

RunSummary sample() {
  RunSummary s;
  s.frontEnd = "daemon";
  s.sequence = "/data/seq";
  s.controller = "adaptive";
  s.controllerSections = {{"adaptive", {{"confirm_translation_m", 0.01}}}};
  s.knobs = {{"csr", 2}};
  s.config = {{"volume_resolution", 64}};
  s.threads = 4;
  s.machine = sb::MachineInfo{"host", "cpu", 8, 4, "cpu", "cpu"};
  s.daemon = sb::DaemonPass{2, "4-7", 4};
  s.frames = 30;
  s.trackingAttempted = 29;
  s.tracked = 28;
  s.trackedPercent = 100.0 * 28 / 29;
  s.stageMsPerFrame = {{"track", 1.5}};
  s.triggers = {{"retrack", 3}};
  s.knobFrames = {{"csr=2", 30}};
  s.controllerFrames = {{"adaptive", 20}, {"fixed", 10}};
  s.trackingState.frames = {{"good", 29}, {"lost", 1}};
  s.trackingState.lostStretches = 1;
  s.ate = sb::AteSummary{0.01, 0.009, 0.03, 0.008, 0.05, 28};
  s.cpuMsPerFrame = 12.5;
  s.stopped = sb::StoppedSummary{30, 100.0, 101.0};
  s.interrupted = sb::InterruptedSummary{"SIGTERM", 30};
  s.odometry = sb::OdometrySummary{"seq/odometry.txt", 812, 30, 2.25};
  s.energy = {{"joules_per_frame", 0.25}, {"mean_watts", 5.0}};
  s.modelView = "overview";
  s.movingVolume = {{"shifts", 3}};
  s.navmap = {{"grid", true}};
  s.meshTriangles = 1000;
  s.meshSlabs = 2;
  s.complete = false;
  s.error = "disk full";
  return s;
}

}  // namespace

TEST_CASE("RunSummary: every field survives toJson and fromJson", "[report][summary]") {
  const RunSummary s = sample();
  const json written = s.toJson();
  const RunSummary back = RunSummary::fromJson(written, "summary.json");
  CHECK(back.toJson() == written);
  CHECK(back.schemaVersion == sb::kRunSummarySchema);
  CHECK(back.daemon->cpus == "4-7");
  CHECK(back.ate->matches == 28);
  CHECK(back.odometry->framesWithPose == 30);
  CHECK(written["odometry"]["source"] == "seq/odometry.txt");
  CHECK(back.joulesPerFrame() == 0.25);
  CHECK(back.energyNumber("mean_watts") == 5.0);
  CHECK(std::isnan(RunSummary{}.joulesPerFrame()));
  // The keys the scripts read stay where they were.
  CHECK(written["computation_ms_per_frame"].is_number());
  CHECK(written["ate"]["rmse_m"] == 0.01);
  CHECK(written["tracking_state"]["frames"]["lost"] == 1);
}

TEST_CASE("RunSummary: optional sections are absent until set", "[report][summary]") {
  const json j = RunSummary{}.toJson();
  for (const char* key : {"ate", "ate_error", "machine", "daemon", "stopped", "energy", "complete",
                          "moving_volume", "mesh_triangles", "error", "model_view", "cpu_ms_per_frame", "odometry"})
    CHECK_FALSE(j.contains(key));
  CHECK(j["schema_version"] == sb::kRunSummarySchema);
}

TEST_CASE("RunSummary: a wrong type is refused naming the file and the dotted key", "[report][summary]") {
  json j = sample().toJson();
  j["ate"]["rmse_m"] = "small";
  CHECK_THROWS_WITH(
      RunSummary::fromJson(j, "run summary 'x/summary.json'"),
      Contains("x/summary.json") && Contains("\"ate.rmse_m\"") && Contains("expected a number"));
  j = sample().toJson();
  j["frames"] = -3;
  CHECK_THROWS_WITH(RunSummary::fromJson(j, "s"), Contains("\"frames\"") && Contains("count"));
  j = sample().toJson();
  j["machine"] = "laptop";
  CHECK_THROWS_WITH(RunSummary::fromJson(j, "s"), Contains("\"machine\"") && Contains("an object"));
  CHECK_THROWS_AS(RunSummary::fromJson(json::array(), "s"), sb::Error);
}

TEST_CASE("RunSummary: a newer schema is refused, an older summary is read", "[report][summary]") {
  json j = sample().toJson();
  j["schema_version"] = sb::kRunSummarySchema + 1;
  CHECK_THROWS_WITH(RunSummary::fromJson(j, "s"), Contains("newer"));
  // A daemon summary from before the type: no version, no controller, null ATE-less fields.
  const json old = {{"frames", 10},
                    {"tracked_percent", 90.0},
                    {"computation_ms_per_frame", 3.0},
                    {"controller_frames", {{"adaptive", 10}}},
                    {"daemon", {{"pass", 1}, {"cpus", "0"}, {"threads", 1}}},
                    {"energy", {{"joules_per_frame", nullptr}}},
                    {"complete", true},
                    {"unknown_later_key", 1}};
  const RunSummary s = RunSummary::fromJson(old, "s");
  CHECK(s.schemaVersion == 0);
  CHECK(s.frames == 10);
  CHECK(s.controller.empty());
  CHECK(s.controllerFrames.at("adaptive") == 10);
  CHECK(std::isnan(s.joulesPerFrame()));
  CHECK(s.complete == true);
  CHECK_FALSE(s.machine);
}

TEST_CASE("RunSummary: completion is read alone, so a damaged field does not hide a finished run",
          "[report][summary]") {
  const std::string dir = sb::test::scratchDir("run_summary_complete");
  json j = sample().toJson();
  j["complete"] = true;
  j["tracked_percent"] = "x";  // bench reports it (file, key, value) and leaves the run out; never reruns it
  std::ofstream(dir + "/done.json") << j.dump();
  CHECK(sb::runSummaryComplete(dir + "/done.json"));
  CHECK_THROWS_WITH(sb::readRunSummary(dir + "/done.json"), Contains("tracked_percent") && Contains("\"x\""));
  std::ofstream(dir + "/running.json") << R"({"frames": 3})";
  CHECK_FALSE(sb::runSummaryComplete(dir + "/running.json"));
  std::ofstream(dir + "/torn.json") << R"({"complete": tr)";
  CHECK_FALSE(sb::runSummaryComplete(dir + "/torn.json"));
  CHECK_FALSE(sb::runSummaryComplete(dir + "/absent.json"));
}
