#pragma once
// The positions of a TUM trajectory file (groundtruth.txt, trajectory.tum: `timestamp tx ty tz qx qy qz qw`), in
// file order, for the system tests that hold a run's frames against the truth.
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace sb::test {

inline std::vector<std::vector<double>> tumPositions(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<double>> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double t = 0, x = 0, y = 0, z = 0;
    fields >> t >> x >> y >> z;
    out.push_back({x, y, z});
  }
  return out;
}

}  // namespace sb::test
