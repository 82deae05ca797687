// `slambooster eval-map`: the navigation grid of a run (map.pgm, map.yaml, map_frame.json; navmap/) against
// the true occupancy of the synthetic corridor it ran in (synth/corridor_scene.h, regenerated from its seed and
// length), brought into the scene's frame by the rigid transform fitted on the run's whole poses against the
// ground truth (eval/trajectory_eval.h alignFrames: positions and orientations; the ATE's fit on positions
// alone leaves a straight drive's frame free to roll about the corridor, which tilts the grid's band through
// the walls), or with --frame-of by the frame fitted on another run (a run in a kept map: its grid is in the
// frame of the run that made the store, as `eval --frame-of`). Precision: occupied cells within one cell of a
// truly occupied one; recall: truly occupied cells in the map's known area with an occupied cell within one
// cell.

#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "synth/corridor_scene.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {

namespace {

struct EvalMapOptions {
  std::string run, sequence;
  uint64_t seed = 0;
  synth::CorridorParams corridor;
  double bandMin = 0.1, bandMax = 1.5;
  std::string picture;  // a PGM: the grid in the scene's frame above the truth (README's picture)
  std::vector<std::string> frameOf;  // EST1 GT1: align by this run's frame (alignFrames), not the run's own ATE
};

struct Pgm {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;  // row 0 the top
};

Pgm readPgm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open '" + path + "'");
  std::string magic;
  in >> magic;
  if (magic != "P5") throw Error("'" + path + "': not a binary PGM (P5)");
  const auto next = [&] {
    in >> std::ws;
    while (in.peek() == '#') in.ignore(1 << 20, '\n'), in >> std::ws;
    int v = 0;
    in >> v;
    return v;
  };
  Pgm p;
  p.width = next(), p.height = next();
  next();  // maxval
  in.get();
  p.pixels.resize(size_t(p.width) * size_t(p.height));
  in.read(reinterpret_cast<char*>(p.pixels.data()), std::streamsize(p.pixels.size()));
  if (!in) throw Error("'" + path + "': truncated");
  return p;
}

void readYaml(const std::string& path, double& resolution, Eigen::Vector2d& origin) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open '" + path + "'");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("resolution:", 0) == 0) resolution = std::stod(line.substr(11));
    if (line.rfind("origin:", 0) == 0) {
      std::string body = line.substr(line.find('[') + 1);
      std::replace(body.begin(), body.end(), ',', ' ');
      std::istringstream s(body);
      s >> origin.x() >> origin.y();
    }
  }
}

void evalMap(const EvalMapOptions& o) {
  const Pgm map = readPgm(o.run + "/map.pgm");
  double res = 0.05;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  readYaml(o.run + "/map.yaml", res, origin);
  std::ifstream frameFile(o.run + "/map_frame.json");
  if (!frameFile) throw Error("cannot open '" + o.run + "/map_frame.json'");
  const nlohmann::json frame = nlohmann::json::parse(frameFile);
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = frame["T_world_to_map"][size_t(r)][size_t(c)].get<double>();
  const Eigen::Isometry3d worldToMap(m);
  const Trajectory estimate = readTumTrajectory(o.run + "/trajectory.tum");
  const Trajectory truthPath = readTumTrajectory(o.sequence + "/groundtruth.txt");
  const AteResult ate = computeAte(estimate, truthPath);
  const Eigen::Isometry3d worldToScene =
      o.frameOf.size() == 2 ? alignFrames(readTumTrajectory(o.frameOf[0]), readTumTrajectory(o.frameOf[1]))
                            : alignFrames(estimate, truthPath);
  const Eigen::Isometry3d mapToScene = worldToScene * worldToMap.inverse();
  const Eigen::Isometry3d sceneToMap = mapToScene.inverse();

  // The truth: scene cells (x, z) whose band column holds a solid; outside the room box everything is solid.
  const synth::Scene scene = synth::generateCorridor(o.seed, o.corridor);
  const double floorY = scene.roomMax.y();
  const double x0 = scene.roomMin.x(), z0 = scene.roomMin.z();
  const int nx = int(std::ceil((scene.roomMax.x() - x0) / res)), nz = int(std::ceil((scene.roomMax.z() - z0) / res));
  std::vector<uint8_t> truth(size_t(nx) * size_t(nz), 0);
  const double yTop = floorY - o.bandMax, yBottom = floorY - o.bandMin;
  for (const synth::Primitive& p : scene.primitives) {
    if (!p.bounded()) continue;
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9f), hi = -lo;
    for (const Eigen::Vector3f& c : p.corners()) lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
    if (hi.y() < yTop || lo.y() > yBottom) continue;
    const int ix0 = std::max(0, int(std::floor((lo.x() - x0) / res))), ix1 = std::min(nx - 1, int(std::floor((hi.x() - x0) / res)));
    const int iz0 = std::max(0, int(std::floor((lo.z() - z0) / res))), iz1 = std::min(nz - 1, int(std::floor((hi.z() - z0) / res)));
    for (int iz = iz0; iz <= iz1; ++iz)
      for (int ix = ix0; ix <= ix1; ++ix) {
        uint8_t& cell = truth[size_t(iz) * size_t(nx) + size_t(ix)];
        for (int s = 0; s < 9 && !cell; ++s)
          for (double y = std::max(yTop, double(lo.y())); y <= std::min(yBottom, double(hi.y())) && !cell; y += 0.02) {
            const Eigen::Vector3f q(float(x0 + (ix + 0.1667 + 0.3333 * (s % 3)) * res), float(y),
                                    float(z0 + (iz + 0.1667 + 0.3333 * (s / 3)) * res));
            cell = p.contains(q);
          }
      }
  }
  const auto truthNear = [&](int ix, int iz) {
    for (int dz = -1; dz <= 1; ++dz)
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = ix + dx, z = iz + dz;
        if (x < 0 || z < 0 || x >= nx || z >= nz || truth[size_t(z) * size_t(nx) + size_t(x)]) return true;
      }
    return false;
  };
  const auto mapAt = [&](int i, int j) -> int {  // j counted from the bottom; -1 outside
    if (i < 0 || j < 0 || i >= map.width || j >= map.height) return -1;
    return map.pixels[size_t(map.height - 1 - j) * size_t(map.width) + size_t(i)];
  };
  const double midBand = 0.5 * (o.bandMin + o.bandMax);
  size_t occupied = 0, correct = 0;
  for (int j = 0; j < map.height; ++j)
    for (int i = 0; i < map.width; ++i) {
      if (mapAt(i, j) != 0) continue;
      ++occupied;
      const Eigen::Vector3d s = mapToScene * Eigen::Vector3d(origin.x() + (i + 0.5) * res, origin.y() + (j + 0.5) * res, midBand);
      correct += truthNear(int(std::floor((s.x() - x0) / res)), int(std::floor((s.z() - z0) / res)));
    }
  size_t trulyKnown = 0, found = 0;
  for (int iz = 0; iz < nz; ++iz)
    for (int ix = 0; ix < nx; ++ix) {
      if (!truth[size_t(iz) * size_t(nx) + size_t(ix)]) continue;
      const Eigen::Vector3d p = sceneToMap * Eigen::Vector3d(x0 + (ix + 0.5) * res, floorY - midBand, z0 + (iz + 0.5) * res);
      const int i = int(std::floor((p.x() - origin.x()) / res)), j = int(std::floor((p.y() - origin.y()) / res));
      const int here = mapAt(i, j);
      if (here != 0 && here != 254) continue;  // outside the map's known area
      ++trulyKnown;
      bool hit = false;
      for (int dj = -1; dj <= 1 && !hit; ++dj)
        for (int di = -1; di <= 1 && !hit; ++di) hit = mapAt(i + di, j + dj) == 0;
      found += hit;
    }
  if (!o.picture.empty()) {  // rows along the corridor (scene z), the map above the truth, 4 px between
    std::ofstream out(o.picture, std::ios::binary);
    out << "P5\n" << nz << " " << 2 * nx + 4 << "\n255\n";
    for (int ix = nx - 1; ix >= 0; --ix)
      for (int iz = 0; iz < nz; ++iz) {
        const Eigen::Vector3d p = sceneToMap * Eigen::Vector3d(x0 + (ix + 0.5) * res, floorY - midBand, z0 + (iz + 0.5) * res);
        const int v = mapAt(int(std::floor((p.x() - origin.x()) / res)), int(std::floor((p.y() - origin.y()) / res)));
        out.put(char(v < 0 ? 205 : v));
      }
    for (int i = 0; i < 4 * nz; ++i) out.put(char(255));
    for (int ix = nx - 1; ix >= 0; --ix)
      for (int iz = 0; iz < nz; ++iz) out.put(char(truth[size_t(iz) * size_t(nx) + size_t(ix)] ? 0 : 254));
    if (!out) throw Error("cannot write '" + o.picture + "'");
  }
  std::cout << std::fixed << std::setprecision(3) << "map " << map.width << "x" << map.height << " cells of " << res
            << " m (" << frame.value("source", "") << "), aligned by "
            << (o.frameOf.size() == 2 ? "the frame of " + o.frameOf[0] : std::string("the trajectory"))
            << " (whole poses; the run's ATE rmse " << ate.rmse * 100 << " cm)\n"
            << "precision " << (occupied ? double(correct) / double(occupied) : 0.0) << " (" << correct << "/"
            << occupied << " occupied cells within one cell of a truly occupied one)\n"
            << "recall " << (trulyKnown ? double(found) / double(trulyKnown) : 0.0) << " (" << found << "/"
            << trulyKnown << " truly occupied cells in the known area with an occupied cell within one)\n";
}

}  // namespace

void addEvalMapCommand(CLI::App& app) {
  auto o = std::make_shared<EvalMapOptions>();
  auto* sub = app.add_subcommand("eval-map", "A run's navigation grid against the synthetic corridor's true occupancy");
  sub->add_option("run", o->run, "Run directory (map.pgm, map.yaml, map_frame.json, trajectory.tum)")->required();
  sub->add_option("sequence", o->sequence, "The corridor sequence it ran (groundtruth.txt)")->required();
  sub->add_option("--seed", o->seed, "The corridor's seed (synth --seed)")->capture_default_str();
  sub->add_option("--corridor-length", o->corridor.lengthM, "synth --corridor-length")->capture_default_str();
  sub->add_option("--corridor-spacing", o->corridor.spacingScale, "synth --corridor-spacing")->capture_default_str();
  sub->add_option("--band-min", o->bandMin, "The robot's band (m), as the run's")->capture_default_str();
  sub->add_option("--band-max", o->bandMax)->capture_default_str();
  sub->add_option("--frame-of", o->frameOf,
                  "EST1 GT1: align the grid by the frame fitted on another run's whole poses (EST1 against GT1), not\n"
                  "by the run's own trajectory: a run in a kept map (--map-store), whose grid is in the store's frame")
      ->expected(2);
  sub->add_option("--picture", o->picture, "Also write a PGM: the grid in the scene's frame above the true occupancy");
  sub->callback([o] { evalMap(*o); });
}

}  // namespace sb::cli
