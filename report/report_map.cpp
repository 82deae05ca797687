// The map sections of a run report: the rendered model with the mesh link, and the two-run comparison.

#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>

#include "core/error.h"
#include "report/map_difference.h"
#include "report/png_codec.h"
#include "report/run_sections.h"
#include "report/text_escape.h"
#include "report/trajectory_view.h"

namespace sb::report {

namespace {

namespace fs = std::filesystem;

struct MapImage {
  std::vector<uint8_t> png;  // the file as written by the run
  Image<uint8_t> grey;       // decoded, to prove it is a whole PNG and for differences
};

// model.png read and decoded; on failure a paragraph says why and nothing is returned.
std::optional<MapImage> loadMap(HtmlPage& page, const RunData& run) {
  if (run.modelPath.empty()) {
    page.paragraph("No rendered model: " + (fs::path(run.dir) / "model.png").string() + " is missing.", "muted");
    return std::nullopt;
  }
  try {
    MapImage m;
    m.png = readFileBytes(run.modelPath);
    m.grey = decodePngGray(m.png, run.modelPath);
    return m;
  } catch (const Error& e) {
    page.paragraph(std::string("No rendered model: ") + e.what(), "problems");
    return std::nullopt;
  }
}

// Percent-encodes a relative path for an href (keeps '/', unreserved characters).
std::string hrefForPath(const std::string& path) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : path) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

std::string percent(double fraction) { return formatNumber(fraction * 100, 3) + "%"; }

double summaryNumber(const RunData& run, double (*read)(const RunSummary&), double scale = 1) {
  return run.summary ? read(*run.summary) * scale : std::nan("");
}

TableCell numberCell(double v, const std::string& key) {
  return {std::isfinite(v) ? formatNumber(v, 4) : "-", std::isfinite(v) ? key : "", true};
}

void comparisonTable(HtmlPage& page, const RunData& a, const RunData& b) {
  struct Measure {
    const char* name;
    const char* key;
    double (*read)(const RunSummary&);
    double scale;
  };
  static constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
  const Measure measures[] = {
      {"frames", "frames", [](const RunSummary& s) { return double(s.frames); }, 1},
      {"tracked (%)", "tracked_percent", [](const RunSummary& s) { return s.trackedPercent; }, 1},
      {"computation (ms/frame)", "computation_ms_per_frame",
       [](const RunSummary& s) { return s.computationMsPerFrame; }, 1},
      {"process CPU (ms/frame)", "cpu_ms_per_frame",
       [](const RunSummary& s) { return s.cpuMsPerFrame.value_or(kNan); }, 1},
      {"ATE RMSE (cm)", "ate_rmse_cm", [](const RunSummary& s) { return s.ate ? s.ate->rmseM : kNan; }, 100},
      {"unaligned mean (cm)", "unaligned_mean_cm",
       [](const RunSummary& s) { return s.ate ? s.ate->unalignedMeanM : kNan; }, 100},
      {"energy (J/frame)", "joules_per_frame", [](const RunSummary& s) { return s.joulesPerFrame(); }, 1},
  };
  Table t{{"measure", a.label, b.label, b.label + " / " + a.label}, {}};
  for (const auto& m : measures) {
    const double va = summaryNumber(a, m.read, m.scale), vb = summaryNumber(b, m.read, m.scale);
    if (!std::isfinite(va) && !std::isfinite(vb)) continue;
    const double ratio = std::isfinite(va) && std::isfinite(vb) && va != 0 ? vb / va : std::nan("");
    t.rows.push_back({{m.name},
                      numberCell(va, std::string("compare.a.") + m.key),
                      numberCell(vb, std::string("compare.b.") + m.key),
                      numberCell(ratio, std::string("compare.ratio.") + m.key)});
  }
  page.table(t, "comparison");
}

// The viewpoint of model.png as summary.json's "model_view" names it (`run --model-view`; absent = last).
bool overviewMap(const RunData& run) {
  return run.summary && run.summary->modelView == "overview";
}

std::string viewpoint(const RunData& run) {
  return overviewMap(run) ? "the overview viewpoint (above and behind the volume centre)"
                          : "the last camera pose";
}

}  // namespace

void addMapSection(HtmlPage& page, const RunData& run, const std::string& reportDir) {
  page.heading(2, "Map", "map");
  if (auto map = loadMap(page, run)) {
    const std::string caption = "Shaded raycast of the final model from " + viewpoint(run) + " (" +
                                std::to_string(map->grey.width()) + " x " + std::to_string(map->grey.height()) +
                                " px, model.png).";
    if (run.grid)  // the navigation map above is the robot's picture: the model stays, smaller
      page.row({HtmlPage::imageMarkup(map->png, "rendered model of " + run.label, caption)});
    else
      page.image(map->png, "rendered model of " + run.label, caption);
  }
  if (run.meshPath.empty()) {
    page.paragraph("No mesh: run with --mesh to write mesh.ply.", "muted");
    return;
  }
  std::error_code ec;
  fs::path rel = fs::relative(fs::absolute(run.meshPath, ec), fs::absolute(reportDir, ec), ec);
  if (ec || rel.empty()) rel = fs::absolute(run.meshPath, ec);
  page.link(hrefForPath(rel.generic_string()), rel.generic_string(),
            "Mesh of the final volume (PLY, " + std::to_string(fs::file_size(run.meshPath, ec) / 1024) + " KiB): ");
}

void addComparisonSection(HtmlPage& page, const RunData& a, const RunData& b) {
  page.heading(2, "Comparison: " + a.label + " vs " + b.label, "comparison");
  page.paragraph(a.label + " = " + a.dir + "; " + b.label + " = " + b.dir, "muted");
  page.problems([&] {
    std::vector<std::string> p;
    for (const auto& s : b.problems) p.push_back(b.label + ": " + s);
    return p;
  }());
  comparisonTable(page, a, b);

  page.heading(3, "Maps");
  auto mapA = loadMap(page, a);
  auto mapB = loadMap(page, b);
  std::vector<std::string> items;
  if (mapA) items.push_back(HtmlPage::imageMarkup(mapA->png, "map of " + a.label, a.label));
  if (mapB) items.push_back(HtmlPage::imageMarkup(mapB->png, "map of " + b.label, b.label));
  std::string stats;
  if (mapA && mapB) {
    const MapDifference d = compareMaps(mapA->grey, mapB->grey);
    items.push_back(HtmlPage::imageMarkup(
        encodePng(d.image), "difference of the maps",
        "Difference: grey = equal, red = shading differs (full red at " + std::to_string(kDifferenceSaturation) +
            " grey levels), blue = surface only in " + a.label + ", orange = only in " + b.label + "."));
    stats = "Where both see a surface (" + std::to_string(d.bothPixels) + " px): mean difference " +
            formatNumber(d.meanAbsDifference, 3) + " grey levels, " + percent(d.fractionDifferent) + " differ by more than " +
            std::to_string(kDifferenceThreshold) + ". Surface only in " + a.label + ": " + percent(d.fractionOnlyA) +
            " of the image; only in " + b.label + ": " + percent(d.fractionOnlyB) + "." +
            (d.resampled ? " The images differ in size: " + b.label + " was resampled to " + a.label + "'s." : "");
  }
  page.row(items);
  if (!stats.empty()) page.paragraph(stats);
  const bool sameView = overviewMap(a) && overviewMap(b);
  page.paragraph(
      sameView ? "Both maps are rendered from the same overview viewpoint: the differences are the models'."
               : a.label + " is rendered from " + viewpoint(a) + ", " + b.label + " from " + viewpoint(b) +
                     ", so a pose difference between the runs also shows up as a shading difference.",
      "muted");

  if (a.grid || b.grid) {
    const RunData& on = a.grid ? a : b;
    const RunData& other = a.grid ? b : a;
    page.heading(3, "Paths on the navigation map");
    page.figure(navMapFigure(on, &other),
                "Both runs' paths on " + on.label + "'s map.pgm, each in its own map frame" +
                    (other.grid ? "" : " (" + other.label + " wrote no grid: its path is drawn through " + on.label +
                                           "'s map frame)") +
                    "; ring at the start, dot at the end.");
  } else {
    page.paragraph("No navigation map: neither run wrote map.pgm.", "muted");
  }

  const RunData& withTruth = a.groundTruth.empty() ? b : a;
  if (!a.trajectory.empty() || !b.trajectory.empty()) {
    const TopView view = chooseTopView(withTruth);
    XyPlot plot;
    plot.title = "Top view (" + view.dropped + " axis dropped)";
    plot.xLabel = view.xLabel;
    plot.yLabel = view.yLabel;
    if (!withTruth.groundTruth.empty()) plot.series.push_back(groundTruthSeries(withTruth, view));
    for (const RunData* r : {&a, &b})
      if (!r->trajectory.empty()) plot.series.push_back(estimateSeries(*r, view, r->label + (r->ate ? " (aligned)" : "")));
    page.figure(svgXyPlot(plot), "Each estimate is aligned to the ground truth on its own when it has one.");
  }
  if (a.ate || b.ate) {
    LinePlot ite;
    ite.title = "ITE per frame";
    ite.xLabel = "frame";
    ite.yLabel = "error (cm)";
    ite.yMin = 0.0;
    for (const RunData* r : {&a, &b})
      if (r->ate) ite.series.push_back(iteSeries(*r, false, r->label));
    page.figure(svgLinePlot(ite));
  }
}

}  // namespace sb::report
