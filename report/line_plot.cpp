// svgLinePlot: signals over a shared x axis, optionally stacked, with event lanes along the top.

#include <algorithm>
#include <cmath>
#include <limits>

#include "report/plot_frame.h"
#include "report/plots.h"

namespace sb::report {

using namespace detail;

namespace {

constexpr double kLaneHeight = 9;  // px per event lane

struct Range {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return lo > hi; }
};

// Cumulative sums of the series (stacked plots); non-finite values count as 0.
std::vector<std::vector<double>> stackedTops(const std::vector<Series>& series) {
  std::vector<std::vector<double>> tops;
  for (const auto& s : series) {
    std::vector<double> top(s.y.size());
    for (size_t i = 0; i < s.y.size(); ++i) {
      const double below = tops.empty() || i >= tops.back().size() ? 0.0 : tops.back()[i];
      top[i] = below + (std::isfinite(s.y[i]) ? s.y[i] : 0.0);
    }
    tops.push_back(std::move(top));
  }
  return tops;
}

// Splits a series into runs of finite points (gaps at NaN), as pixel polylines.
std::vector<std::vector<Point>> pixelRuns(const PlotArea& a, const std::vector<double>& x,
                                          const std::vector<double>& y, LineStyle style) {
  std::vector<std::vector<Point>> runs(1);
  const size_t n = std::min(x.size(), y.size());
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) {
      if (!runs.back().empty()) runs.emplace_back();
      continue;
    }
    const Point p{a.px(x[i]), a.py(clampY(a, y[i]))};
    if (style == LineStyle::step && !runs.back().empty()) runs.back().push_back({p.first, runs.back().back().second});
    runs.back().push_back(p);
  }
  return runs;
}

}  // namespace

std::string svgLinePlot(const LinePlot& plot) {
  SvgWriter svg(plot.size.width, plot.size.height, plot.title);
  size_t colourIndex = 0;
  std::vector<std::string> colours;
  FrameLayout layout{plot.title, plot.xLabel, plot.yLabel, {}, {}, 16};
  for (const auto& s : plot.series) {
    colours.push_back(s.color.empty() ? paletteColour(colourIndex++) : s.color);
    const LegendKind kind = plot.stacked ? LegendKind::area
                            : s.style == LineStyle::points ? LegendKind::dot
                            : s.dashed ? LegendKind::dashed
                                       : LegendKind::line;
    layout.legend.push_back({s.name, colours.back(), kind});
  }
  std::vector<std::string> eventColours;
  for (const auto& e : plot.events) {
    eventColours.push_back(e.color.empty() ? paletteColour(colourIndex++) : e.color);
    layout.legend.push_back({e.name, eventColours.back(), LegendKind::mark});
  }

  const auto tops = plot.stacked ? stackedTops(plot.series) : std::vector<std::vector<double>>{};
  Range xr, yr;
  for (size_t k = 0; k < plot.series.size(); ++k) {
    for (double v : plot.series[k].x) xr.add(v);
    for (double v : plot.stacked ? tops[k] : plot.series[k].y) yr.add(v);
  }
  for (const auto& e : plot.events)
    for (double v : e.x) xr.add(v);
  if (plot.stacked) yr.add(0.0);
  if (xr.empty()) xr = {0, 1};
  if (yr.empty()) yr = {0, 1};

  const Axis xAxis = niceAxis(xr.lo, xr.hi, 8);
  Axis yAxis = niceAxis(plot.yMin.value_or(yr.lo), plot.yMax.value_or(yr.hi), 5);
  if (plot.yMin) yAxis.min = *plot.yMin;
  if (plot.yMax) yAxis.max = *plot.yMax;
  std::vector<double> yTicks;
  std::vector<std::string> yLabels;
  if (!plot.yTicks.empty()) {
    for (const auto& [v, l] : plot.yTicks) {
      yTicks.push_back(v);
      yLabels.push_back(l);
      yAxis.min = std::min(yAxis.min, v);
      yAxis.max = std::max(yAxis.max, v);
    }
  } else {
    for (size_t i = 0; i < yAxis.ticks.size(); ++i)
      if (yAxis.ticks[i] >= yAxis.min - 1e-9 * yAxis.step && yAxis.ticks[i] <= yAxis.max + 1e-9 * yAxis.step) {
        yTicks.push_back(yAxis.ticks[i]);
        yLabels.push_back(yAxis.labels[i]);
      }
  }
  layout.yTickLabels = yLabels;

  PlotArea a = drawFrame(svg, plot.size, layout);
  const double lanes = kLaneHeight * static_cast<double>(plot.events.size());
  a.xMin = xAxis.min;
  a.xMax = xAxis.max;
  a.yMin = yAxis.min;
  a.yMax = yAxis.max;
  // Event lanes sit above the data: shrink the data area's top edge without changing the frame.
  PlotArea data = a;
  data.top = std::min(a.bottom - 10, a.top + lanes + (lanes > 0 ? 4 : 0));
  drawAxes(svg, data, layout, xAxis.ticks, xAxis.labels, yTicks, yLabels);

  for (size_t k = 0; k < plot.series.size(); ++k) {
    const Series& s = plot.series[k];
    if (plot.stacked) {
      const std::vector<double>* below = k > 0 ? &tops[k - 1] : nullptr;
      std::vector<Point> poly;
      const size_t n = std::min(s.x.size(), tops[k].size());
      for (size_t i = 0; i < n; ++i)
        if (std::isfinite(s.x[i])) poly.push_back({data.px(s.x[i]), data.py(clampY(data, tops[k][i]))});
      for (size_t i = n; i-- > 0;)
        if (std::isfinite(s.x[i]))
          poly.push_back({data.px(s.x[i]), data.py(clampY(data, below ? (*below)[i] : 0.0))});
      svg.beginGroup(s.name);
      svg.polygon(poly, colours[k], 0.85);
      svg.endGroup();
      continue;
    }
    svg.beginGroup(s.name);
    for (const auto& run : pixelRuns(data, s.x, s.y, s.style)) {
      if (s.style == LineStyle::points || run.size() == 1)
        for (const auto& [px, py] : run) svg.circle(px, py, std::max(1.5, s.width), colours[k]);
      else
        svg.polyline(run, {colours[k], s.width, s.dashed ? "5 3" : ""});
    }
    svg.endGroup();
  }

  for (size_t k = 0; k < plot.events.size(); ++k) {
    const double laneTop = a.top + 2 + kLaneHeight * static_cast<double>(k);
    svg.beginGroup(plot.events[k].name + " (" + std::to_string(plot.events[k].x.size()) + ")");
    const std::vector<double>& xs = plot.events[k].x;
    for (size_t i = 0; i < xs.size(); ++i) {
      if (!std::isfinite(xs[i])) continue;
      size_t last = i;
      while (plot.events[k].spans && last + 1 < xs.size() && std::isfinite(xs[last + 1]) && xs[last + 1] >= xs[last] &&
             xs[last + 1] - xs[last] <= 1.0)
        ++last;
      if (last == i) {
        svg.line(data.px(xs[i]), laneTop, data.px(xs[i]), laneTop + kLaneHeight - 2, {eventColours[k], 1.5});
      } else {
        const double x0 = data.px(xs[i]), x1 = data.px(xs[last]);
        svg.rect(x0 - 0.75, laneTop, std::max(1.5, x1 - x0 + 1.5), kLaneHeight - 2, eventColours[k]);
      }
      i = last;
    }
    svg.endGroup();
  }
  return svg.str();
}

}  // namespace sb::report
