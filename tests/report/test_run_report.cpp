// `slambooster report` end to end: from a short synthetic run, the page is well-formed, self-contained
// (every image embedded and decodable, the only link is the mesh beside it), and its numbers are those of
// summary.json; damaged or missing inputs give a partial report naming the file; two runs compare.

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "report/base64.h"
#include "report/png_codec.h"
#include "report/text_escape.h"
#include "tests/report/markup_check.h"
#include "tests/report/report_fixture.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace fs = std::filesystem;
using sb::test::checkMarkup;
using sb::test::MarkupCheck;
using sb::test::readText;
using sb::test::runCommand;

namespace {

const std::string kTool = SB_SLAMBOOSTER_BIN;

const sb::test::ReportRuns& runs() { return sb::test::reportRuns("report_e2e"); }

// A copy of run A to damage.
std::string copyRun(const std::string& name) {
  const std::string dir = sb::test::scratchDir("report_e2e_" + name) + "/run";
  fs::copy(runs().runA, dir, fs::copy_options::recursive);
  return dir;
}

MarkupCheck checkedPage(const std::string& path) {
  const std::string html = readText(path);
  MarkupCheck check = checkMarkup(html);
  for (const auto& e : check.errors) INFO(e);
  REQUIRE(check.errors.empty());
  CHECK(html.find("<script") == std::string::npos);  // the page needs no scripts
  return check;
}

// Each <img> is a PNG data: URI that decodes; returns the decoded images in page order.
std::vector<std::vector<uint8_t>> embeddedImages(const MarkupCheck& page) {
  std::vector<std::vector<uint8_t>> images;
  for (const auto* img : page.find("img")) {
    const std::string& src = img->attributes.at("src");
    const std::string prefix = "data:image/png;base64,";
    REQUIRE(src.compare(0, prefix.size(), prefix) == 0);
    std::vector<uint8_t> png;
    REQUIRE(sb::report::base64Decode(src.substr(prefix.size()), png));
    CHECK_NOTHROW(sb::report::decodePngGray(png, "embedded image"));
    CHECK_FALSE(img->attributes.at("alt").empty());
    images.push_back(std::move(png));
  }
  return images;
}

std::map<std::string, std::string> cellsByKey(const MarkupCheck& page) {
  std::map<std::string, std::string> cells;
  for (const auto* td : page.find("td"))
    if (td->attributes.count("data-key")) cells[td->attributes.at("data-key")] = td->text;
  return cells;
}

void collectNumbers(const nlohmann::json& j, const std::string& prefix, std::map<std::string, double>& out) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) collectNumbers(*it, prefix.empty() ? it.key() : prefix + "." + it.key(), out);
  } else if (j.is_number()) {
    out[prefix] = j.get<double>();
  }
}

bool hasText(const MarkupCheck& page, const std::string& element, const std::string& needle) {
  for (const auto* e : page.find(element))
    if (e->text.find(needle) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("the report of a run is self-contained and its numbers are the summary's", "[report][system]") {
  const auto& r = runs();
  const auto result = runCommand(kTool + " report " + r.runA);
  INFO(result.output);
  REQUIRE(result.exitCode == 0);
  CHECK_THAT(result.output, Catch::Contains("report.html"));
  CHECK_THAT(result.output, !Catch::Contains("warning"));
  const std::string page = r.runA + "/report.html";
  const MarkupCheck check = checkedPage(page);

  // Plots: trajectory, ITE, speed, csr, icp, pd0, stacked stage times, mean per stage.
  CHECK(check.find("svg").size() >= 8);
  for (const auto* svg : check.find("svg")) CHECK(svg->attributes.count("viewbox"));  // names are lower-cased by the check

  // The map: the one image is model.png byte for byte; the one link is mesh.ply beside the page.
  const auto images = embeddedImages(check);
  REQUIRE(images.size() == 1);
  CHECK(images[0] == sb::report::readFileBytes(r.runA + "/model.png"));
  const auto links = check.find("a");
  REQUIRE(links.size() == 1);
  CHECK(links[0]->attributes.at("href") == "mesh.ply");
  CHECK(fs::exists(fs::path(page).parent_path() / links[0]->attributes.at("href")));
  for (const auto& e : check.elements)
    for (const auto& [name, value] : e.attributes)
      if (name == "src" || name == "href") CHECK(value.find("://") == std::string::npos);

  // Every number of summary.json is in the table under its key, at the printed precision.
  const auto summary = nlohmann::json::parse(readText(r.runA + "/summary.json"));
  std::map<std::string, double> numbers;
  collectNumbers(summary, "", numbers);
  REQUIRE(numbers.size() > 20);
  const auto cells = cellsByKey(check);
  for (const auto& [key, value] : numbers) {
    INFO(key);
    REQUIRE(cells.count(key) == 1);
    CHECK(std::stod(cells.at(key)) == Approx(value).epsilon(5e-6).margin(1e-300));
  }
  CHECK(cells.at("knobs.pd") == "10, 5, 4");
  CHECK(cells.at("sequence") == summary.at("sequence").get<std::string>());

  // Headline numbers in display units.
  const double ateCm = summary.at("ate").at("rmse_m").get<double>() * 100;
  CHECK(std::stod(cells.at("headline.ate_rmse_cm")) == Approx(ateCm).epsilon(5e-4));
  CHECK(std::stod(cells.at("headline.frames")) == 20);
  CHECK(std::stod(cells.at("headline.computation_ms_per_frame")) ==
        Approx(summary.at("computation_ms_per_frame").get<double>()).epsilon(5e-4));
  // The report's own alignment of trajectory.tum to the ground truth gives the summary's ATE.
  CHECK(hasText(check, "figcaption", "ATE RMSE " + sb::report::formatNumber(ateCm, 4) + " cm"));
  CHECK(hasText(check, "figcaption", "20 matched poses"));
}

TEST_CASE("damaged or missing inputs give a partial report that names the file and line", "[report][system]") {
  SECTION("truncated frames.jsonl") {
    const std::string run = copyRun("truncated");
    std::string log = readText(run + "/frames.jsonl");
    log.resize(log.size() - 40);  // cut into the last line, as an interrupted writer would
    sb::test::writeText(run + "/frames.jsonl", log);
    const auto result = runCommand(kTool + " report " + run);
    INFO(result.output);
    REQUIRE(result.exitCode == 0);
    CHECK_THAT(result.output, Catch::Contains("frames.jsonl line 20 is incomplete") && Catch::Contains("19 frames"));
    const auto check = checkedPage(run + "/report.html");
    CHECK(hasText(check, "li", "frames.jsonl line 20 is incomplete"));
    CHECK(check.find("svg").size() >= 8);  // the 19 frames still plot
  }
  SECTION("empty frames.jsonl, no summary, damaged model.png") {
    const std::string run = copyRun("empty");
    sb::test::writeText(run + "/frames.jsonl", "");
    fs::remove(run + "/summary.json");
    const std::string png = readText(run + "/model.png");
    sb::test::writeText(run + "/model.png", png.substr(0, png.size() / 2));
    const auto result = runCommand(kTool + " report " + run);
    INFO(result.output);
    REQUIRE(result.exitCode == 0);
    CHECK_THAT(result.output, Catch::Contains("frames.jsonl is empty"));
    CHECK_THAT(result.output, Catch::Contains("summary.json' is missing"));
    const auto check = checkedPage(run + "/report.html");
    CHECK(check.find("img").empty());  // a broken image is never embedded
    CHECK(hasText(check, "p", "No rendered model: cannot decode PNG"));
    CHECK(hasText(check, "p", "No summary"));
    // Without a summary there is no sequence to find the ground truth through: the estimate alone.
    CHECK(check.find("svg").size() == 1);
    CHECK(hasText(check, "figcaption", "volume frame"));
  }
  SECTION("ground truth missing, then given explicitly") {
    const std::string run = copyRun("nogt");
    auto summary = nlohmann::json::parse(readText(run + "/summary.json"));
    summary["sequence"] = run + "/moved-away";
    sb::test::writeText(run + "/summary.json", summary.dump(2));
    const auto without = runCommand(kTool + " report " + run);
    REQUIRE(without.exitCode == 0);
    auto check = checkedPage(run + "/report.html");
    CHECK(hasText(check, "p", "no ground truth"));
    CHECK(hasText(check, "p", "No per-frame error"));

    const auto with = runCommand(kTool + " report " + run + " --groundtruth " + runs().sequence + "/groundtruth.txt --out " +
                                 run + "/with-gt.html");
    INFO(with.output);
    REQUIRE(with.exitCode == 0);
    check = checkedPage(run + "/with-gt.html");
    CHECK(hasText(check, "h2", "Per-frame error"));
    CHECK(hasText(check, "figcaption", "20 matched poses"));
  }
  SECTION("not a run directory") {
    const auto missing = runCommand(kTool + " report " + runs().runA + "/no-such-dir");
    CHECK(missing.exitCode == 1);
    CHECK_THAT(missing.output, Catch::Contains("no-such-dir") && Catch::Contains("does not exist"));
    const std::string empty = sb::test::scratchDir("report_e2e_not_a_run");
    const auto notRun = runCommand(kTool + " report " + empty);
    CHECK(notRun.exitCode == 1);
    CHECK_THAT(notRun.output, Catch::Contains("holds none of summary.json"));
  }
}

TEST_CASE("two runs compare side by side with a difference image", "[report][system]") {
  const auto& r = runs();
  const auto result = runCommand(kTool + " report " + r.runA + " --compare " + r.runB);
  INFO(result.output);
  REQUIRE(result.exitCode == 0);
  const std::string page = r.runA + "/compare-csr8.html";
  const auto check = checkedPage(page);
  CHECK(hasText(check, "h2", "Comparison: csr4 vs csr8"));

  // Map A, map B, their difference, then map A again in the single-run map section.
  const auto images = embeddedImages(check);
  REQUIRE(images.size() == 4);
  CHECK(images[0] == sb::report::readFileBytes(r.runA + "/model.png"));
  CHECK(images[1] == sb::report::readFileBytes(r.runB + "/model.png"));
  const auto a = sb::report::decodePngGray(images[0], "a");
  const auto diff = sb::report::decodePngGray(images[2], "difference");
  CHECK(diff.width() == a.width());
  CHECK(diff.height() == a.height());
  CHECK(hasText(check, "p", "mean difference"));

  const auto cells = cellsByKey(check);
  for (const auto& [run, side] : {std::pair{r.runA, "a"}, std::pair{r.runB, "b"}}) {
    const auto summary = nlohmann::json::parse(readText(run + "/summary.json"));
    INFO(side);
    CHECK(std::stod(cells.at(std::string("compare.") + side + ".ate_rmse_cm")) ==
          Approx(summary.at("ate").at("rmse_m").get<double>() * 100).epsilon(5e-4));
    CHECK(std::stod(cells.at(std::string("compare.") + side + ".computation_ms_per_frame")) ==
          Approx(summary.at("computation_ms_per_frame").get<double>()).epsilon(5e-4));
  }
}
