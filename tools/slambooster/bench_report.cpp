#include "tools/slambooster/bench_report.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "core/error.h"
#include "tools/slambooster/matrix_plan.h"

namespace sb::cli {

namespace {

namespace fs = std::filesystem;
using report::TableCell;

// The paper's requirement for an acceptable run: ATE below 5 cm with at least 99% of the frames tracked.
constexpr double kMaxAteM = 0.05;
constexpr double kMinTrackedPercent = 99.0;

std::string intro(const BenchResults& r) {
  return "Sequences: " + std::to_string(r.sequences.size()) +
         "; frames per run: " + (r.framesPerRun ? std::to_string(r.framesPerRun) : std::string("all")) +
         "; computation = preprocessing + tracking + integration + raycast (ms/frame, host clock); ATE RMSE "
         "in cm "
         "against the ground truth, or against the ACCURATE run where a sequence has none (marked *).";
}

std::string sequenceCell(const BenchResults& r, const std::string& name) {
  const auto it = r.ownTruth.find(name);
  return name + (it != r.ownTruth.end() && !it->second ? "*" : "");
}

// DEFAULT vs SLAMBooster with the geometric mean of the time ratios. Cell keys "main/<sequence>/<controller>/
// <results.csv column>" (ATE as ate_rmse_cm), "main/<sequence>/time_cut_percent", "main/geomean/...".
BenchSection mainSection(const BenchResults& r) {
  BenchSection s;
  s.title = "DEFAULT vs SLAMBooster";
  s.table.header = {"sequence",
                    "frames",
                    "DEFAULT tracked %",
                    "DEFAULT ms/frame",
                    "DEFAULT ATE cm",
                    "SLAMBooster tracked %",
                    "SLAMBooster ms/frame",
                    "SLAMBooster ATE cm",
                    "time cut %"};
  const bool energy = r.hasEnergy();
  if (energy)
    s.table.header.insert(s.table.header.end(), {"DEFAULT J/frame", "SLAMBooster J/frame", "energy cut %"});
  double logRatio = 0, cutSum = 0;
  int paired = 0, violations = 0;
  for (const std::string& name : r.sequences) {
    const BenchCell d = r.cell(name, "default"), b = r.cell(name, "slambooster");
    if (!d.present || !b.present) continue;
    const double cut = 100.0 * (1.0 - b.ms / d.ms);
    logRatio += std::log(b.ms / d.ms);
    cutSum += cut;
    ++paired;
    violations += !(b.ateM < kMaxAteM) || b.tracked < kMinTrackedPercent;
    const std::string k = "main/" + name + "/";
    std::vector<TableCell> row{{sequenceCell(r, name)},
                            {benchNumber(b.frames, 0), k + "slambooster/frames", true},
                            {benchNumber(d.tracked), k + "default/tracked_percent", true},
                            {benchNumber(d.ms), k + "default/computation_ms_per_frame", true},
                            {benchCm(d.ateM), k + "default/ate_rmse_cm", true},
                            {benchNumber(b.tracked), k + "slambooster/tracked_percent", true},
                            {benchNumber(b.ms), k + "slambooster/computation_ms_per_frame", true},
                            {benchCm(b.ateM), k + "slambooster/ate_rmse_cm", true},
                            {benchNumber(cut), k + "time_cut_percent", true}};
    if (energy) {
      row.push_back({benchNumber(d.joulesPerFrame, 3), k + "default/joules_per_frame", true});
      row.push_back({benchNumber(b.joulesPerFrame, 3), k + "slambooster/joules_per_frame", true});
      row.push_back({benchNumber(100.0 * (1.0 - b.joulesPerFrame / d.joulesPerFrame)), k + "energy_cut_percent", true});
    }
    s.table.rows.push_back(row);
  }
  if (paired) {
    const double geoCut = 100.0 * (1.0 - std::exp(logRatio / paired));
    std::vector<TableCell> row(s.table.header.size());
    row.front() = {"geomean"};
    row.back() = {benchNumber(geoCut), "main/geomean/time_cut_percent", true};
    s.boldRows.push_back(s.table.rows.size());
    s.table.rows.push_back(row);
    s.after =
        "Mean computation-time cut of SLAMBooster vs DEFAULT: " + benchNumber(cutSum / paired) +
        "% (arithmetic mean of per-sequence cuts), " + benchNumber(geoCut) +
        "% (geometric mean of time ratios); sequences with ATE >= 5 cm or < 99% tracked under SLAMBooster: " +
        std::to_string(violations) + " of " + std::to_string(paired) + ".";
  }
  return s;
}

// ms/frame / ATE cm of each controller in `cols` (and % tracked where below 100), one row per sequence.
BenchSection study(const BenchResults& r, const std::string& title, const std::vector<std::string>& cols) {
  BenchSection s;
  s.title = title;
  s.before = "ms/frame / ATE cm (% of frames tracked, where below 100)";
  s.table.header = {"sequence"};
  s.table.header.insert(s.table.header.end(), cols.begin(), cols.end());
  for (const std::string& name : r.sequences) {
    std::vector<TableCell> row{{name}};
    for (const auto& c : cols) {
      const BenchCell x = r.cell(name, c);
      std::string text = x.present ? benchNumber(x.ms) + " / " + benchCm(x.ateM) : "-";
      if (x.present && benchNumber(x.tracked) != "100.0") text += " (" + benchNumber(x.tracked) + "%)";
      row.push_back({text, "", true});
    }
    s.table.rows.push_back(row);
  }
  return s;
}

// Reference velocities x profiling sets. Per set, of the bench's sequences: error violations = those whose
// tc run has ATE >= 5 cm (or no ATE), better time = those where tc's ms/frame is below SLAMBooster's. Cell
// keys "tc/<set>/<v>/error_violations" and "tc/<set>/<v>/better_time" (the count, shown as "k of n").
BenchSection tcSection(const BenchResults& r) {
  BenchSection s;
  s.title = "TC (application-agnostic) vs SLAMBooster";
  s.before = "Profiling sets (column groups):";
  for (size_t i = 0; i < r.tcSets.size(); ++i) {
    const BenchTcSet& t = r.tcSets[i];
    std::string on;
    for (const std::string& name : t.profiledOn) on += (on.empty() ? "" : ", ") + name;
    s.before += std::string(i ? ";" : "") + " `" + t.name + "`: table `" + t.path + "`, " +
                (on.empty() ? "profiled sequences not recorded in the table" : "profiled on " + on) +
                " (columns " + t.prefix + "@v)";
  }
  s.before +=
      ". Error violations: sequences whose tc run has ATE >= 5 cm; better time: sequences where tc "
      "takes less computation ms/frame than SLAMBooster.";
  s.table.header = {"v_ref m/frame"};
  for (const BenchTcSet& t : r.tcSets)
    s.table.header.insert(s.table.header.end(), {t.name + ": error violations (ATE >= 5 cm)",
                                                 t.name + ": better time than SLAMBooster"});
  const std::string of = " of " + std::to_string(r.sequences.size());
  for (double v : r.tcVelocities) {
    std::vector<TableCell> row{{benchNumber(v, 3), "", true}};
    for (const BenchTcSet& t : r.tcSets) {
      int bad = 0, faster = 0;
      for (const std::string& name : r.sequences) {
        const BenchCell c = r.cell(name, t.label(v)), b = r.cell(name, "slambooster");
        bad += c.present && !(c.ateM < kMaxAteM);
        faster += c.present && b.present && c.ms < b.ms;
      }
      const std::string k = "tc/" + t.name + "/" + benchNumber(v, 3) + "/";
      row.push_back({std::to_string(bad) + of, k + "error_violations"});
      row.push_back({std::to_string(faster) + of, k + "better_time"});
    }
    s.table.rows.push_back(row);
  }
  return s;
}

std::string overhead(const BenchResults& r) {
  std::string text = "Controller overhead (slambooster): ";
  for (const std::string& name : r.sequences) {
    const BenchCell b = r.cell(name, "slambooster");
    if (b.present) text += name + " " + benchNumber(100.0 * b.controllerMs / std::max(b.ms, 1e-9), 3) + "% ";
  }
  return text + "of frame time.";
}

std::string markdownRow(const std::vector<std::string>& cells, bool bold) {
  std::string line = "|";
  for (const auto& c : cells) line += c.empty() ? " |" : " " + (bold ? "**" + c + "**" : c) + " |";
  return line + "\n";
}

// Markdown markup in a paragraph shown as plain text.
std::string plain(std::string text) {
  text.erase(std::remove(text.begin(), text.end(), '`'), text.end());
  return text;
}

}  // namespace

bool BenchResults::hasEnergy() const {
  for (const auto& [key, c] : cells)
    if (c.present && std::isfinite(c.joulesPerFrame)) return true;
  return false;
}

std::string BenchTcSet::label(double velocityMPerFrame) const {
  return prefix + "@" + benchNumber(velocityMPerFrame, 3);
}

BenchCell BenchResults::cell(const std::string& sequence, const std::string& label) const {
  const auto it = cells.find({sequence, label});
  return it == cells.end() ? BenchCell{} : it->second;
}

std::string benchNumber(double v, int decimals) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << v;
  return s.str();
}

std::string benchCm(double metres) {
  return std::isfinite(metres) ? benchNumber(metres * 100, 2) : "-";
}

std::vector<BenchSection> benchSections(const BenchResults& r) {
  std::vector<BenchSection> sections{mainSection(r)};
  sections.push_back(study(r, "Incremental study",
                           {"default", "pid", "pid+surface", "pid+surface+correction", "slambooster"}));
  sections.push_back(study(r, "PID vs step", {"default", "pid", "step", "slambooster"}));
  if (r.offline)
    sections.push_back(study(r, "Online vs offline best (dse)", {"default", "offline", "slambooster"}));
  if (!r.tcSets.empty()) {
    sections.push_back(tcSection(r));
    std::vector<std::string> cols{"slambooster"};
    for (const BenchTcSet& t : r.tcSets)
      for (double v : r.tcVelocities) cols.push_back(t.label(v));
    sections.push_back(study(r, "TC vs SLAMBooster per sequence", cols));
  }
  return sections;
}

std::string benchMarkdown(const BenchResults& r, const std::vector<BenchSection>& sections) {
  std::string md = "# slambooster bench\n\n" + intro(r) + "\n\n";
  for (const std::string& note : r.notes) md += "> " + note + "\n\n";
  for (const BenchSection& s : sections) {
    md += "## " + s.title + "\n\n";
    if (!s.before.empty()) md += s.before + "\n\n";
    md += markdownRow(s.table.header, false) + "|";
    for (size_t i = 0; i < s.table.header.size(); ++i) md += "---|";
    md += "\n";
    for (size_t i = 0; i < s.table.rows.size(); ++i) {
      std::vector<std::string> texts;
      for (const auto& c : s.table.rows[i]) texts.push_back(c.text);
      md += markdownRow(texts, std::count(s.boldRows.begin(), s.boldRows.end(), i) > 0);
    }
    md += "\n";
    if (!s.after.empty()) md += s.after + "\n\n";
  }
  return md + overhead(r) + "\n\nPlots: time.svg, ate.svg, trace.svg. Raw numbers: results.csv.\n";
}

std::string writeBenchHtml(const BenchResults& r, const std::vector<BenchSection>& sections,
                           const BenchFigures& figures) {
  report::HtmlPage page("slambooster bench: " + fs::path(r.outDir).lexically_normal().filename().string());
  page.paragraph(intro(r));
  for (const std::string& note : r.notes) page.paragraph(note);
  for (const BenchSection& s : sections) {
    page.heading(2, s.title);
    if (!s.before.empty()) page.paragraph(plain(s.before));
    page.table(s.table);
    if (!s.after.empty()) page.paragraph(s.after);
  }
  page.paragraph(overhead(r));

  page.heading(2, "Time and ATE per sequence", "bars");
  for (const auto& svg : figures.bars) page.figure(svg);
  page.heading(2, "Per-frame trace: " + r.plotSequence + " under slambooster", "trace");
  if (figures.trace.empty()) page.paragraph("No slambooster run of this sequence in the bench.", "muted");
  page.problems(figures.traceProblems);
  for (const auto& svg : figures.trace)
    page.figure(svg, "Marks along the top: frames where each controller trigger fired.");

  // Each run's own report, linked relative to this page so the bench directory can move as a whole.
  page.heading(2, "Runs", "runs");
  report::Table runs;
  runs.header = {"sequence", "controller", "frames", "ms/frame", "ATE cm", "report"};
  std::vector<std::string> labels = r.columns;
  if (r.offline) labels.push_back("offline");
  for (const std::string& name : r.sequences)
    for (const std::string& label : labels) {
      const BenchCell c = r.cell(name, label);
      if (!c.present) continue;
      const fs::path runPage = fs::path(c.dir) / "report.html";
      const bool exists = fs::exists(runPage);
      const std::string href = exists ? fs::relative(runPage, r.outDir).generic_string() : "";
      runs.rows.push_back({{name},
                           {label},
                           {benchNumber(c.frames, 0), "", true},
                           {benchNumber(c.ms), "", true},
                           {benchCm(c.ateM), "", true},
                           {exists ? "report.html" : "(no report)", "", false, href}});
    }
  page.table(runs);
  page.link("results.csv", "results.csv", "Raw numbers: ");
  page.link("report.md", "report.md", "The tables in Markdown: ");

  const std::string path = r.outDir + "/report.html";
  writeFileAtomically(path, page.str());
  return path;
}

}  // namespace sb::cli
