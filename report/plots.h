#pragma once
// Plots as standalone SVG elements (strings to embed in HTML or write to .svg files): line plots over a
// shared x (per-frame signals, stacked stage times, knob traces with event marks), grouped bar charts, and
// equal-aspect XY plots (trajectory top views). Axes carry nice-number ticks and labels; a legend sits above
// the plot area; all text is escaped. Non-finite y values leave gaps. Documented in report/README.md.

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sb::report {

enum class LineStyle {
  line,    // straight segments between samples
  step,    // hold each value until the next x (knob traces)
  points,  // dots only
};

// Constructors (rather than bare aggregates) so that brace lists may stop early without -Wextra warnings:
// Series{"name", x, y} is a solid line in the next palette colour.
struct Series {
  Series(std::string seriesName = "", std::vector<double> xs = {}, std::vector<double> ys = {},
         std::string colour = "", LineStyle lineStyle = LineStyle::line, double strokeWidth = 1.5, bool isDashed = false)
      : name(std::move(seriesName)), x(std::move(xs)), y(std::move(ys)), color(std::move(colour)),
        style(lineStyle), width(strokeWidth), dashed(isDashed) {}
  std::string name;           // legend entry; empty = not in the legend
  std::vector<double> x, y;   // same length; NaN/inf in y breaks the line
  std::string color;          // "#rrggbb"; empty = next palette colour
  LineStyle style;
  double width;               // stroke width, px
  bool dashed;
};

// Moments marked on a line plot (e.g. controller triggers): a short tick per x in a lane along the top.
struct EventMarks {
  EventMarks(std::string marksName = "", std::vector<double> xs = {}, std::string colour = "", bool asSpans = false)
      : name(std::move(marksName)), x(std::move(xs)), color(std::move(colour)), spans(asSpans) {}
  std::string name;           // legend entry, e.g. "surface trigger"
  std::vector<double> x;
  std::string color;          // empty = next palette colour
  bool spans;                 // consecutive x (sorted, steps of at most 1) drawn as one bar: states held for frames
};

struct Size {
  double width = 820, height = 260;  // px, whole figure including title, legend and axis labels
};

struct LinePlot {
  std::string title, xLabel, yLabel;
  std::vector<Series> series;
  std::vector<EventMarks> events;
  bool stacked = false;  // fill each series on top of the previous ones (all must share x)
  std::optional<double> yMin, yMax;  // fixed y range; otherwise nice bounds of the data (0 included if stacked)
  std::vector<std::pair<double, std::string>> yTicks;  // explicit y ticks (value, label) instead of nice ones
  Size size;
};

struct BarGroup {
  BarGroup(std::string groupName = "", std::vector<double> barValues = {}, std::string colour = "")
      : name(std::move(groupName)), values(std::move(barValues)), color(std::move(colour)) {}
  std::string name;            // legend entry (e.g. "DEFAULT")
  std::vector<double> values;  // one per category; NaN = no bar
  std::string color;           // empty = next palette colour
};

struct BarChart {
  std::string title, yLabel;
  std::vector<std::string> categories;  // x-axis labels (e.g. sequence names)
  std::vector<BarGroup> groups;         // bars side by side within each category
  bool valueLabels = true;              // print each bar's value above it
  double limit = NAN;     // a dashed red line across the chart (e.g. the 5 cm bound); NaN = none
  std::string limitName;  // its legend entry
  Size size;
};

// A PNG drawn under an XY plot's paths (a map), stretched over [x0, x1] x [y0, y1] in data units, pixels kept
// sharp. Its extent counts in the plot's bounds.
struct RasterBackground {
  std::vector<unsigned char> png;
  double x0 = 0, y0 = 0, x1 = 1, y1 = 1;
};

struct XyPlot {
  std::string title, xLabel, yLabel;
  std::vector<Series> series;  // paths in data units; style line or points
  bool equalAspect = true;     // one metre is as long on both axes (maps, trajectories)
  bool markStart = true;       // a ring at each line series' first finite point
  bool markEnd = false;        // a dot at each line series' last finite point
  std::optional<RasterBackground> background;
  Size size{560, 480};
};

std::string svgLinePlot(const LinePlot& plot);
std::string svgBarChart(const BarChart& chart);
std::string svgXyPlot(const XyPlot& plot);

// The palette used for series without a colour (12 entries, cycled; the first 8 colour-blind safe).
const std::string& paletteColour(size_t index);

}  // namespace sb::report
