// The navigation map of a run report: map.pgm as map_server shows it, with the run's path (and the wheels' and
// the ground truth's when there are) in the map frame, start and end marked, metres on the axes.

#include <cmath>

#include "report/odometry_view.h"
#include "report/png_codec.h"
#include "report/run_sections.h"
#include "report/text_escape.h"

namespace sb::report {

namespace {

// map.pgm's cells as an image whose first row is the top of the map (PGM's order, map_server's too).
RasterBackground gridBackground(const NavGrid& g) {
  RasterBackground b;
  b.png = encodePng(g.cells);
  b.x0 = g.originX;
  b.y0 = g.originY;
  b.x1 = g.originX + g.resolutionM * g.cells.width();
  b.y1 = g.originY + g.resolutionM * g.cells.height();
  return b;
}

Series mapPath(const std::string& name, const std::vector<Eigen::Vector3d>& world, const Eigen::Isometry3d& T_world_to_map,
               const std::string& colour, bool dashed = false) {
  Series s{name, {}, {}, colour, LineStyle::line, dashed ? 1.5 : 2.0, dashed};
  for (const Eigen::Vector3d& p : world) {
    const Eigen::Vector3d m = T_world_to_map * p;
    s.x.push_back(m.x());
    s.y.push_back(m.y());
  }
  return s;
}

std::vector<Eigen::Vector3d> positions(const Trajectory& t) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : t) out.push_back(p.position());
  return out;
}

size_t countCells(const Image<uint8_t>& cells, uint8_t value) {
  size_t n = 0;
  for (int y = 0; y < cells.height(); ++y)
    for (int x = 0; x < cells.width(); ++x) n += cells(x, y) == value;
  return n;
}

}  // namespace

std::string navMapFigure(const RunData& run, const RunData* other) {
  const NavGrid& g = *run.grid;
  XyPlot plot;
  plot.title = "Navigation map (map.pgm) with the path" + std::string(other ? "s" : "");
  plot.xLabel = "x, map frame (m)";
  plot.yLabel = "y, map frame (m)";
  plot.markEnd = true;
  plot.background = gridBackground(g);
  // A wide map (a corridor) gets the page's width, a square one a square.
  const double aspect = (plot.background->x1 - plot.background->x0) / std::max(1e-6, plot.background->y1 - plot.background->y0);
  plot.size = aspect > 1.6 ? Size{900, 360} : Size{640, 560};
  if (!run.groundTruth.empty() && run.ate) {  // the truth in the run's world frame, then the map's
    std::vector<Eigen::Vector3d> truth;
    const Eigen::Isometry3d toWorld = run.ate->alignment.inverse();
    for (const auto& p : run.groundTruth) truth.push_back(toWorld * p.position());
    plot.series.push_back(mapPath("ground truth", truth, g.T_world_to_map, "#555555", true));
  }
  if (!run.wheels.empty() && !other)
    plot.series.push_back(mapPath("wheels", compareWheels(run).wheelsPath, g.T_world_to_map, "#e69f00", true));
  plot.series.push_back(mapPath(other ? run.label : "estimate", positions(run.trajectory), g.T_world_to_map, "#0072b2"));
  if (other) {
    const Eigen::Isometry3d& T = other->grid ? other->grid->T_world_to_map : g.T_world_to_map;
    plot.series.push_back(mapPath(other->label, positions(other->trajectory), T, "#d55e00"));
  }
  return svgXyPlot(plot);
}

void addNavMapSection(HtmlPage& page, const RunData& run) {
  page.heading(2, "Navigation map", "navmap");
  if (!run.grid) {
    page.paragraph(run.gridWhy, "muted");
    return;
  }
  const NavGrid& g = *run.grid;
  const size_t occupied = countCells(g.cells, 0), free = countCells(g.cells, 254);
  page.figure(navMapFigure(run, nullptr),
              "map.pgm as map_server loads it (black occupied, white free, grey unknown): " +
                  std::to_string(g.cells.width()) + " x " + std::to_string(g.cells.height()) + " cells of " +
                  formatNumber(g.resolutionM * 100, 3) + " cm (" + std::to_string(occupied) + " occupied, " +
                  std::to_string(free) + " free), up from " + (g.up.empty() ? "?" : g.up) +
                  " (map_frame.json). The run's estimate in the map frame, ring at the start, dot at the end" +
                  (run.ate ? "; the ground truth dashed, brought into the map frame by the ATE's alignment" : "") +
                  (run.wheels.empty() ? "" : "; the wheels' path dashed orange") + ".");
}

}  // namespace sb::report
