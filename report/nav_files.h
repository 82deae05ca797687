#pragma once
// The files a robot's run adds beside the camera's (read forgivingly, like the rest of the run directory): the
// wheels' odometry the run was given and the navigation map it wrote. Each fills its RunData fields, or says
// in one line why there is nothing (`wheelsWhy`, `gridWhy`); a damaged file is also a problem.

#include <string>

#include "report/run_data.h"

namespace sb::report {

// summary.json odometry.source when it names a TUM-format file (else `<sequence>/odometry.txt`), read as
// T_camera_to_odom poses into `run.wheels`.
void loadWheels(RunData& run);

// map.pgm (binary P5, 8 bit), map.yaml (resolution, origin) and map_frame.json (T_world_to_map, source).
void loadGrid(RunData& run);

// map.pgm's pixels (P5, maxval at most 255). Throws sb::Error naming `name` and what is wrong.
Image<uint8_t> parsePgm(const std::string& bytes, const std::string& name);

}  // namespace sb::report
