// `slambooster report`: the HTML report of a run directory (plots, the wheels against the view, the navigation
// map, the rendered model, the summary), optionally side by side with a second run.

#include <iostream>
#include <memory>

#include "report/run_report.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {

void addReportCommand(CLI::App& app) {
  auto options = std::make_shared<RunReportOptions>();
  auto runDir = std::make_shared<std::string>();
  auto* sub = app.add_subcommand("report", "Write a self-contained HTML report of a run directory");
  sub->add_option("run", *runDir, "Run directory (the --out of `slambooster run`)")->required();
  sub->add_option("--out", options->output,
                  "HTML file to write (default: RUN/report.html, or RUN/compare-<B>.html with --compare)");
  sub->add_option("--compare", options->compareDir,
                  "Second run directory: adds maps side by side with a difference image, both trajectories, and both paths\n"
                  "on the first run's navigation map when either wrote map.pgm");
  sub->add_option("--groundtruth", options->groundTruth,
                  "Ground truth (TUM) when the sequence named in summary.json has none or has moved");
  sub->add_option("--title", options->title, "Page title");
  sub->callback([options, runDir] {
    const RunReportResult result = writeRunReport(*runDir, *options);
    for (const auto& p : result.problems) std::cerr << "slambooster report: warning: " << p << "\n";
    std::cout << "report written to " << result.path << "\n";
  });
}

}  // namespace sb::cli
