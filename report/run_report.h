#pragma once
// The HTML report of a run directory written by `slambooster run` (see report/README.md).
//
//   sb::RunReportOptions options;                 // defaults: <runDir>/report.html
//   sb::RunReportResult r = sb::writeRunReport("out/kitchen", options);
//   for (const auto& p : r.problems) std::cerr << p << "\n";   // inputs that were missing or damaged
//
// The page is one self-contained file: inline SVG plots and the map embedded as a base64 PNG, no scripts,
// nothing fetched from the network.

#include <string>
#include <vector>

namespace sb {

struct RunReportOptions {
  std::string output;       // the HTML file; empty = <runDir>/report.html (<runDir>/compare-<b>.html with compareDir)
  std::string groundTruth;  // TUM ground truth; empty = groundtruth.txt of the sequence named in summary.json
  std::string compareDir;   // a second run directory: adds the side-by-side map comparison (a vs b)
  std::string title;        // empty = "SLAMBooster run: <dir name>"
};

struct RunReportResult {
  std::string path;                   // the file written
  std::vector<std::string> problems;  // inputs that were missing or damaged (also listed on the page)
};

// Writes the report atomically (temporary file, then rename). Throws sb::Error when `runDir` (or compareDir)
// is not a run directory or the output cannot be written; damaged inputs give a partial report instead.
RunReportResult writeRunReport(const std::string& runDir, const RunReportOptions& options = {});

// The page as a string, without writing it (`reportDir` is where it will live, for the mesh link).
std::string buildRunReport(const std::string& runDir, const RunReportOptions& options, const std::string& reportDir,
                           RunReportResult* result = nullptr);

}  // namespace sb
