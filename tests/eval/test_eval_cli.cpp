// `slambooster eval` end to end: the JSON output agrees with the library on the same files, the table is
// printed by default, and user errors exit with 1 and say what is wrong.

#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "tests/eval/eval_test_util.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace {

sb::test::CommandResult runEval(const std::string& args) {
  return sb::test::runCommand(std::string(SB_SLAMBOOSTER_BIN) + " eval " + args);
}

// Ground truth and an estimate with a per-frame drift, written as TUM files in a scratch directory.
struct Files {
  std::string estimate, groundTruth, dir;
};

Files writeFiles(const std::string& name, double estimateTimeShiftS) {
  Files f;
  f.dir = sb::test::scratchDir(name);
  f.groundTruth = f.dir + "/gt.txt";
  f.estimate = f.dir + "/est.txt";
  const auto gt = sb::test::helixTrajectory(120);
  auto est = gt;
  for (size_t i = 0; i < est.size(); ++i) {
    est[i].T_camera_to_world.translation() +=
        Eigen::Vector3d(0.001, -0.0005, 0.002) * static_cast<double>(i % 7);
    est[i].timestamp += estimateTimeShiftS;
  }
  sb::writeTumTrajectory(f.groundTruth, gt);
  sb::writeTumTrajectory(f.estimate, est);
  return f;
}

}  // namespace

TEST_CASE("slambooster eval --json agrees with the library on the same files", "[eval][cli]") {
  const Files f = writeFiles("eval_cli_json", 0.0);
  const std::string csv = f.dir + "/ite.csv";
  const sb::test::CommandResult r = runEval("--json --ite-csv " + csv + " " + f.estimate + " " + f.groundTruth);
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  const auto j = nlohmann::json::parse(r.output);
  const auto est = sb::readTumTrajectory(f.estimate), gt = sb::readTumTrajectory(f.groundTruth);
  const auto ate = sb::computeAte(est, gt);
  const auto rpe = sb::computeRpe(est, gt, 1, false);
  CHECK(j.at("class") == "EVAL");
  CHECK(j.at("matches").get<size_t>() == ate.matches);
  CHECK(j.at("ate").at("rmse_m").get<double>() == Approx(ate.rmse).margin(1e-12));
  CHECK(j.at("ate").at("median_m").get<double>() == Approx(ate.median).margin(1e-12));
  CHECK(j.at("unaligned_mean_m").get<double>() == Approx(ate.unalignedMean).margin(1e-12));
  CHECK(j.at("rpe_frames").at("translation_rmse_m").get<double>() ==
        Approx(rpe.translationRmse).margin(1e-12));
  CHECK(j.at("rpe_seconds").at("pairs").get<size_t>() == 90);  // 120 poses at 30 Hz, partners 30 frames later
  CHECK(ate.rmse > 1e-4);
  std::ifstream in(csv);
  std::string header;
  CHECK((std::getline(in, header) && header == "timestamp,ate_error_m,unaligned_error_m"));
}

TEST_CASE("slambooster eval prints a table by default and honours --offset", "[eval][cli]") {
  const Files f = writeFiles("eval_cli_table", 50.0);
  const sb::test::CommandResult shifted = runEval(f.estimate + " " + f.groundTruth);
  CHECK(shifted.exitCode == 1);
  CHECK_THAT(shifted.output, Catch::Contains("no overlap in time") && Catch::Contains("gt.txt") &&
                                 Catch::Contains("50.000000 .. "));
  const sb::test::CommandResult r = runEval("--offset -50 " + f.estimate + " " + f.groundTruth);
  INFO(r.output);
  CHECK(r.exitCode == 0);
  CHECK_THAT(r.output, Catch::Contains("matches       120") && Catch::Contains("ATE (aligned) rmse") &&
                           Catch::Contains("RPE over 1 frame") && Catch::Contains("RPE over 1 s"));
}

TEST_CASE("slambooster eval exits 1 with a message on bad input", "[eval][cli][errors]") {
  const Files f = writeFiles("eval_cli_errors", 0.0);
  const sb::test::CommandResult missing = runEval(f.dir + "/absent.txt " + f.groundTruth);
  CHECK(missing.exitCode == 1);
  CHECK_THAT(missing.output, Catch::Contains("cannot open trajectory"));
  const sb::test::CommandResult badDelta = runEval("--rpe-delta 1.5 " + f.estimate + " " + f.groundTruth);
  CHECK(badDelta.exitCode == 1);
  CHECK_THAT(badDelta.output, Catch::Contains("whole number"));
  const sb::test::CommandResult badDt = runEval("--max-dt -1 " + f.estimate + " " + f.groundTruth);
  CHECK(badDt.exitCode == 1);
}
