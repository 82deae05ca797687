// svgXyPlot: paths in the plane (trajectory top views), equal aspect by default.

#include <algorithm>
#include <cmath>
#include <limits>

#include "report/plot_frame.h"
#include "report/plots.h"

namespace sb::report {

using namespace detail;

std::string svgXyPlot(const XyPlot& plot) {
  SvgWriter svg(plot.size.width, plot.size.height, plot.title);
  FrameLayout layout{plot.title, plot.xLabel, plot.yLabel, {}, {}, 16};
  std::vector<std::string> colours;
  size_t colourIndex = 0;  // only series without a colour take palette colours, as in line plots
  for (size_t k = 0; k < plot.series.size(); ++k) {
    const Series& s = plot.series[k];
    colours.push_back(s.color.empty() ? paletteColour(colourIndex++) : s.color);
    layout.legend.push_back({s.name, colours.back(),
                             s.style == LineStyle::points ? LegendKind::dot
                             : s.dashed                   ? LegendKind::dashed
                                                          : LegendKind::line});
  }
  if (plot.markStart && !plot.series.empty()) layout.legend.push_back({"start", "#444444", LegendKind::ring});
  if (plot.markEnd && !plot.series.empty()) layout.legend.push_back({"end", "#444444", LegendKind::dot});

  constexpr double inf = std::numeric_limits<double>::infinity();
  double x0 = inf, x1 = -inf, y0 = inf, y1 = -inf;
  for (const auto& s : plot.series)
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
        x0 = std::min(x0, s.x[i]);
        x1 = std::max(x1, s.x[i]);
        y0 = std::min(y0, s.y[i]);
        y1 = std::max(y1, s.y[i]);
      }
  if (const auto& b = plot.background) {
    x0 = std::min(x0, b->x0), x1 = std::max(x1, b->x1);
    y0 = std::min(y0, b->y0), y1 = std::max(y1, b->y1);
  }
  if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;

  Axis xAxis, yAxis;
  PlotArea a;
  if (plot.equalAspect) {
    // Pad by 5% of the larger extent, then widen the shorter axis so one unit spans equal pixels.
    const double pad = 0.05 * std::max({x1 - x0, y1 - y0, 1e-3});
    x0 -= pad, x1 += pad, y0 -= pad, y1 += pad;
    layout.yTickLabels = niceTicksWithin(y0, y1, 6).labels;  // first guess for the left margin
    a = drawFrame(svg, plot.size, layout);
    const double w = a.right - a.left, h = a.bottom - a.top;
    const double scale = std::min(w / (x1 - x0), h / (y1 - y0));  // px per unit
    const double cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
    a.xMin = cx - w / scale / 2, a.xMax = cx + w / scale / 2;
    a.yMin = cy - h / scale / 2, a.yMax = cy + h / scale / 2;
    const int xTicks = std::max(3, static_cast<int>(w / 70)), yTicks = std::max(3, static_cast<int>(h / 50));
    xAxis = niceTicksWithin(a.xMin, a.xMax, xTicks);
    yAxis = niceTicksWithin(a.yMin, a.yMax, yTicks);
    // Ticks on both axes share one step so the grid cells are square.
    const double step = std::max(xAxis.step, yAxis.step);
    xAxis = ticksWithin(a.xMin, a.xMax, step);
    yAxis = ticksWithin(a.yMin, a.yMax, step);
  } else {
    xAxis = niceAxis(x0, x1, 6);
    yAxis = niceAxis(y0, y1, 6);
    layout.yTickLabels = yAxis.labels;
    a = drawFrame(svg, plot.size, layout);
    a.xMin = xAxis.min, a.xMax = xAxis.max, a.yMin = yAxis.min, a.yMax = yAxis.max;
  }
  if (const auto& b = plot.background)  // under the grid lines and paths; the bounds above hold its extent
    svg.image(a.px(b->x0), a.py(b->y1), a.px(b->x1) - a.px(b->x0), a.py(b->y0) - a.py(b->y1), b->png);
  drawAxes(svg, a, layout, xAxis.ticks, xAxis.labels, yAxis.ticks, yAxis.labels);

  for (size_t k = 0; k < plot.series.size(); ++k) {
    const Series& s = plot.series[k];
    svg.beginGroup(s.name);
    std::vector<Point> run;
    auto flush = [&] {
      if (s.style == LineStyle::points || run.size() == 1)
        for (const auto& [px, py] : run) svg.circle(px, py, std::max(1.5, s.width), colours[k]);
      else
        svg.polyline(run, {colours[k], s.width, s.dashed ? "5 3" : ""});
      run.clear();
    };
    bool first = true;
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
        flush();
        continue;
      }
      run.push_back({a.px(s.x[i]), a.py(s.y[i])});
      if (first && plot.markStart && s.style != LineStyle::points) {
        const Stroke ring{colours[k], 1.5};
        svg.circle(run.back().first, run.back().second, 4, "none", &ring);
        first = false;
      }
    }
    flush();
    if (plot.markEnd && s.style != LineStyle::points)
      for (size_t i = std::min(s.x.size(), s.y.size()); i-- > 0;)
        if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
          svg.circle(a.px(s.x[i]), a.py(s.y[i]), 4, colours[k]);
          break;
        }
    svg.endGroup();
  }
  return svg.str();
}

}  // namespace sb::report
