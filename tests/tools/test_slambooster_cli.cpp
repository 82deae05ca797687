// `slambooster` end to end, as a user would run it: render a synthetic sequence, reconstruct it, evaluate
// the trajectory, and get clear errors with exit code 1 for bad input.

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/report/markup_check.h"
#include "tests/support/constant_power.h"
#include "tests/support/files.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace fs = std::filesystem;
using sb::test::readJson;
using sb::test::readText;
using sb::test::runCommand;

namespace {

const std::string kTool = SB_SLAMBOOSTER_BIN;


// results.csv of bench: (sequence, controller) -> column -> value.
std::map<std::pair<std::string, std::string>, std::map<std::string, double>> readResults(
    const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> columns;
  std::map<std::pair<std::string, std::string>, std::map<std::string, double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> fields;
    std::istringstream split(line);
    for (std::string f; std::getline(split, f, ',');) fields.push_back(f);
    if (columns.empty()) {
      columns = fields;
      continue;
    }
    REQUIRE(fields.size() == columns.size());
    auto& row = rows[{fields[0], fields[1]}];
    for (size_t i = 2; i < fields.size(); ++i)
      if (columns[i] != "reference") row[columns[i]] = std::stod(fields[i]);  // "nan" reads as NaN
  }
  return rows;
}

// Bench's report.html: well-formed and self-contained, every number of its main table (cells keyed
// main/<sequence>/<controller>/<column>, main/<sequence>/time_cut_percent, main/geomean/time_cut_percent) the
// value of results.csv at the shown precision, and every link a relative path to an existing file.
void checkBenchPage(const std::string& benchDir, size_t sequences, size_t runs) {
  const std::string html = readText(benchDir + "/report.html");
  const sb::test::MarkupCheck page = sb::test::checkMarkup(html);
  for (const auto& e : page.errors) INFO(e);
  REQUIRE(page.errors.empty());
  CHECK(html.find("<script") == std::string::npos);
  CHECK(page.find("img").empty());      // the figures are inline SVG
  CHECK(page.find("svg").size() >= 4);  // time and ATE bars, ITE and csr trace

  const auto csv = readResults(benchDir + "/results.csv");
  const auto shown = [](const sb::test::MarkupElement* cell, double expected, int decimals) {
    INFO(cell->attributes.at("data-key") << " = '" << cell->text << "', results.csv " << expected);
    if (!std::isfinite(expected)) {
      CHECK(cell->text == "-");
      return;
    }
    CHECK(std::abs(std::stod(cell->text) - expected) <= 0.5 * std::pow(10.0, -decimals) + 1e-3);
  };
  size_t checked = 0;
  double logRatio = 0;
  int pairs = 0;
  for (const auto* td : page.find("td")) {
    const auto key = td->attributes.find("data-key");
    if (key == td->attributes.end() || key->second.rfind("main/", 0) != 0) continue;
    std::vector<std::string> parts;
    std::istringstream split(key->second);
    for (std::string p; std::getline(split, p, '/');) parts.push_back(p);
    ++checked;
    if (parts.size() == 4) {
      const auto& row = csv.at({parts[1], parts[2]});
      const std::string& column = parts[3];
      if (column == "ate_rmse_cm")
        shown(td, row.at("ate_rmse_m") * 100, 2);
      else
        shown(td, row.at(column), column == "frames" ? 0 : 1);
    } else {
      REQUIRE(parts.size() == 3);
      CHECK(parts[2] == "time_cut_percent");
      if (parts[1] == "geomean") {
        shown(td, 100.0 * (1.0 - std::exp(logRatio / pairs)), 1);
        continue;
      }
      const double d = csv.at({parts[1], "default"}).at("computation_ms_per_frame");
      const double b = csv.at({parts[1], "slambooster"}).at("computation_ms_per_frame");
      shown(td, 100.0 * (1.0 - b / d), 1);
      logRatio += std::log(b / d);
      ++pairs;
    }
  }
  CHECK(checked == 8 * sequences + 1);  // per sequence: 7 numbers and the time cut; the geomean

  size_t runReports = 0;
  for (const auto* a : page.find("a")) {
    const std::string& href = a->attributes.at("href");
    INFO(href);
    CHECK(href.find(':') == std::string::npos);  // no scheme: nothing fetched, nothing absolute
    CHECK(href.front() != '/');
    CHECK(fs::is_regular_file(fs::path(benchDir) / href));
    runReports += fs::path(href).filename() == "report.html";
  }
  CHECK(runReports == runs);
}

// The "k of n" texts of the TC table for one tc column, from results.csv as tcSection defines them: error
// violations = tc ATE >= 5 cm or NaN; better time = tc ms/frame below slambooster's.
std::pair<std::string, std::string> tcCounts(
    const std::map<std::pair<std::string, std::string>, std::map<std::string, double>>& csv,
    const std::vector<std::string>& sequences, const std::string& label) {
  int bad = 0, faster = 0;
  for (const std::string& s : sequences) {
    const auto& t = csv.at({s, label});
    bad += !(t.at("ate_rmse_m") < 0.05);
    faster += t.at("computation_ms_per_frame") < csv.at({s, "slambooster"}).at("computation_ms_per_frame");
  }
  const std::string of = " of " + std::to_string(sequences.size());
  return {std::to_string(bad) + of, std::to_string(faster) + of};
}

}  // namespace

TEST_CASE("synth, run and eval agree end to end on a short synthetic sequence", "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_e2e");
  const std::string seq = dir + "/seq";
  const std::string out = dir + "/run";
  constexpr int kFrames = 40;

  const auto synth = runCommand(kTool + " synth --out " + seq + " --scene office --builtin-frames " +
                                std::to_string(kFrames) + " --no-noise");
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  REQUIRE(sb::test::dataLines(seq + "/depth.txt") == kFrames);
  REQUIRE(sb::test::dataLines(seq + "/groundtruth.txt") == kFrames);

  const auto run = runCommand(kTool + " run " + seq + " --out " + out + " --preset default --mesh --quiet");
  INFO(run.output);
  REQUIRE(run.exitCode == 0);
  for (const char* f : {"trajectory.tum", "frames.jsonl", "summary.json", "model.png", "mesh.ply", "report.html"}) {
    INFO(f);
    CHECK(fs::file_size(fs::path(out) / f) > 0);
  }
  CHECK_THAT(run.output, Catch::Contains("report " + out + "/report.html"));
  CHECK(sb::test::dataLines(out + "/trajectory.tum") == kFrames);
  CHECK(sb::test::dataLines(out + "/frames.jsonl") == kFrames);

  const auto summary = readJson(out + "/summary.json");
  CHECK(summary.at("frames").get<int>() == kFrames);
  const double summaryAte = summary.at("ate").at("rmse_m").get<double>();
  // Noise-free synthetic depth and a slow camera: KinectFusion must stay within a couple of centimetres.
  CHECK(summaryAte < 0.02);

  // The trajectory on disk, evaluated by `slambooster eval`, gives the ATE the summary reports.
  const auto eval = runCommand(kTool + " eval --json " + out + "/trajectory.tum " + seq + "/groundtruth.txt");
  INFO(eval.output);
  REQUIRE(eval.exitCode == 0);
  const auto evalJson = nlohmann::json::parse(eval.output);
  CHECK(evalJson.at("ate").at("rmse_m").get<double>() == Approx(summaryAte).margin(1e-6));
}

TEST_CASE("slambooster reports bad input with exit code 1 and says what is wrong", "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_errors");

  const auto missing = runCommand(kTool + " run " + dir + "/no-such-seq --out " + dir + "/o --quiet");
  CHECK(missing.exitCode == 1);
  CHECK_THAT(missing.output, Catch::Contains("no-such-seq"));

  const std::string seq = dir + "/seq";
  REQUIRE(runCommand(kTool + " synth --out " + seq + " --builtin-frames 3 --no-noise").exitCode == 0);
  const auto badKnob = runCommand(kTool + " run " + seq + " --out " + dir + "/o --knobs csr=3 --quiet");
  CHECK(badKnob.exitCode == 1);
  CHECK_THAT(badKnob.output, Catch::Contains("csr"));

  const auto badScene = runCommand(kTool + " synth --out " + dir + "/s2 --builtin-frames 3 --scene castle");
  CHECK(badScene.exitCode != 0);
  CHECK_THAT(badScene.output, Catch::Contains("castle") || Catch::Contains("scene"));

  const auto noCommand = runCommand(kTool);
  CHECK(noCommand.exitCode == 2);
}

TEST_CASE("synth --stress renders a stress trajectory and names its parts in segments.csv", "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_stress");
  const auto r = runCommand(kTool + " synth --out " + dir + "/s --stress blank-wall --scene office --frames 12" +
                            " --width 80 --height 60 --fx 60.15 --fy 60 --threads 1");
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  CHECK_THAT(r.output, Catch::Contains("wrote 12 frames"));
  std::ifstream csv(dir + "/s/segments.csv");
  std::string header, first, rest;
  std::getline(csv, header);
  std::getline(csv, first);
  CHECK(header == "label,begin_frame,end_frame");
  CHECK(first == "furnished,0,12");  // the later segments start after the 12 rendered frames
  CHECK_FALSE(std::getline(csv, rest));

  const auto two = runCommand(kTool + " synth --out " + dir + "/t --stress bursts --builtin-frames 3");
  CHECK(two.exitCode != 0);
  const auto unknown = runCommand(kTool + " synth --out " + dir + "/u --stress spin");
  CHECK(unknown.exitCode != 0);
  CHECK_THAT(unknown.output, Catch::Contains("spin"));
}

TEST_CASE("run takes the controller from --controller and from the config file's controller section", "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_controller");
  const std::string seq = dir + "/seq";
  REQUIRE(runCommand(kTool + " synth --out " + seq + " --builtin-frames 4 --no-noise").exitCode == 0);
  const std::string config = dir + "/config.json";
  std::ofstream(config) << R"({"volume_resolution": 64, "controller": {"name": "fixed", "fixed": {"knobs": "csr=4,ir=1"}}})";

  const auto fromFile = runCommand(kTool + " run " + seq + " --out " + dir + "/a --config " + config + " --quiet");
  INFO(fromFile.output);
  REQUIRE(fromFile.exitCode == 0);
  std::ifstream log(dir + "/a/frames.jsonl");
  std::string line;
  REQUIRE(std::getline(log, line));
  const auto first = nlohmann::json::parse(line);
  CHECK(first.at("controller") == "fixed");
  CHECK(first.at("knobs").at("csr") == 4);
  CHECK(first.at("knobs").at("ir") == 1);
  CHECK(readJson(dir + "/a/summary.json").at("controller") == "fixed");

  // --controller wins over the file's name; the sections stay.
  const auto flag = runCommand(kTool + " run " + seq + " --out " + dir + "/b --config " + config +
                               " --controller default --knobs csr=8 --frames 2 --quiet");
  INFO(flag.output);
  REQUIRE(flag.exitCode == 0);
  CHECK(readJson(dir + "/b/summary.json").at("controller") == "default");
  CHECK(readJson(dir + "/b/summary.json").at("knobs").at("csr") == 1);

  std::ofstream(dir + "/bad.json") << R"({"controller": {"name": "fixed", "fixed": {"knobz": "csr=2"}}})";
  const auto bad = runCommand(kTool + " run " + seq + " --out " + dir + "/c --config " + dir + "/bad.json --quiet");
  CHECK(bad.exitCode == 1);
  CHECK_THAT(bad.output, Catch::Contains("bad.json") && Catch::Contains("knobz"));
  const auto unknown = runCommand(kTool + " run " + seq + " --out " + dir + "/d --controller fastest --quiet");
  CHECK(unknown.exitCode == 1);
  CHECK_THAT(unknown.output, Catch::Contains("fastest"));
}

TEST_CASE("run --model-view overview renders model.png from above the volume centre and says so",
          "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_model_view");
  const std::string seq = dir + "/seq";
  REQUIRE(runCommand(kTool + " synth --out " + seq + " --builtin-frames 3 --no-noise").exitCode == 0);
  const std::string run = kTool + " run " + seq + " --volume-resolution 64 --quiet";
  const auto last = runCommand(run + " --out " + dir + "/last");
  const auto overview = runCommand(run + " --out " + dir + "/overview --model-view overview");
  INFO(last.output << overview.output);
  REQUIRE(last.exitCode == 0);
  REQUIRE(overview.exitCode == 0);
  CHECK(readJson(dir + "/last/summary.json").at("model_view") == "last");
  CHECK(readJson(dir + "/overview/summary.json").at("model_view") == "overview");
  // Same model, another camera: another image.
  CHECK(readText(dir + "/overview/model.png") != readText(dir + "/last/model.png"));
  CHECK_THAT(readText(dir + "/overview/report.html"), Catch::Contains("from the overview viewpoint"));
  CHECK_THAT(readText(dir + "/last/report.html"), Catch::Contains("from the last camera pose"));

  const auto bad = runCommand(run + " --out " + dir + "/bad --model-view sideways");
  CHECK(bad.exitCode != 0);
  CHECK_THAT(bad.output, Catch::Contains("sideways"));
}

TEST_CASE("bench and dse run their matrix once, resume, and write their tables", "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_bench");
  const std::string seq = dir + "/seq";
  REQUIRE(runCommand(kTool + " synth --out " + seq + " --builtin-frames 6 --no-noise").exitCode == 0);
  std::ofstream(dir + "/small.json") << R"({"volume_resolution": 64})";
  const std::string bench = kTool + " bench " + seq + " --out " + dir + "/bench --config " + dir +
                            "/small.json --controllers default,slambooster --jobs 2";
  const auto first = runCommand(bench);
  INFO(first.output);
  REQUIRE(first.exitCode == 0);
  CHECK_THAT(first.output, Catch::Contains("DEFAULT vs SLAMBooster") && Catch::Contains("geomean"));
  CHECK(sb::test::dataLines(dir + "/bench/results.csv") == 4);  // header + default, slambooster, accurate
  for (const char* f : {"report.md", "time.svg", "ate.svg", "trace.svg"}) {
    INFO(f);
    CHECK(fs::file_size(fs::path(dir) / "bench" / f) > 0);
  }
  CHECK(readJson(dir + "/bench/runs/seq/slambooster/summary.json").at("controller") == "slambooster");
  checkBenchPage(dir + "/bench", 1, 3);
  // Resumed: nothing runs again.
  const auto again = runCommand(bench);
  REQUIRE(again.exitCode == 0);
  CHECK_THAT(again.output, Catch::Contains("3 already done, 0 to run"));

  const auto dse = runCommand(kTool + " dse " + seq + " --out " + dir + "/dse --config " + dir +
                              "/small.json --csr 4,8 --icp 1e-5 --pd0 4 --jobs 2 --max-ate 1.0");
  INFO(dse.output);
  REQUIRE(dse.exitCode == 0);
  const auto best = readJson(dir + "/dse/best.json");
  CHECK(best.at("settings") == 2);
  REQUIRE(best.at("best").is_object());
  CHECK(sb::test::dataLines(dir + "/dse/results.csv") == 3);
  // The offline controller replays it.
  std::ofstream(dir + "/offline.json") << R"({"volume_resolution": 64, "controller": {"name": "offline", "offline": {"result": ")"
                                       << dir << R"(/dse/best.json"}}})";
  const auto offline = runCommand(kTool + " run " + seq + " --out " + dir + "/offline --config " + dir + "/offline.json --quiet");
  INFO(offline.output);
  REQUIRE(offline.exitCode == 0);
  const int bestCsr = best.at("best").at("knobs").get<std::string>().rfind("csr=4", 0) == 0 ? 4 : 8;
  CHECK(readJson(dir + "/offline/summary.json").at("knobs").at("csr") == bestCsr);
  CHECK(readJson(dir + "/offline/summary.json").at("controller") == "offline");
}

TEST_CASE("bench runs tc once per profiling set and reports each set in the TC table", "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_bench_tc");
  const std::string seq = dir + "/seq";
  REQUIRE(runCommand(kTool + " synth --out " + seq + " --builtin-frames 6 --no-noise").exitCode == 0);
  std::ofstream(dir + "/small.json") << R"({"volume_resolution": 64})";
  // Two tables as `slambooster profile` writes them; the second from before tables recorded their sequences.
  // One entry each, so tc runs it. The two sets' error violations must differ, or a swapped column group would
  // not show; that must not hang on how the room is furnished (integrating every 6th frame used to lose this
  // view, until the rooms got wall fixtures). So: tr=10 never tracks in 6 frames, every pose stays the first,
  // the ATE is undefined and counts as a violation; DEFAULT's knobs track this slow motion (0.32 cm here, the
  // livingroom at seed 0; 0.3-0.6 cm in both scenes at seeds 0-1).
  fs::create_directories(dir + "/profile-real");
  fs::create_directories(dir + "/synth");
  std::ofstream(dir + "/profile-real/tc_table.json") << R"({"reference_ms_per_frame": 100.0,
    "sequences": ["/data/7scenes-redkitchen-a", "/out/sequences/synth-office-traj2/"],
    "entries": [{"knobs": "csr=1,icp=1e-05,pd=10:5:4,tr=10,ir=6", "ms_per_frame": 50.0, "speedup": 2.0, "ate_m": 0.01}]})";
  std::ofstream(dir + "/synth/tc_table.json") << R"({"reference_ms_per_frame": 90.0,
    "entries": [{"knobs": "csr=1,icp=1e-05,pd=10:5:4,tr=1,ir=2", "ms_per_frame": 15.0, "speedup": 6.0, "ate_m": 0.02}]})";
  const std::string common = kTool + " bench " + seq + " --out " + dir + "/bench --config " + dir +
                             "/small.json --controllers default,slambooster --jobs 2";
  const std::string bench = common + " --tc-table real=" + dir + "/profile-real/tc_table.json --tc-table " + dir +
                            "/synth/tc_table.json --tc-velocities 0.01,0.02";
  const auto first = runCommand(bench);
  INFO(first.output);
  REQUIRE(first.exitCode == 0);

  // One tc column per set and velocity, each run with its own table.
  const auto csv = readResults(dir + "/bench/results.csv");
  CHECK(csv.size() == 7);  // default, slambooster, accurate, 2 sets x 2 velocities
  for (const std::string set : {"real", "synth"})
    for (const std::string v : {"0.010", "0.020"}) {
      const std::string label = "tc-" + set + "@" + v;
      INFO(label);
      CHECK(csv.count({"seq", label}) == 1);
      CHECK(readJson(dir + "/bench/runs/seq/" + label + "/summary.json").at("controller") == "tc");
      const auto config = readJson(dir + "/bench/configs/tc-" + set + "_" + v + ".json");
      CHECK_THAT(config.at("controller").at("tc").at("table").get<std::string>(),
                 Catch::EndsWith((set == "real" ? "/profile-real" : "/synth") + std::string("/tc_table.json")));
    }
  checkBenchPage(dir + "/bench", 1, 7);

  // The TC table: rows = velocities, a column group per set, numbers as results.csv gives them.
  const std::string md = readText(dir + "/bench/report.md");
  CHECK_THAT(md, Catch::Contains("| v_ref m/frame | real: error violations (ATE >= 5 cm) | real: better time than "
                                 "SLAMBooster | synth: error violations (ATE >= 5 cm) | synth: better time than "
                                 "SLAMBooster |"));
  CHECK_THAT(md, Catch::Contains("`real`: table `" + dir +
                                 "/profile-real/tc_table.json`, profiled on 7scenes-redkitchen-a, synth-office-traj2"));
  CHECK_THAT(md, Catch::Contains("`synth`: table") && Catch::Contains("profiled sequences not recorded"));
  const sb::test::MarkupCheck page = sb::test::checkMarkup(readText(dir + "/bench/report.html"));
  std::map<std::string, std::string> shown;
  for (const auto* td : page.find("td")) {
    const auto key = td->attributes.find("data-key");
    if (key != td->attributes.end() && key->second.rfind("tc/", 0) == 0) shown[key->second] = td->text;
  }
  CHECK(shown.size() == 8);
  for (const std::string v : {"0.010", "0.020"}) {
    std::string row = "| " + v + " |";
    for (const std::string set : {"real", "synth"}) {
      const auto [violations, faster] = tcCounts(csv, {"seq"}, "tc-" + set + "@" + v);
      INFO(set << " @ " << v);
      CHECK(shown["tc/" + set + "/" + v + "/error_violations"] == violations);
      CHECK(shown["tc/" + set + "/" + v + "/better_time"] == faster);
      row += " " + violations + " | " + faster + " |";
    }
    CHECK_THAT(md, Catch::Contains(row + "\n"));
    CHECK(shown["tc/real/" + v + "/error_violations"] != shown["tc/synth/" + v + "/error_violations"]);
  }

  // Per sequence: SLAMBooster and every tc column as ms/frame / ATE cm, with % tracked where below 100.
  CHECK_THAT(md, Catch::Contains("## TC vs SLAMBooster per sequence\n\nms/frame / ATE cm (% of frames tracked, "
                                 "where below 100)\n\n| sequence | slambooster | tc-real@0.010 | tc-real@0.020 | "
                                 "tc-synth@0.010 | tc-synth@0.020 |"));
  CHECK_THAT(md, Catch::Contains(" / - (0.0%) |"));  // tc-real: tr=10 never tracks, no ATE

  // Resumed: nothing runs again.
  const auto again = runCommand(bench);
  REQUIRE(again.exitCode == 0);
  CHECK_THAT(again.output, Catch::Contains("7 already done, 0 to run"));

  // One table without a name keeps the columns tc@v; the set is named after the table's directory.
  const auto single = runCommand(common + " --tc-table " + dir + "/profile-real/tc_table.json --tc-velocities 0.01");
  INFO(single.output);
  REQUIRE(single.exitCode == 0);
  CHECK_THAT(single.output, Catch::Contains("3 already done, 1 to run"));
  CHECK(readResults(dir + "/bench/results.csv").count({"seq", "tc@0.010"}) == 1);
  CHECK_THAT(readText(dir + "/bench/report.md"),
             Catch::Contains("| v_ref m/frame | profile-real: error violations (ATE >= 5 cm) |"));

  // Two sets of one name, or a missing table: refused before any run.
  const auto twice = runCommand(common + " --tc-table " + dir + "/synth/tc_table.json --tc-table synth=" + dir +
                                "/profile-real/tc_table.json");
  CHECK(twice.exitCode == 1);
  CHECK_THAT(twice.output, Catch::Contains("'synth'") && Catch::Contains("NAME=PATH"));
  const auto missing = runCommand(common + " --tc-table x=" + dir + "/nowhere.json");
  CHECK(missing.exitCode == 1);
  CHECK_THAT(missing.output, Catch::Contains("nowhere.json"));
}

TEST_CASE("run --power accounts joules per frame that offline re-accounting reproduces", "[tools][system]") {
  const std::string dir = sb::test::scratchDir("cli_power");
  const std::string seq = dir + "/seq";
  REQUIRE(runCommand(kTool + " synth --out " + seq + " --builtin-frames 8 --no-noise").exitCode == 0);
  std::ofstream(dir + "/small.json") << R"({"volume_resolution": 64})";
  // A recorded trace of a constant 4.5 W at 200 Hz, replayed live by the "file" meter.
  constexpr double kWatts = 4.5;
  sb::test::writeConstantPowerMeter(dir, kWatts);

  const std::string out = dir + "/run";
  const auto run = runCommand(kTool + " run " + seq + " --out " + out + " --config " + dir + "/small.json --power " +
                              dir + "/power.json --quiet");
  INFO(run.output);
  REQUIRE(run.exitCode == 0);
  CHECK_THAT(run.output, Catch::Contains("energy (file): 8/8 frames known") && Catch::Contains("J/frame"));

  // energy.jsonl: every frame known, its joules the constant power times the interval frames.jsonl logs.
  std::ifstream frames(out + "/frames.jsonl"), energy(out + "/energy.jsonl");
  double sum = 0.0;
  int n = 0;
  for (std::string f, e; std::getline(frames, f) && std::getline(energy, e); ++n) {
    const auto fj = nlohmann::json::parse(f), ej = nlohmann::json::parse(e);
    INFO("frame " << n);
    REQUIRE(ej.at("frame") == fj.at("frame"));
    CHECK(ej.at("t_start_mono_ns") == fj.at("t_start_mono_ns"));
    const int64_t start = fj.at("t_start_mono_ns"), end = fj.at("t_end_mono_ns");
    CHECK(end > start);
    REQUIRE(ej.at("known") == true);
    CHECK(ej.at("joules").get<double>() == Approx(kWatts * (end - start) * 1e-9).epsilon(1e-9));
    sum += ej.at("joules").get<double>();
  }
  CHECK(n == 8);
  const auto summary = readJson(out + "/summary.json").at("energy");
  CHECK(summary.at("known_frames") == 8);
  CHECK(summary.at("joules").get<double>() == Approx(sum).epsilon(1e-12));
  CHECK(summary.at("mean_watts").get<double>() == Approx(kWatts).epsilon(1e-9));
  CHECK(fs::file_size(out + "/power.csv") > 0);
  // The run's report plots the energy from energy.jsonl.
  std::ifstream reportFile(out + "/report.html");
  const std::string report((std::istreambuf_iterator<char>(reportFile)), std::istreambuf_iterator<char>());
  CHECK_THAT(report, Catch::Contains("Energy per frame") && !Catch::Contains("No power meter was used"));

  // bench --power: J/frame per run in results.csv and energy columns in the main table.
  const auto bench = runCommand(kTool + " bench " + seq + " --out " + dir + "/bench --config " + dir +
                                "/small.json --controllers default,slambooster --jobs 2 --quiet --power " + dir +
                                "/power.json");
  INFO(bench.output);
  REQUIRE(bench.exitCode == 0);
  CHECK_THAT(bench.output, Catch::Contains("running one job at a time") && Catch::Contains("SLAMBooster J/frame"));
  std::ifstream csv(dir + "/bench/results.csv");
  std::string header;
  std::getline(csv, header);
  CHECK(header.substr(header.rfind(',') + 1) == "joules_per_frame");
  int energyRows = 0;
  for (std::string row; std::getline(csv, row); ++energyRows) {
    INFO(row);
    const double jpf = std::stod(row.substr(row.rfind(',') + 1));
    CHECK(jpf > 0.0);
  }
  CHECK(energyRows == 3);  // default, slambooster, accurate

  // The trace and frame log written by the run re-account to the same joules offline.
  const auto offline =
      runCommand(kTool + " energy --trace " + out + "/power.csv --frames " + out + "/frames.jsonl --json");
  INFO(offline.output);
  REQUIRE(offline.exitCode == 0);
  const auto o = nlohmann::json::parse(offline.output);
  CHECK(o.at("known_frames") == 8);
  CHECK(o.at("joules").get<double>() == Approx(summary.at("joules").get<double>()).epsilon(1e-12));
}
