#include "tools/slambooster/bench_plots.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace sb::cli {

namespace {

const char* const kColors[] = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f",
                               "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac"};

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

void save(const std::string& path, const std::string& svg) {
  std::ofstream out(path);
  out << svg;
  if (!out) throw Error("cannot write plot '" + path + "'");
}

}  // namespace

void writeBarChart(const std::string& path, const BarChart& c) {
  const double groupW = 30.0 * double(std::max<size_t>(c.series.size(), 1)) + 20, left = 60, top = 40, h = 260;
  const double width = left + groupW * double(c.groups.size()) + 160, height = top + h + 110;
  double maxV = c.limit;
  for (const auto& g : c.values)
    for (double v : g)
      if (std::isfinite(v)) maxV = std::max(maxV, v);
  if (maxV <= 0) maxV = 1;
  const auto y = [&](double v) { return top + h - v / maxV * h; };
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width << "' height='" << height
    << "' font-family='sans-serif' font-size='11'>\n<text x='" << left << "' y='20' font-size='14'>" << c.title
    << "</text>\n<line x1='" << left << "' y1='" << top + h << "' x2='" << width - 150 << "' y2='" << top + h
    << "' stroke='black'/>\n";
  for (int t = 0; t <= 4; ++t) {
    const double v = maxV * t / 4;
    s << "<text x='" << left - 5 << "' y='" << y(v) + 4 << "' text-anchor='end'>" << fmt(v) << "</text>"
      << "<line x1='" << left << "' y1='" << y(v) << "' x2='" << width - 150 << "' y2='" << y(v)
      << "' stroke='#ddd'/>\n";
  }
  s << "<text x='15' y='" << top + h / 2 << "' transform='rotate(-90 15," << top + h / 2 << ")'>" << c.unit
    << "</text>\n";
  for (size_t g = 0; g < c.groups.size(); ++g) {
    const double x0 = left + groupW * double(g) + 10;
    for (size_t k = 0; k < c.series.size(); ++k) {
      const double v = g < c.values.size() && k < c.values[g].size() ? c.values[g][k] : NAN;
      if (!std::isfinite(v)) continue;
      s << "<rect x='" << x0 + 30.0 * double(k) << "' y='" << y(v) << "' width='26' height='" << top + h - y(v)
        << "' fill='" << kColors[k % 10] << "'><title>" << c.series[k] << ": " << fmt(v) << "</title></rect>\n";
    }
    s << "<text x='" << x0 << "' y='" << top + h + 14 << "' transform='rotate(30 " << x0 << "," << top + h + 14
      << ")'>" << c.groups[g] << "</text>\n";
  }
  if (c.limit > 0)
    s << "<line x1='" << left << "' y1='" << y(c.limit) << "' x2='" << width - 150 << "' y2='" << y(c.limit)
      << "' stroke='red' stroke-dasharray='6,4'/>\n";
  for (size_t k = 0; k < c.series.size(); ++k)
    s << "<rect x='" << width - 140 << "' y='" << top + 16.0 * double(k) << "' width='10' height='10' fill='"
      << kColors[k % 10] << "'/><text x='" << width - 125 << "' y='" << top + 16.0 * double(k) + 9 << "'>"
      << c.series[k] << "</text>\n";
  s << "</svg>\n";
  save(path, s.str());
}

void writeTraceFigure(const std::string& path, const FrameTrace& t) {
  const size_t n = std::max(t.iteCm.size(), t.csr.size());
  const double left = 70, plotW = 800, panelH = 120, gap = 30, top = 40;
  const double rasterH = 14.0 * double(t.triggerNames.size());
  const double height = top + 2 * (panelH + gap) + rasterH + 50;
  const auto x = [&](size_t i) { return left + (n > 1 ? plotW * double(i) / double(n - 1) : 0.0); };
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << left + plotW + 20 << "' height='" << height
    << "' font-family='sans-serif' font-size='11'>\n<text x='" << left << "' y='20' font-size='14'>" << t.title
    << "</text>\n";
  // Panel 1: ITE (cm).
  double maxIte = 1.0;
  for (double v : t.iteCm) maxIte = std::max(maxIte, v);
  s << "<text x='5' y='" << top + panelH / 2 << "'>ITE cm</text><text x='" << left - 5 << "' y='" << top + 8
    << "' text-anchor='end'>" << fmt(maxIte) << "</text>\n<polyline fill='none' stroke='#4e79a7' points='";
  for (size_t i = 0; i < t.iteCm.size(); ++i) s << x(i) << "," << top + panelH - t.iteCm[i] / maxIte * panelH << " ";
  s << "'/>\n";
  // Panel 2: csr (1, 2, 4, 8 as levels 0..3).
  const double top2 = top + panelH + gap;
  s << "<text x='5' y='" << top2 + panelH / 2 << "'>csr</text>\n";
  for (int level = 0; level < 4; ++level)
    s << "<text x='" << left - 5 << "' y='" << top2 + panelH - level * panelH / 3 + 4 << "' text-anchor='end'>"
      << (1 << level) << "</text>\n";
  s << "<polyline fill='none' stroke='#e15759' points='";
  for (size_t i = 0; i < t.csr.size(); ++i) {
    const double level = std::log2(std::max(1, t.csr[i]));
    s << x(i) << "," << top2 + panelH - level * panelH / 3 << " ";
  }
  s << "'/>\n";
  // Raster of triggers.
  const double top3 = top2 + panelH + gap;
  for (size_t r = 0; r < t.triggerNames.size(); ++r) {
    const double yy = top3 + 14.0 * double(r);
    s << "<text x='" << left - 5 << "' y='" << yy + 10 << "' text-anchor='end'>" << t.triggerNames[r] << "</text>\n";
    for (size_t i = 0; i < t.triggers[r].size(); ++i)
      if (t.triggers[r][i])
        s << "<rect x='" << x(i) << "' y='" << yy + 2 << "' width='" << std::max(1.0, plotW / double(n))
          << "' height='10' fill='" << kColors[r % 10] << "'/>";
    s << "\n";
  }
  s << "<text x='" << left + plotW / 2 << "' y='" << height - 10 << "'>frame</text>\n</svg>\n";
  save(path, s.str());
}

}  // namespace sb::cli
