#include "report/nav_files.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "core/config_reader.h"
#include "core/error.h"

namespace sb::report {

namespace fs = std::filesystem;

namespace {

bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

std::string readAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw Error("cannot open '" + p.string() + "'");
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// "resolution: 0.05" and "origin: [x, y, yaw]" of map_server's YAML (the two keys navmap writes on one line each).
void readYaml(const fs::path& path, NavGrid& grid) {
  std::istringstream in(readAll(path));
  bool resolution = false, origin = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("resolution:", 0) == 0) {
      grid.resolutionM = std::strtod(line.c_str() + 11, nullptr);
      resolution = grid.resolutionM > 0 && std::isfinite(grid.resolutionM);
    } else if (line.rfind("origin:", 0) == 0) {
      const size_t open = line.find('[');
      if (open == std::string::npos) continue;
      std::string body = line.substr(open + 1);
      for (char& c : body)
        if (c == ',' || c == ']') c = ' ';
      std::istringstream s(body);
      origin = static_cast<bool>(s >> grid.originX >> grid.originY);
    }
  }
  if (!resolution || !origin)
    throw Error("'" + path.string() + "' lacks " + (resolution ? "origin: [x, y, yaw]" : "a positive resolution:") +
                " (map_server's map.yaml)");
}

void readMapFrame(const fs::path& path, NavGrid& grid) {
  const nlohmann::json j = readJsonConfig(path.string(), "navigation map frame");
  const auto where = "'" + path.string() + "'";
  if (!j.contains("T_world_to_map") || !j["T_world_to_map"].is_array() || j["T_world_to_map"].size() != 4)
    throw Error(where + ": key \"T_world_to_map\" should be 4 rows of 4 numbers");
  Eigen::Matrix4d m;
  for (size_t r = 0; r < 4; ++r) {
    const auto& row = j["T_world_to_map"][r];
    if (!row.is_array() || row.size() != 4) throw Error(where + ": key \"T_world_to_map\" row " + std::to_string(r) + " should be 4 numbers");
    for (size_t c = 0; c < 4; ++c) {
      if (!row[c].is_number()) throw Error(where + ": key \"T_world_to_map\" row " + std::to_string(r) + " holds " + row[c].dump());
      m(int(r), int(c)) = row[c].get<double>();
    }
  }
  grid.T_world_to_map = Eigen::Isometry3d(m);
  if (j.contains("source") && j["source"].is_string()) grid.up = j["source"].get<std::string>();
}

}  // namespace

Image<uint8_t> parsePgm(const std::string& bytes, const std::string& name) {
  size_t pos = 0;
  const auto token = [&]() -> std::string {
    while (pos < bytes.size()) {  // whitespace and '#' comments between header fields
      if (std::isspace(static_cast<unsigned char>(bytes[pos]))) {
        ++pos;
      } else if (bytes[pos] == '#') {
        while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
      } else {
        break;
      }
    }
    const size_t start = pos;
    while (pos < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[pos]))) ++pos;
    return bytes.substr(start, pos - start);
  };
  if (token() != "P5") throw Error("'" + name + "' is not a binary PGM (no P5 header)");
  const std::string w = token(), h = token(), max = token();
  const auto positive = [](const std::string& s) {
    return !s.empty() && s.size() < 6 && s.find_first_not_of("0123456789") == std::string::npos ? std::stoi(s) : 0;
  };
  const int width = positive(w), height = positive(h), maxval = positive(max);
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw Error("'" + name + "': size " + w + " x " + h + " is not 1-16384 cells a side");
  if (maxval <= 0 || maxval > 255) throw Error("'" + name + "': maxval " + max + " (only 8-bit PGM is read)");
  ++pos;  // the one whitespace byte after maxval
  const size_t need = size_t(width) * size_t(height);
  if (bytes.size() < pos + need)
    throw Error("'" + name + "' is truncated: " + std::to_string(bytes.size() - std::min(pos, bytes.size())) +
                " bytes of pixels, " + std::to_string(need) + " expected");
  Image<uint8_t> image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) image(x, y) = static_cast<uint8_t>(bytes[pos + size_t(y) * size_t(width) + size_t(x)]);
  return image;
}

void loadWheels(RunData& run) {
  if (!run.summary || !run.summary->odometry) {
    run.wheelsWhy = run.summary ? "the run had no odometry (summary.json has no \"odometry\")" : "no summary.json";
    return;
  }
  const std::string& source = run.summary->odometry->source;
  fs::path path(source);
  if (!isFile(path) || path.extension() == ".bag") {
    const fs::path fallback = fs::path(run.summary->sequence) / "odometry.txt";
    if (run.summary->sequence.empty() || !isFile(fallback)) {
      run.wheelsWhy = "the odometry came from '" + source + "', not a file on disk here: no wheels' path (the " +
                      "verdicts below are the run's own, from frames.jsonl)";
      return;
    }
    path = fallback;
  }
  try {
    // Streamed, and only what the run's frames span: an odometry file may hold a day of a robot's log (10^7
    // lines) for a run of seconds, and the report must not hold it all (issue 53's memory bound). At most
    // kMaxWheelPoints are kept, evenly in time.
    constexpr size_t kMaxWheelPoints = 20000;
    constexpr double kMarginS = 1.0;
    double from = -INFINITY, to = INFINITY;
    if (!run.trajectory.empty()) {
      from = run.trajectory.front().timestamp - kMarginS;
      to = run.trajectory.back().timestamp + kMarginS;
    }
    const double spacing = std::isfinite(to - from) ? (to - from) / kMaxWheelPoints : 0.0;
    TumTrajectoryReader reader(path.string());
    run.wheels.clear();
    for (TimedPose pose; reader.next(pose);) {
      if (pose.timestamp < from) continue;
      if (pose.timestamp > to) break;
      if (!run.wheels.empty() && pose.timestamp - run.wheels.back().timestamp < spacing) continue;
      run.wheels.push_back(pose);
    }
    run.wheelsPath = path.string();
  } catch (const Error& e) {
    run.wheelsWhy = std::string("the wheels' path is not shown: ") + e.what();
    run.problems.push_back(run.wheelsWhy);
  }
}

void loadGrid(RunData& run) {
  const fs::path dir(run.dir);
  if (!isFile(dir / "map.pgm")) {
    std::string why;
    if (run.summary && run.summary->navmap.is_object() && run.summary->navmap.contains("why") &&
        run.summary->navmap["why"].is_string())
      why = run.summary->navmap["why"].get<std::string>();
    run.gridWhy = "No navigation map: " +
                  (why.empty() ? (dir / "map.pgm").string() + " is missing (run with --map-mount or --map-floor)"
                               : "the run made none (" + why + ")") + ".";
    return;
  }
  try {
    NavGrid grid;
    grid.cells = parsePgm(readAll(dir / "map.pgm"), (dir / "map.pgm").string());
    readYaml(dir / "map.yaml", grid);
    readMapFrame(dir / "map_frame.json", grid);
    run.grid = std::move(grid);
  } catch (const std::exception& e) {
    run.gridWhy = std::string("No navigation map shown: ") + e.what();
    run.problems.push_back(run.gridWhy);
  }
}

}  // namespace sb::report
