// Overview (headline numbers and problems) and the full summary table of a run report.

#include <cmath>

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

const json* findPath(const json& j, std::initializer_list<const char*> path) {
  const json* node = &j;
  for (const char* k : path) {
    if (!node->is_object() || !node->contains(k)) return nullptr;
    node = &node->at(k);
  }
  return node;
}

double numberAt(const json& j, std::initializer_list<const char*> path) {
  const json* v = findPath(j, path);
  return v && v->is_number() ? v->get<double>() : std::nan("");
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
  const json& s = *run.summary;
  Table t{{"measure", "value", "unit"}, {}};
  addHeadline(t, "frames", numberAt(s, {"frames"}), "", "headline.frames");
  addHeadline(t, "tracked", numberAt(s, {"tracked_percent"}), "% of attempted", "headline.tracked_percent");
  addHeadline(t, "computation time", numberAt(s, {"computation_ms_per_frame"}), "ms/frame",
              "headline.computation_ms_per_frame");
  addHeadline(t, "process CPU time", numberAt(s, {"cpu_ms_per_frame"}), "ms/frame", "headline.cpu_ms_per_frame");
  addHeadline(t, "ATE RMSE", numberAt(s, {"ate", "rmse_m"}) * 100, "cm", "headline.ate_rmse_cm");
  addHeadline(t, "unaligned mean error", numberAt(s, {"ate", "unaligned_mean_m"}) * 100, "cm",
              "headline.unaligned_mean_cm");
  double joules = numberAt(s, {"joules_per_frame"});
  if (!std::isfinite(joules)) joules = numberAt(s, {"energy", "joules_per_frame"});
  addHeadline(t, "energy", joules, "J/frame", "headline.joules_per_frame");
  double power = numberAt(s, {"mean_power_w"});
  if (!std::isfinite(power)) power = numberAt(s, {"energy", "mean_power_w"});
  addHeadline(t, "mean power", power, "W", "headline.mean_power_w");
  if (const json* knobs = findPath(s, {"knobs"}); knobs && knobs->is_object()) {
    std::string text;
    for (auto it = knobs->begin(); it != knobs->end(); ++it) text += (text.empty() ? "" : ", ") + it.key() + "=" + cellText(*it);
    t.rows.push_back({{"knobs (initial)"}, {text}, {""}});
  }
  if (const json* error = findPath(s, {"ate_error"}); error && error->is_string())
    t.rows.push_back({{"ATE not computed"}, {error->get<std::string>()}, {""}});
  page.table(t, "headline");
}

void addSummarySection(HtmlPage& page, const RunData& run) {
  page.heading(2, "Summary", "summary");
  if (!run.summary) {
    page.paragraph("No summary: summary.json is missing or unreadable (see the problems above).", "muted");
    return;
  }
  json rest = *run.summary;
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
