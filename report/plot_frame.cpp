#include "report/plot_frame.h"

#include <algorithm>

namespace sb::report::detail {

namespace {

constexpr double kTitleSize = 14, kLegendSize = 12, kTickSize = 11, kLabelSize = 12;
constexpr double kLegendRow = 18, kSwatch = 18, kLegendGap = 16, kPad = 8;
const std::string kAxisColour = "#444444", kGridColour = "#e4e4e4";

double legendEntryWidth(const LegendEntry& e) { return kSwatch + 6 + textWidth(e.name, kLegendSize) + kLegendGap; }

// Lays the legend out in rows within `width`; returns the number of rows (0 without named entries).
int legendRows(const std::vector<LegendEntry>& legend, double width) {
  int rows = 0;
  double x = width;  // forces a first row
  for (const auto& e : legend) {
    if (e.name.empty()) continue;
    const double w = legendEntryWidth(e);
    if (x + w > width) {
      ++rows;
      x = 0;
    }
    x += w;
  }
  return rows;
}

void drawSwatch(SvgWriter& svg, const LegendEntry& e, double x, double yMid) {
  switch (e.kind) {
    case LegendKind::area: svg.rect(x, yMid - 5, kSwatch, 10, e.color); break;
    case LegendKind::mark: svg.line(x + kSwatch / 2, yMid - 6, x + kSwatch / 2, yMid + 6, {e.color, 2.0}); break;
    case LegendKind::dot: svg.circle(x + kSwatch / 2, yMid, 3, e.color); break;
    case LegendKind::ring: {
      const Stroke ring{e.color, 1.5};
      svg.circle(x + kSwatch / 2, yMid, 4, "none", &ring);
      break;
    }
    case LegendKind::dashed: svg.line(x, yMid, x + kSwatch, yMid, {e.color, 2.0, "4 3"}); break;
    default: svg.line(x, yMid, x + kSwatch, yMid, {e.color, 2.0});
  }
}

}  // namespace

double textWidth(const std::string& text, double fontSize) {
  size_t chars = 0;
  for (unsigned char c : text)
    if ((c & 0xC0) != 0x80) ++chars;  // count UTF-8 code points, not bytes
  return 0.58 * fontSize * static_cast<double>(chars);
}

PlotArea drawFrame(SvgWriter& svg, const Size& size, const FrameLayout& layout) {
  double y = kPad;
  if (!layout.title.empty()) {
    svg.text(kPad, y + kTitleSize, layout.title, {kTitleSize, Anchor::start, "#222222", true});
    y += kTitleSize + 6;
  }
  const double legendWidth = size.width - 2 * kPad;
  const int rows = legendRows(layout.legend, legendWidth);
  double lx = legendWidth, ly = y - kLegendRow;
  for (const auto& e : layout.legend) {
    if (e.name.empty()) continue;
    const double w = legendEntryWidth(e);
    if (lx + w > legendWidth) {
      lx = 0;
      ly += kLegendRow;
    }
    drawSwatch(svg, e, kPad + lx, ly + kLegendRow / 2);
    svg.text(kPad + lx + kSwatch + 6, ly + kLegendRow / 2 + 4, e.name, {kLegendSize});
    lx += w;
  }
  y += rows * kLegendRow + 6;

  double yLabelWidth = 0;
  for (const auto& l : layout.yTickLabels) yLabelWidth = std::max(yLabelWidth, textWidth(l, kTickSize));
  PlotArea a;
  a.left = kPad + (layout.yLabel.empty() ? 0 : kLabelSize + 8) + yLabelWidth + 8;
  a.right = size.width - 2 * kPad;
  a.top = y + 4;
  a.bottom = size.height - kPad - layout.xTickLabelHeight - (layout.xLabel.empty() ? 0 : kLabelSize + 6);
  if (a.bottom < a.top + 20) a.bottom = a.top + 20;  // degenerate sizes still give a valid area
  if (a.right < a.left + 20) a.right = a.left + 20;
  return a;
}

void drawAxes(SvgWriter& svg, const PlotArea& a, const FrameLayout& layout, const std::vector<double>& xTicks,
              const std::vector<std::string>& xLabels, const std::vector<double>& yTicks,
              const std::vector<std::string>& yLabels) {
  for (size_t i = 0; i < yTicks.size(); ++i) {
    const double y = a.py(yTicks[i]);
    svg.line(a.left, y, a.right, y, {kGridColour, 1});
    svg.line(a.left - 4, y, a.left, y, {kAxisColour, 1});
    if (i < yLabels.size()) svg.text(a.left - 6, y + 4, yLabels[i], {kTickSize, Anchor::end});
  }
  for (size_t i = 0; i < xTicks.size(); ++i) {
    const double x = a.px(xTicks[i]);
    svg.line(x, a.top, x, a.bottom, {kGridColour, 1});
    svg.line(x, a.bottom, x, a.bottom + 4, {kAxisColour, 1});
    if (i < xLabels.size()) svg.text(x, a.bottom + 15, xLabels[i], {kTickSize, Anchor::middle});
  }
  const Stroke frame{kAxisColour, 1};
  svg.rect(a.left, a.top, a.right - a.left, a.bottom - a.top, "none", &frame);
  if (!layout.xLabel.empty())
    svg.text((a.left + a.right) / 2, a.bottom + layout.xTickLabelHeight + kLabelSize + 2, layout.xLabel,
             {kLabelSize, Anchor::middle});
  if (!layout.yLabel.empty())
    svg.text(kPad + kLabelSize, (a.top + a.bottom) / 2, layout.yLabel, {kLabelSize, Anchor::middle, "#222222", false, -90});
}

double clampY(const PlotArea& a, double y) {
  return std::clamp(y, std::min(a.yMin, a.yMax), std::max(a.yMin, a.yMax));
}

}  // namespace sb::report::detail
