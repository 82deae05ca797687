// Overview (headline numbers and problems) and the full summary table of a run report.

#include <cmath>
#include <limits>

#include "report/run_sections.h"
#include "report/text_escape.h"

namespace sb::report {

namespace {

using nlohmann::json;

std::string scalarText(const json& v) {
  if (v.is_number_integer() || v.is_number_unsigned()) return v.dump();
  if (v.is_number_float()) return formatNumber(v.get<double>(), 6);
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_null()) return "(none)";
  return v.dump();
}

// One row per leaf; arrays of scalars stay one row ("10, 5, 4").
void flatten(const json& j, const std::string& prefix, std::vector<std::pair<std::string, const json*>>& out) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) flatten(*it, prefix.empty() ? it.key() : prefix + "." + it.key(), out);
    return;
  }
  if (j.is_array()) {
    bool scalars = true;
    for (const auto& e : j) scalars &= !e.is_structured();
    if (!scalars) {
      for (size_t i = 0; i < j.size(); ++i) flatten(j[i], prefix + "." + std::to_string(i), out);
      return;
    }
  }
  out.emplace_back(prefix, &j);
}

std::string cellText(const json& v) {
  if (!v.is_array()) return scalarText(v);
  std::string s;
  for (const auto& e : v) s += (s.empty() ? "" : ", ") + scalarText(e);
  return s;
}

Table flatTable(const json& j, const std::string& prefix) {
  std::vector<std::pair<std::string, const json*>> leaves;
  flatten(j, prefix, leaves);
  Table t{{"key", "value"}, {}};
  for (const auto& [key, value] : leaves)
    t.rows.push_back({{key}, {cellText(*value), key, value->is_number()}});
  return t;
}

void addHeadline(Table& t, const std::string& what, double value, const std::string& unit, const std::string& key) {
  if (!std::isfinite(value)) return;
  t.rows.push_back({{what}, {formatNumber(value, 4), key, true}, {unit}});
}

}  // namespace

void addOverviewSection(HtmlPage& page, const RunData& run) {
  page.paragraph("Run directory: " + run.dir + (run.groundTruthPath.empty() ? "" : "; ground truth: " + run.groundTruthPath),
                 "muted");
  page.problems(run.problems);
  for (const auto& n : run.notes) page.paragraph(n, "muted");
  if (!run.summary) return;
  const RunSummary& s = *run.summary;
  constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
  Table t{{"measure", "value", "unit"}, {}};
  addHeadline(t, "frames", double(s.frames), "", "headline.frames");
  addHeadline(t, "tracked", s.trackedPercent, "% of attempted", "headline.tracked_percent");
  addHeadline(t, "computation time", s.computationMsPerFrame, "ms/frame", "headline.computation_ms_per_frame");
  addHeadline(t, "process CPU time", s.cpuMsPerFrame.value_or(kNan), "ms/frame", "headline.cpu_ms_per_frame");
  addHeadline(t, "ATE RMSE", s.ate ? s.ate->rmseM * 100 : kNan, "cm", "headline.ate_rmse_cm");
  addHeadline(t, "unaligned mean error", s.ate ? s.ate->unalignedMeanM * 100 : kNan, "cm",
              "headline.unaligned_mean_cm");
  addHeadline(t, "energy", s.joulesPerFrame(), "J/frame", "headline.joules_per_frame");
  addHeadline(t, "mean power", s.meanWatts(), "W", "headline.mean_power_w");
  if (s.knobs.csr > 0) {  // a summary from before the knobs has none
    const json knobs = s.knobs.toJson();
    std::string text;
    for (auto it = knobs.begin(); it != knobs.end(); ++it)
      text += (text.empty() ? "" : ", ") + it.key() + "=" + cellText(*it);
    t.rows.push_back({{"knobs (initial)"}, {text}, {""}});
  }
  if (!s.ateError.empty()) t.rows.push_back({{"ATE not computed"}, {s.ateError}, {""}});
  page.table(t, "headline");
}

void addSummarySection(HtmlPage& page, const RunData& run) {
  page.heading(2, "Summary", "summary");
  if (!run.summary) {
    page.paragraph("No summary: summary.json is missing or unreadable (see the problems above).", "muted");
    return;
  }
  json rest = run.summary->toJson();
  json config;
  if (rest.contains("config")) {
    config = rest["config"];
    rest.erase("config");
  }
  page.table(flatTable(rest, ""), "summary");
  if (!config.is_null()) {
    page.heading(3, "Configuration");
    page.table(flatTable(config, "config"), "summary");
  }
}

}  // namespace sb::report
