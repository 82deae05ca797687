// Overview (headline numbers and problems) and the full summary table of a run report.

#include <algorithm>
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
  if (s.knobs) {  // a summary from before the knobs has none
    const json knobs = knobsToJson(*s.knobs);
    std::string text;
    for (auto it = knobs.begin(); it != knobs.end(); ++it)
      text += (text.empty() ? "" : ", ") + it.key() + "=" + cellText(*it);
    t.rows.push_back({{"knobs (initial)"}, {text}, {""}});
  }
  if (!s.ateError.empty()) t.rows.push_back({{"ATE not computed"}, {s.ateError}, {""}});
  page.table(t, "headline");
}

std::string unitOfKey(const std::string& key, std::string* stem) {
  static const std::pair<const char*, const char*> suffixes[] = {
      {"_deg_per_s", "deg/s"}, {"_m_per_frame", "m/frame"}, {"_ms_per_frame", "ms/frame"}, {"_per_frame", "/frame"},
      {"_percent", "%"},       {"_ms", "ms"},               {"_cm", "cm"},               {"_mm", "mm"},
      {"_m", "m"},             {"_deg", "deg"},             {"_seconds", "s"},           {"_s", "s"},
      {"_kib", "KiB"},         {"_mib", "MiB"},             {"_watts", "W"},             {"_w", "W"},
      {"joules", "J"},         {"_j", "J"},                 {"_frames", "frames"},       {"frames", "frames"}};
  for (const auto& [suffix, unit] : suffixes) {
    const std::string s(suffix);
    if (key.size() > s.size() && key.compare(key.size() - s.size(), s.size(), s) == 0) {
      if (stem) *stem = s[0] == '_' ? key.substr(0, key.size() - s.size()) : key;
      return unit;
    }
  }
  if (stem) *stem = key;
  return "";
}

namespace {

// RunSummary's sections (report/run_summary.h) by their top-level keys; a key none names goes to "other".
struct SummaryGroup {
  const char* title;
  std::vector<const char*> keys;
};

const std::vector<SummaryGroup>& summaryGroups() {
  static const std::vector<SummaryGroup> groups = {
      {"Run", {"front_end", "sequence", "controller", "knobs", "threads", "daemon", "frames", "tracking_attempted",
               "tracked", "tracked_percent", "integrated", "corrected", "unconstrained", "retracked", "half_wish_frames",
               "half_applied_frames", "triggers", "knob_frames", "controller_frames", "tracking_state", "stopped",
               "interrupted", "complete", "error", "schema_version"}},
      {"Accuracy", {"ate", "ate_error"}},
      {"Time", {"computation_ms_per_frame", "cpu_ms_per_frame", "controller_ms_per_frame", "stage_ms_per_frame", "work"}},
      {"Odometry", {"odometry"}},
      {"Map", {"navmap", "moving_volume", "model_view", "mesh_triangles", "mesh_slabs"}},
      {"Energy", {"energy"}},
      {"Machine", {"machine"}},
  };
  return groups;
}

// One row per leaf: the key's last part without its unit suffix (dots kept for nesting), the value, the unit.
void groupRows(Table& t, const json& value, const std::string& key) {
  std::vector<std::pair<std::string, const json*>> leaves;
  flatten(value, key, leaves);
  for (const auto& [leaf, v] : leaves) {
    std::string stem;
    const std::string unit = unitOfKey(leaf, &stem);
    for (char& c : stem)
      if (c == '_') c = ' ';
    t.rows.push_back({{stem}, {cellText(*v), leaf, v->is_number()}, {unit}});
  }
}

}  // namespace

void addSummarySection(HtmlPage& page, const RunData& run) {
  page.heading(2, "Summary", "summary");
  if (!run.summary) {
    page.paragraph("No summary: summary.json is missing or unreadable (see the problems above).", "muted");
    return;
  }
  const json all = run.summaryJson.is_object() ? run.summaryJson : run.summary->toJson();
  std::vector<std::string> placed = {"config", "controller_sections"};
  for (const auto& g : summaryGroups()) {
    Table t{{"quantity", "value", "unit"}, {}};
    for (const char* key : g.keys) {
      placed.emplace_back(key);
      if (all.contains(key)) groupRows(t, all[key], key);
    }
    if (t.rows.empty()) continue;
    page.heading(3, g.title);
    page.table(t, "summary");
  }
  Table other{{"quantity", "value", "unit"}, {}};
  for (auto it = all.begin(); it != all.end(); ++it)
    if (std::find(placed.begin(), placed.end(), it.key()) == placed.end()) groupRows(other, *it, it.key());
  if (!other.rows.empty()) {
    page.heading(3, "Other");
    page.table(other, "summary");
  }
  // Every key as written, and the configuration, folded away.
  json rest = all;
  rest.erase("config");
  rest.erase("controller_sections");
  Table raw = flatTable(rest, "");
  for (auto& row : raw.rows) row[1].key.clear();  // the data-key cells are the grouped tables'
  page.beginDetails("Every key of summary.json (" + std::to_string(raw.rows.size()) + ")");
  page.table(raw, "summary");
  page.endDetails();
  if (all.contains("config") || all.contains("controller_sections")) {
    page.beginDetails("Configuration (summary.json \"config\" and \"controller_sections\")");
    for (const char* key : {"config", "controller_sections"})
      if (all.contains(key)) page.table(flatTable(all[key], key), "summary");
    page.endDetails();
  }
}

}  // namespace sb::report
