#pragma once
// Internal to the plot implementations: the figure layout (title, legend rows, plot area, margins sized to
// the tick labels) and the drawing of title, legend, grid and axes.

#include <string>
#include <vector>

#include "report/axis.h"
#include "report/plots.h"
#include "report/svg_writer.h"

namespace sb::report::detail {

enum class LegendKind { line, dashed, area, mark, ring, dot };

struct LegendEntry {
  std::string name, color;
  LegendKind kind = LegendKind::line;
};

// Pixel rectangle of the data area and the data range it shows.
struct PlotArea {
  double left = 0, top = 0, right = 0, bottom = 0;  // px
  double xMin = 0, xMax = 1, yMin = 0, yMax = 1;    // data units
  double px(double x) const { return left + (x - xMin) / (xMax - xMin) * (right - left); }
  double py(double y) const { return bottom - (y - yMin) / (yMax - yMin) * (bottom - top); }
};

struct FrameLayout {
  std::string title, xLabel, yLabel;
  std::vector<LegendEntry> legend;
  std::vector<std::string> yTickLabels;  // to size the left margin
  double xTickLabelHeight = 16;         // px below the axis for tick labels (more when rotated)
};

// Rough width of `text` at `fontSize` px in a sans-serif font (no font metrics available offline).
double textWidth(const std::string& text, double fontSize);

// Computes the plot area for `size` and draws title and legend. The caller sets the data ranges.
PlotArea drawFrame(SvgWriter& svg, const Size& size, const FrameLayout& layout);

// Grid lines, tick marks and labels, axis labels, and the frame around the area. `xLabels` may be empty
// (no x tick labels, e.g. bar charts draw their own).
void drawAxes(SvgWriter& svg, const PlotArea& area, const FrameLayout& layout, const std::vector<double>& xTicks,
              const std::vector<std::string>& xLabels, const std::vector<double>& yTicks,
              const std::vector<std::string>& yLabels);

// Clamps y to the area's vertical range (a fixed range must not let lines run over the axes).
double clampY(const PlotArea& area, double y);

}  // namespace sb::report::detail
