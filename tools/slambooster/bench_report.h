#pragma once
// The reports of `slambooster bench`, made from its evaluated runs: report.md (the paper's tables in
// Markdown) and report.html (the same tables, time and ATE bars per sequence, the per-frame trace of one run,
// links to each run's own report.html; one self-contained file). Both are built from one list of tables, so
// they show the same numbers. The figures live in bench_plots.h.

#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "report/html_page.h"

namespace sb::cli {

// One run of the matrix, as results.csv has it.
struct BenchCell {
  bool present = false;
  double frames = 0;
  double tracked = 0;       // percent of attempted tracks that converged
  double ms = 0;            // computation ms/frame (host clock)
  double ateM = NAN;        // ATE RMSE, metres; NaN = could not be computed
  double controllerMs = 0;  // controller ms/frame
  double joulesPerFrame = NAN;  // J/frame over the frames whose energy is known; NaN = no meter (bench --power)
  std::string dir;          // the run's output directory
};

// One profiling set of the TC table: a tc configuration table (bench --tc-table [NAME=]PATH) and its columns.
struct BenchTcSet {
  std::string name;    // short name: the TC table's column group
  std::string path;    // the tc_table.json
  std::string prefix;  // column labels are prefix@v: "tc-NAME", or "tc" for one unnamed table
  // The sequence names the table records ("sequences"); empty = not recorded.
  std::vector<std::string> profiledOn;

  std::string label(double velocityMPerFrame) const;  // the column of one reference velocity
};

struct BenchResults {
  std::string outDir;                    // bench --out (report links are relative to it)
  std::vector<std::string> sequences;    // sequence names, command-line order
  std::vector<std::string> columns;      // controller labels of the bars (the tc columns included, offline not)
  std::map<std::string, bool> ownTruth;  // sequence -> has its own ground truth (else: against ACCURATE)
  std::map<std::pair<std::string, std::string>, BenchCell> cells;  // (sequence, label)
  size_t framesPerRun = 0;                                         // 0 = all
  bool offline = false;              // --dse-dir given: the online vs offline study
  std::vector<BenchTcSet> tcSets;    // --tc-table, command-line order; empty = no TC table
  std::vector<double> tcVelocities;  // m/frame
  std::string plotSequence;          // the sequence of the per-frame trace
  // Sentences above the tables: the machines the runs were timed on (mixed machines said so), missing runs.
  std::vector<std::string> notes;

  // The cell, or an absent one.
  BenchCell cell(const std::string& sequence, const std::string& label) const;
  // Some run has a J/frame (a meter was configured): the main table gets energy columns.
  bool hasEnergy() const;
};

// A table of the report with the text around it: rendered as Markdown and as HTML from the same cells.
struct BenchSection {
  std::string title;
  std::string before;  // paragraph between heading and table; may be empty
  report::Table table;
  std::vector<size_t> boldRows;  // row indices shown in bold in Markdown (the geomean row)
  std::string after;             // paragraph after the table; may be empty
};

std::vector<BenchSection> benchSections(const BenchResults& results);
// Number formatting shared by the tables and the tests' expectations: fixed decimals, "-" for NaN in cm().
std::string benchNumber(double v, int decimals = 1);
std::string benchCm(double metres);

std::string benchMarkdown(const BenchResults& results, const std::vector<BenchSection>& sections);
// The figures of report.html (complete <svg> elements, bench_plots.h).
struct BenchFigures {
  std::vector<std::string> bars;           // time and ATE per sequence
  std::vector<std::string> trace;          // the per-frame trace of results.plotSequence; empty = none
  std::vector<std::string> traceProblems;  // why (part of) the trace is missing
};
// Writes <outDir>/report.html (atomically) and returns its path.
std::string writeBenchHtml(const BenchResults& results, const std::vector<BenchSection>& sections,
                           const BenchFigures& figures);

}  // namespace sb::cli
