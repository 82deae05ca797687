// report/run_summary.h: summary.json's type round-trips, refuses wrong types and newer schemas by key, and
// reads a summary from before the type.

#include <algorithm>
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
  s.knobs = sb::Knobs{2, 1e-5, {8, 5, 4}, 1, 2};
  s.config = {{"volume_resolution", 64}, {"constrained_min_conditioning", 0.0003}};
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
  s.energy.emplace();
  s.energy->meter = "file";
  s.energy->frames = s.energy->knownFrames = 30;
  s.energy->joulesPerFrame = 0.25;
  s.energy->meanWatts = 5.0;
  s.energy->unknownReasons = {{"gap", 2}};
  s.modelView = "overview";
  s.movingVolume = sb::MovingVolumeSummary{3, 1.5, 20.0, {0.0, 0.0, 1.5625}, 170.0, 0.0, 20.25, 0};
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
  CHECK(back.meanWatts() == 5.0);
  CHECK(back.energy->unknownReasons.at("gap") == 2);
  CHECK(back.knobs->pyramidIterations[0] == 8);
  CHECK(back.movingVolume->cornerM[2] == 1.5625);
  CHECK(back.movingVolume->slabFilesRemoved == size_t(0));
  CHECK(back.constrainedMinConditioning() == 0.0003);
  CHECK(std::isnan(RunSummary{}.joulesPerFrame()));
  CHECK(std::isnan(RunSummary{}.constrainedMinConditioning()));
  // The keys the scripts read stay where they were.
  CHECK(written["computation_ms_per_frame"].is_number());
  CHECK(written["ate"]["rmse_m"] == 0.01);
  CHECK(written["tracking_state"]["frames"]["lost"] == 1);
  CHECK(written["knobs"] == json::parse(R"({"csr": 2, "icp": 1e-5, "pd": [8, 5, 4], "tr": 1, "ir": 2})"));
  CHECK(written["moving_volume"]["slab_queue_peak_mib"] == 20.25);
  CHECK(written["energy"]["known_frames"] == 30);
}

TEST_CASE("RunSummary: unknown energy is null, slab counts only with slabs", "[report][summary]") {
  RunSummary s;
  s.energy.emplace();  // a meter, no frame known yet
  s.movingVolume = sb::MovingVolumeSummary{};
  const json j = s.toJson();
  for (const char* key : {"joules_per_frame", "mean_watts", "span_mean_watts"}) CHECK(j["energy"][key].is_null());
  CHECK(j["energy"]["joules"] == 0.0);
  CHECK(j["energy"].dump().find("NaN") == std::string::npos);
  for (const char* key : {"slab_worker_ms", "slab_wait_ms", "slab_queue_peak_mib", "slab_files_removed"})
    CHECK_FALSE(j["moving_volume"].contains(key));
  const RunSummary back = RunSummary::fromJson(j, "s");
  CHECK(std::isnan(back.joulesPerFrame()));
  CHECK_FALSE(back.movingVolume->slabWorkerMs);
  CHECK(back.toJson() == j);
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
  // The typed sub-objects: each key's type, named with its dotted path.
  const std::vector<std::pair<json::json_pointer, json>> damaged = {
      {json::json_pointer("/energy/joules_per_frame"), "many"},
      {json::json_pointer("/energy/unknown_reasons"), json::array()},
      {json::json_pointer("/knobs/pd"), json::array({10, 5})},
      {json::json_pointer("/knobs/csr"), 1.5},
      {json::json_pointer("/moving_volume/corner_m"), json::array({0, "x", 0})},
      {json::json_pointer("/moving_volume/slab_files_removed"), -1},
      {json::json_pointer("/config/constrained_min_conditioning"), "tiny"}};
  for (const auto& [where, value] : damaged) {
    j = sample().toJson();
    j[where] = value;
    std::string dotted = where.to_string().substr(1);
    std::replace(dotted.begin(), dotted.end(), '/', '.');
    CAPTURE(dotted);
    CHECK_THROWS_WITH(RunSummary::fromJson(j, "s"), Contains("\"" + dotted + "\""));
  }
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

TEST_CASE("RunSummary: a run's directory or its summary file, a missing one named with the hint", "[report][summary]") {
  const std::string dir = sb::test::scratchDir("run_summary_dir");
  std::ofstream(dir + "/summary.json") << sample().toJson().dump();
  CHECK(sb::readRunDirSummary(dir).frames == 30);
  CHECK(sb::readRunDirSummary(dir + "/summary.json").frames == 30);
  CHECK_THROWS_WITH(sb::readRunDirSummary(dir + "/none", "did the run finish?"),
                    Contains("none/summary.json") && Contains("does not exist: did the run finish?"));
  CHECK_THROWS_WITH(sb::readRunDirSummary(dir + "/none"), Contains("does not exist") && !Contains(": did"));
}
