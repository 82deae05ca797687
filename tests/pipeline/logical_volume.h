#pragma once
// The whole TSDF volume of a CPU backend read in logical order (through a moving volume's offset), for tests that
// compare two backends' maps voxel for voxel.

#include <cstdint>
#include <vector>

#include "pipeline/cpu/cpu_backend.h"

namespace sb::test {

inline std::vector<int16_t> logicalVolume(CpuBackend& backend, int resolution) {
  std::vector<int16_t> out(2 * size_t(resolution) * resolution * resolution);
  backend.readVolumeBox({0, 0, 0}, {resolution, resolution, resolution}, out.data());
  return out;
}

}  // namespace sb::test
