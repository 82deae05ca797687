// The report of a robot's run: a hand-made run directory of a 1200-frame drive with wheel odometry (3% long,
// a slip at frames 400-419, dead reckoning at 600-649, a verdict field the runtime does not write today) and a
// navigation grid. The odometry section and the grid are there, sized, and show the slip where it happened;
// verdicts the report has never heard of get their lane; runs without odometry or grid say so in one line;
// the comparison draws both paths on one grid; the page stays within twice the size of the same run's report
// without odometry and grid.

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "report/base64.h"
#include "report/odometry_view.h"
#include "report/png_codec.h"
#include "report/run_report.h"
#include "report/run_summary.h"
#include "report/text_escape.h"
#include "tests/report/markup_check.h"
#include "tests/support/test_data.h"

namespace fs = std::filesystem;
using nlohmann::json;
using sb::test::checkMarkup;
using sb::test::MarkupCheck;

namespace {

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in.good());
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  REQUIRE(out.good());
  out << text;
}

constexpr int kFrames = 1200;
constexpr double kStepM = 0.03;  // the camera's true step per frame along z

bool slipping(int i) { return i >= 400 && i < 420; }
bool deadReckoning(int i) { return i >= 600 && i < 650; }

Eigen::Vector3d truthAt(int i) { return {2.0 * std::sin(i * kStepM / 5.0), 0.0, i * kStepM}; }

// The nine classic stages' times of frame i, varying from frame to frame as measured ones do.
json stageTimes(int i) {
  json ms = json::object();
  int k = 0;
  for (const char* stage : {"mm2meters", "bilateralFilter", "halfSampleRobust", "depth2vertex", "vertex2normal", "track",
                            "reduce", "integrate", "raycast"}) {
    ms[stage] = 0.5 + 0.25 * k + 0.1 * std::sin(0.37 * i + k);
    ++k;
  }
  return ms;
}

struct RobotRun {
  std::string dir, sequence;
};

std::string tumLine(double t, const Eigen::Vector3d& p) {
  char line[160];
  std::snprintf(line, sizeof line, "%.6f %.9f %.9f %.9f 0 0 0 1\n", t, p.x(), p.y(), p.z());
  return line;
}

// odometry: wheels and verdicts in frames.jsonl and summary.json; grid: map.pgm, map.yaml, map_frame.json.
RobotRun makeRun(const std::string& name, bool odometry, bool grid, const std::string& extraVerdict = "fault") {
  const std::string root = sb::test::scratchDir("report_odometry_" + name);
  RobotRun r{root + "/run", root + "/seq"};
  fs::create_directories(r.dir);
  fs::create_directories(r.sequence);
  std::string truth = "# timestamp tx ty tz qx qy qz qw\n", wheels = truth, estimate = truth, frames;
  Eigen::Vector3d w = Eigen::Vector3d(5, 0, 1), e = truthAt(0);  // the wheels start elsewhere: their own frame
  for (int i = 0; i < kFrames; ++i) {
    const double t = 100.0 + i / 30.0;
    const Eigen::Vector3d step = i == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(truthAt(i) - truthAt(i - 1));
    const Eigen::Vector3d wheelStep = 1.03 * step + (slipping(i) ? Eigen::Vector3d(0, 0, 0.10) : Eigen::Vector3d::Zero());
    w += wheelStep;
    e += deadReckoning(i) ? wheelStep : step;
    truth += tumLine(t, truthAt(i));
    wheels += tumLine(t, w);
    estimate += tumLine(t, e);
    json line = {{"frame", i},
                 {"timestamp", t},
                 {"position", {e.x(), e.y(), e.z()}},
                 {"quaternion", {0, 0, 0, 1}},
                 {"knobs", {{"csr", 2}, {"icp", 1e-5}, {"pd", {10, 5, 4}}}},
                 {"ms", stageTimes(i)},
                 {"computation_ms", 9.5},
                 {"tracking_attempted", true},
                 {"tracked", !deadReckoning(i)},
                 {"state", deadReckoning(i) ? "odometry" : "good"},
                 {"velocity_m_per_frame", kStepM},
                 {"triggers", json::array()}};
    if (odometry) {
      line["odometry"] = {{"available", i > 0},
                          {"used", i > 0 && !slipping(i)},
                          {"rejected", slipping(i)},
                          {"drift_m", deadReckoning(i) ? (i - 599) * kStepM : 0.0}};
      if (slipping(i)) {
        line["odometry"]["why"] = "the wheels' step " + std::to_string(13 + i % 3) + " cm against the view's 3 cm";
        line["odometry"][extraVerdict] = "slipping";  // a field the report's code never names
      }
      if (i == 0) line["odometry"]["why"] = "no previous pose";
      line["odometry"]["scale_error"] = 0.03 * (1.0 - std::exp(-i / 200.0));  // a per-frame value, if logged
    }
    frames += line.dump() + "\n";
  }
  writeText(r.sequence + "/groundtruth.txt", truth);
  writeText(r.dir + "/trajectory.tum", estimate);
  writeText(r.dir + "/frames.jsonl", frames);
  sb::Image<uint8_t> model(64, 48, 128);
  const auto png = sb::report::encodePng(model);
  std::ofstream(r.dir + "/model.png", std::ios::binary).write(reinterpret_cast<const char*>(png.data()), png.size());

  sb::RunSummary s;
  s.frontEnd = "run";
  s.sequence = r.sequence;
  s.controller = "adaptive";
  s.frames = s.trackingAttempted = kFrames;
  s.tracked = kFrames - 50;
  s.trackedPercent = 100.0 * s.tracked / kFrames;
  s.computationMsPerFrame = 9.5;
  s.stageMsPerFrame = {{"preprocess", 1.5}, {"track", 4.25}};
  json summary;
  if (odometry) {
    sb::OdometrySummary o;
    o.source = r.sequence + "/odometry.txt";
    o.samples = o.framesWithPose = kFrames;
    o.pathM = 37.9;
    o.scaleError = 0.0297;
    o.yawScaleError = -0.004;
    o.yawBiasDegPerS = 0.02;
    o.calibrationFrames = 1100;
    s.odometry = o;
    writeText(r.sequence + "/odometry.txt", wheels);
  }
  if (grid) s.navmap = {{"grid", true}, {"up", "floor"}, {"slabs", 25}, {"upkeep_ms_per_frame", 0.03}};
  else s.navmap = {{"grid", false}, {"why", "no mount and no floor fit (give --map-mount or --map-floor)"}};
  summary = s.toJson();
  if (odometry) summary["odometry"]["time_offset_s"] = 0.012;  // a key the typed summary does not know yet
  writeText(r.dir + "/summary.json", summary.dump(2));

  if (grid) {  // a corridor along map x: walls at y = +-2.5 m, free between, unknown outside; 0.1 m cells
    const int width = 400, height = 60;
    std::string pgm = "P5\n# test\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
    for (int row = 0; row < height; ++row)
      for (int col = 0; col < width; ++col) {
        const double y = -3.0 + (height - 0.5 - row) * 0.1;
        pgm += char(std::abs(std::abs(y) - 2.5) < 0.06 ? 0 : std::abs(y) < 2.5 ? 254 : 205);
      }
    writeText(r.dir + "/map.pgm", pgm);
    writeText(r.dir + "/map.yaml", "image: map.pgm\nresolution: 0.100000\norigin: [-1.000000, -3.000000, 0.0]\n"
                                             "negate: 0\noccupied_thresh: 0.650\nfree_thresh: 0.196\n");
    // The world (camera: x right, y down, z forward) to the map (x forward, y left, z up).
    writeText(r.dir + "/map_frame.json",
                        R"({"T_world_to_map": [[0, 0, 1, 0], [-1, 0, 0, 0], [0, -1, 0, 0], [0, 0, 0, 1]], "source": "floor"})");
  }
  return r;
}

MarkupCheck checked(const std::string& html) {
  MarkupCheck check = checkMarkup(html);
  for (const auto& e : check.errors) INFO(e);
  REQUIRE(check.errors.empty());
  return check;
}

bool hasText(const MarkupCheck& page, const std::string& element, const std::string& needle) {
  for (const auto* e : page.find(element))
    if (e->text.find(needle) != std::string::npos) return true;
  return false;
}

// The <svg> element whose <title> is `title`, as markup (empty when absent).
std::string svgTitled(const std::string& html, const std::string& title) {
  const size_t at = html.find("<title>" + sb::report::escapeXml(title) + "</title>");
  if (at == std::string::npos) return "";
  const size_t start = html.rfind("<svg", at), end = html.find("</svg>", at);
  return html.substr(start, end + 6 - start);
}

std::string build(const RobotRun& r, const std::string& compareDir = "") {
  sb::RunReportOptions o;
  o.compareDir = compareDir;
  sb::RunReportResult result;
  const std::string html = sb::buildRunReport(r.dir, o, r.dir, &result);
  for (const auto& p : result.problems) INFO(p);
  CHECK(result.problems.empty());
  return html;
}

}  // namespace

TEST_CASE("a robot's report shows the wheels against the view and the grid with the path", "[report]") {
  const RobotRun run = makeRun("robot", true, true);
  const std::string html = build(run);
  const MarkupCheck page = checked(html);
  CHECK(hasText(page, "h2", "Odometry"));
  CHECK(hasText(page, "h2", "Navigation map"));

  // Every figure is a plot of its own under 200 KB (the stacked stage times of this drive were 251 KB before
  // they were drawn as means over two frames).
  for (size_t at = html.find("<svg"); at != std::string::npos; at = html.find("<svg", at + 1)) {
    const size_t end = html.find("</svg>", at);
    CHECK(end - at < 200 * 1024);
  }

  SECTION("the disagreement plot: the slip stands out at its frames, every verdict has a lane") {
    const std::string plot = svgTitled(html, "Wheels' step against the run's, per frame");
    REQUIRE_FALSE(plot.empty());
    for (const char* lane : {"used (1179)", "rejected (slip) (20)", "dead reckoning (state odometry) (50)",
                             "fault: slipping (20)", "no wheels' pose (1)"})
      CHECK_THAT(plot, Catch::Contains("<title>" + sb::report::escapeXml(lane) + "</title>"));
    // The numbers behind it: at the slip 10 cm, elsewhere the 3% scale error of a 3 cm step.
    sb::report::RunLoadOptions load;
    const sb::report::RunData data = sb::report::loadRun(run.dir, load);
    const auto w = sb::report::compareWheels(data);
    REQUIRE(w.frame.size() == kFrames - 1);
    double slipMin = 1e9, elsewhereMax = 0;
    for (size_t k = 0; k < w.frame.size(); ++k)
      (slipping(int(w.frame[k])) ? slipMin : elsewhereMax) =
          slipping(int(w.frame[k])) ? std::min(slipMin, w.translationCm[k]) : std::max(elsewhereMax, w.translationCm[k]);
    CHECK(slipMin == Approx(10.0).margin(0.2));
    CHECK(elsewhereMax < 0.2);
    CHECK(w.wheelsOnlyFrames == 50);
    double driven = 0;  // the wheels' (3% long) steps over the dead-reckoning frames
    for (int i = 600; i < 650; ++i) driven += 1.03 * (truthAt(i) - truthAt(i - 1)).norm();
    CHECK(w.wheelsOnlyM == Approx(driven).epsilon(1e-6));
  }

  SECTION("numbers the fusion logs per frame get a plot; the final values include keys the type lacks") {
    CHECK_FALSE(svgTitled(html, "odometry.drift_m per frame").empty());
    CHECK_FALSE(svgTitled(html, "odometry.scale_error per frame").empty());
    CHECK(hasText(page, "td", "time_offset_s"));
    // The reasons, grouped with their digits masked: one row for the 20 slip frames (first example: frame 400).
    CHECK(hasText(page, "td", "the wheels' step 14 cm against the view's 3 cm"));
  }

  SECTION("the grid: map.pgm embedded at its size under the path, start and end marked, metres on the axes") {
    const std::string map = svgTitled(html, "Navigation map (map.pgm) with the path");
    REQUIRE_FALSE(map.empty());
    const MarkupCheck svg = checked(map);
    const auto images = svg.find("image");
    REQUIRE(images.size() == 1);
    const std::string href = images[0]->attributes.at("href");
    const std::string prefix = "data:image/png;base64,";
    REQUIRE(href.rfind(prefix, 0) == 0);
    std::vector<uint8_t> png;
    REQUIRE(sb::report::base64Decode(href.substr(prefix.size()), png));
    CHECK(png.size() < 200 * 1024);
    const auto cells = sb::report::decodePngGray(png, "grid");
    CHECK(cells.width() == 400);
    CHECK(cells.height() == 60);
    CHECK(cells(0, 0) == 205);   // unknown, top-left: y = +3 m
    CHECK(cells(10, 30) == 254);  // free, the middle row
    // The drawn box is 40 m x 6 m in the plot's own equal scale.
    const double w = std::stod(images[0]->attributes.at("width")), h = std::stod(images[0]->attributes.at("height"));
    CHECK(w / h == Approx(40.0 / 6.0).epsilon(0.02));
    CHECK(hasText(svg, "text", "x, map frame (m)"));
    CHECK(hasText(svg, "text", "end"));
    CHECK(svg.find("polyline").size() >= 3);  // truth, wheels, estimate
  }

  SECTION("the summary is grouped with units, the raw keys folded away") {
    for (const char* group : {"Run", "Time", "Odometry", "Map"}) CHECK(hasText(page, "h3", group));
    CHECK(hasText(page, "summary", "Every key of summary.json"));
    bool unit = false;
    for (const auto* td : page.find("td")) unit |= td->text == "ms/frame";
    CHECK(unit);
  }
}

TEST_CASE("a new boolean verdict in frames.jsonl gets its lane without code changes", "[report]") {
  const RobotRun run = makeRun("new_verdict", true, false, "stalled");
  std::string frames = readText(run.dir + "/frames.jsonl");
  // Turn the text field into a boolean one: "stalled": true.
  for (size_t at = frames.find("\"stalled\":\"slipping\""); at != std::string::npos;
       at = frames.find("\"stalled\":\"slipping\"", at))
    frames.replace(at, 20, "\"stalled\":true");
  writeText(run.dir + "/frames.jsonl", frames);
  const std::string html = build(run);
  CHECK_THAT(svgTitled(html, "Wheels' step against the run's, per frame"),
             Catch::Contains("<title>stalled (20)</title>"));
}

TEST_CASE("runs without odometry or grid say so in one line", "[report]") {
  const RobotRun run = makeRun("plain", false, false);
  const MarkupCheck page = checked(build(run));
  CHECK(hasText(page, "p", "No odometry: the run had none"));
  CHECK(hasText(page, "p", "No navigation map: the run made none (no mount and no floor fit"));
  fs::remove(run.dir + "/summary.json");
  sb::RunReportResult result;
  const MarkupCheck bare = checked(sb::buildRunReport(run.dir, {}, run.dir, &result));
  CHECK(hasText(bare, "p", "No navigation map: " + run.dir + "/map.pgm is missing (run with --map-mount or --map-floor)"));
}

TEST_CASE("the comparison draws both runs' paths on one grid", "[report]") {
  const RobotRun a = makeRun("compare_a", true, true), b = makeRun("compare_b", false, false);
  const std::string html = build(a, b.dir);
  checked(html);
  const std::string map = svgTitled(html, "Navigation map (map.pgm) with the paths");
  REQUIRE_FALSE(map.empty());
  CHECK_THAT(map, Catch::Contains("<title>run (b)</title>"));
  CHECK_THAT(html, Catch::Contains("run (b) wrote no grid"));
}

TEST_CASE("a 1200-frame robot report is at most twice the size of the same run's without odometry and grid",
          "[report]") {
  const std::string robot = build(makeRun("size_robot", true, true));
  const std::string plain = build(makeRun("size_plain", false, false));
  INFO("robot " << robot.size() << " bytes, plain " << plain.size());
  CHECK(robot.size() <= 2 * plain.size());
}
