#include "report/run_report.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>

#include "core/error.h"
#include "core/exclusive_file.h"
#include "report/html_page.h"
#include "report/run_data.h"
#include "report/run_sections.h"

namespace sb {

namespace fs = std::filesystem;
using namespace report;

namespace {

std::string defaultOutput(const std::string& runDir, const RunReportOptions& o) {
  if (!o.output.empty()) return o.output;
  if (o.compareDir.empty()) return (fs::path(runDir) / "report.html").string();
  std::string name = fs::path(o.compareDir).lexically_normal().filename().string();
  if (name.empty() || name == ".") name = "b";
  return (fs::path(runDir) / ("compare-" + name + ".html")).string();
}

}  // namespace

std::string buildRunReport(const std::string& runDir, const RunReportOptions& options, const std::string& reportDir,
                           RunReportResult* result) {
  RunLoadOptions load;
  load.groundTruth = options.groundTruth;
  const RunData run = loadRun(runDir, load);
  std::optional<RunData> other;
  if (!options.compareDir.empty()) {
    other = loadRun(options.compareDir, load);
    if (other->label == run.label) other->label += " (b)";
  }

  HtmlPage page(!options.title.empty() ? options.title
                : other              ? "SLAMBooster runs: " + run.label + " vs " + other->label
                                     : "SLAMBooster run: " + run.label);
  addOverviewSection(page, run);
  if (other) addComparisonSection(page, run, *other);
  addTrajectorySection(page, run);
  addOdometrySection(page, run);
  addNavMapSection(page, run);
  addErrorSection(page, run);
  addKnobSection(page, run);
  addTrackingQualitySection(page, run);
  addStageTimeSection(page, run);
  addEnergySection(page, run);
  addMapSection(page, run, reportDir);
  addSummarySection(page, run);

  if (result) {
    result->problems = run.problems;
    if (other)
      for (const auto& p : other->problems) result->problems.push_back(other->label + ": " + p);
  }
  return page.str();
}

RunReportResult writeRunReport(const std::string& runDir, const RunReportOptions& options) {
  RunReportResult result;
  result.path = defaultOutput(runDir, options);
  const fs::path out(result.path);
  const fs::path dir = out.has_parent_path() ? out.parent_path() : fs::path(".");
  const std::string html = buildRunReport(runDir, options, dir.string(), &result);

  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw Error("cannot write the report '" + result.path + "': directory '" + dir.string() + "' does not exist");
  // A new temporary file (core/exclusive_file.h), renamed over the report once whole.
  TemporaryFile temporary(result.path);
  std::FILE* file = temporary.stream();
  if (std::fwrite(html.data(), 1, html.size(), file) != html.size())
    throw Error("cannot write the report '" + temporary.path() + "': " + std::strerror(errno) +
                " (permissions? disk full?)");
  try {
    temporary.commit();
  } catch (const Error& e) {
    throw Error("cannot write the report '" + result.path + "': " + e.what());
  }
  return result;
}

}  // namespace sb
