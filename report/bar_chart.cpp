// svgBarChart: grouped bars per category (e.g. per-sequence time or ATE, one bar per controller).

#include <algorithm>
#include <cmath>

#include "report/plot_frame.h"
#include "report/plots.h"
#include "report/text_escape.h"

namespace sb::report {

using namespace detail;

std::string svgBarChart(const BarChart& chart) {
  SvgWriter svg(chart.size.width, chart.size.height, chart.title);
  FrameLayout layout{chart.title, "", chart.yLabel, {}, {}, 16};
  std::vector<std::string> colours;
  for (size_t g = 0; g < chart.groups.size(); ++g) {
    colours.push_back(chart.groups[g].color.empty() ? paletteColour(g) : chart.groups[g].color);
    layout.legend.push_back({chart.groups[g].name, colours.back(), LegendKind::area});
  }
  const bool limit = std::isfinite(chart.limit);
  if (limit) layout.legend.push_back({chart.limitName, "#CC0000", LegendKind::dashed});
  double lo = 0, hi = limit ? chart.limit : 0;  // bars start at zero
  if (limit) lo = std::min(lo, chart.limit);
  for (const auto& g : chart.groups)
    for (double v : g.values)
      if (std::isfinite(v)) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
  if (lo == hi) hi = 1;
  const Axis yAxis = niceAxis(lo, hi, 5);
  layout.yTickLabels = yAxis.labels;

  // Long category names are drawn rotated; reserve room for them below the axis.
  const size_t categories = std::max<size_t>(1, chart.categories.size());
  double longest = 0;
  for (const auto& c : chart.categories) longest = std::max(longest, textWidth(c, 11));
  const double slotGuess = (chart.size.width - 80) / static_cast<double>(categories);
  const bool rotate = longest > slotGuess - 4;
  if (rotate) layout.xTickLabelHeight = std::min(120.0, longest * 0.71 + 16);

  PlotArea a = drawFrame(svg, chart.size, layout);
  a.xMin = 0;
  a.xMax = static_cast<double>(categories);
  a.yMin = yAxis.min;
  a.yMax = yAxis.max;
  drawAxes(svg, a, layout, {}, {}, yAxis.ticks, yAxis.labels);

  const double groups = static_cast<double>(std::max<size_t>(1, chart.groups.size()));
  const double slot = (a.right - a.left) / static_cast<double>(categories);
  const double barWidth = slot * 0.8 / groups;
  for (size_t c = 0; c < chart.categories.size(); ++c) {
    const double x0 = a.left + slot * static_cast<double>(c) + slot * 0.1;
    for (size_t g = 0; g < chart.groups.size(); ++g) {
      if (c >= chart.groups[g].values.size()) continue;
      const double v = chart.groups[g].values[c];
      if (!std::isfinite(v)) continue;
      const double x = x0 + barWidth * static_cast<double>(g);
      const double yTop = a.py(std::max(v, 0.0)), yBottom = a.py(std::min(v, 0.0));
      svg.beginGroup(chart.categories[c] + ", " + chart.groups[g].name + ": " + formatNumber(v, 4));
      svg.rect(x, yTop, barWidth - 1, yBottom - yTop, colours[g]);
      if (chart.valueLabels)
        svg.text(x + barWidth / 2, (v >= 0 ? yTop - 3 : yBottom + 11), formatNumber(v, 3),
                 {9, Anchor::middle, "#333333"});
      svg.endGroup();
    }
    const double cx = a.left + slot * (static_cast<double>(c) + 0.5);
    if (rotate)
      svg.text(cx, a.bottom + 12, chart.categories[c], {11, Anchor::end, "#222222", false, -45});
    else
      svg.text(cx, a.bottom + 15, chart.categories[c], {11, Anchor::middle});
  }
  if (a.yMin < 0) svg.line(a.left, a.py(0), a.right, a.py(0), {"#444444", 1});
  if (limit) svg.line(a.left, a.py(chart.limit), a.right, a.py(chart.limit), {"#CC0000", 1.2, "6 4"});
  return svg.str();
}

const std::string& paletteColour(size_t index) {
  // Okabe-Ito (reordered so the first colours separate well on white), then four of Tol's muted colours
  // so that a stack of all ten pipeline stages needs no repeat.
  static const std::string palette[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9",
                                        "#000000", "#F0E442", "#882255", "#999933", "#44AA99", "#AA4499"};
  return palette[index % (sizeof palette / sizeof palette[0])];
}

}  // namespace sb::report
