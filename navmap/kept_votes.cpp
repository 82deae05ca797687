#include "navmap/kept_votes.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <tuple>

#include "core/error.h"
#include "runtime/map_store_bytes.h"

namespace sb::navmap {

namespace {

using mapstore::ByteReader;
using mapstore::ByteWriter;

constexpr uint32_t kMaxSourceBytes = 4096;
constexpr size_t kChunkCells = size_t(GridVotes::kChunk) * GridVotes::kChunk;

// The settings the votes depend on, in the payload's order, with the names a message gives them.
std::array<std::pair<const char*, double>, 5> settings(const NavMapConfig& c) {
  return {{{"resolution_m", c.resolutionM},
           {"band_min_m", c.bandMinM},
           {"band_max_m", c.bandMaxM},
           {"surface_depth_m", c.surfaceDepthM},
           {"octomap_resolution_m", c.octomapResolutionM}}};
}

Error malformed(const std::string& path, const std::string& what) {
  return Error("map store: '" + path + "' " + what + ": corrupt; move it away");
}

void encodeChunk(ByteWriter& w, const GridVotes::Chunk& chunk) {
  for (size_t i = 0; i < kChunkCells;) {
    size_t skip = 0, count = 0;
    while (i + skip < kChunkCells && chunk[i + skip].surface == 0 && chunk[i + skip].free == 0) ++skip;
    while (i + skip + count < kChunkCells &&
           (chunk[i + skip + count].surface != 0 || chunk[i + skip + count].free != 0))
      ++count;
    w.u16(uint16_t(skip));
    w.u16(uint16_t(count));
    for (size_t j = 0; j < count; ++j) {
      w.u16(chunk[i + skip + j].surface);
      w.u16(chunk[i + skip + j].free);
    }
    i += skip + count;
  }
}

void decodeChunk(ByteReader& r, GridVotes::Chunk& chunk, const std::string& path) {
  for (size_t i = 0; i < kChunkCells;) {
    const size_t skip = r.u16(), count = r.u16();
    if (skip > kChunkCells - i || count > kChunkCells - i - skip || skip + count == 0)
      throw malformed(path, "holds grid runs that do not cover a chunk");
    i += skip;
    for (size_t j = 0; j < count; ++j, ++i) {
      chunk[i].surface = r.u16();
      chunk[i].free = r.u16();
    }
  }
}

}  // namespace

std::vector<uint8_t> encodeKeptVotes(const KeptVotes& votes, const NavMapConfig& config) {
  ByteWriter w;
  const Eigen::Matrix4d m = votes.frame.T_world_to_map.matrix();
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col) w.f64(m(row, col));
  const std::string source = votes.frame.source.substr(0, kMaxSourceBytes);
  w.u32(uint32_t(source.size()));
  w.raw(source.data(), source.size());
  for (const auto& [name, value] : settings(config)) w.f64(value);
  // Sorted: the same votes give the same bytes whatever the hash's order.
  std::vector<std::tuple<int32_t, int32_t, const GridVotes::Chunk*>> chunks;
  votes.grid.forEachChunk([&](int32_t cx, int32_t cy, const GridVotes::Chunk& c) { chunks.emplace_back(cx, cy, &c); });
  std::sort(chunks.begin(), chunks.end());
  w.u32(uint32_t(chunks.size()));
  for (const auto& [cx, cy, chunk] : chunks) {
    w.i32(cx);
    w.i32(cy);
    encodeChunk(w, *chunk);
  }
  // The 3D cells sorted (z fastest) in runs of neighbours along z: a column of cells costs one header.
  std::vector<std::pair<std::array<int32_t, 3>, CellVotes>> cells;
  cells.reserve(votes.cells.size());
  votes.cells.forEach([&](int32_t x, int32_t y, int32_t z, const CellVotes& v) { cells.push_back({{x, y, z}, v}); });
  std::sort(cells.begin(), cells.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::pair<size_t, size_t>> runs;  // first cell, cells
  for (size_t i = 0; i < cells.size(); ++i) {
    const auto& c = cells[i].first;
    if (!runs.empty()) {
      auto& [first, n] = runs.back();
      const auto& last = cells[first + n - 1].first;
      if (n < 65535 && last[0] == c[0] && last[1] == c[1] && int64_t(last[2]) + 1 == c[2]) {
        ++n;
        continue;
      }
    }
    runs.emplace_back(i, 1);
  }
  w.u32(uint32_t(runs.size()));
  for (const auto& [first, n] : runs) {
    for (int32_t c : cells[first].first) w.i32(c);
    w.u16(uint16_t(n));
    for (size_t j = first; j < first + n; ++j) {
      w.u16(cells[j].second.surface);
      w.u16(cells[j].second.free);
    }
  }
  return std::move(w.bytes);
}

KeptVotes decodeKeptVotes(const std::vector<uint8_t>& payload, const std::string& path, const NavMapConfig& config) {
  ByteReader r{path, payload};
  KeptVotes out;
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col) m(row, col) = r.f64();
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  if (!m.allFinite() || !(R.transpose() * R).isIdentity(1e-6) || R.determinant() < 0.0)
    throw malformed(path, "holds a map frame that is not a rigid transform");
  out.frame.T_world_to_map.matrix() = m;
  const uint32_t sourceBytes = r.u32();
  if (sourceBytes > kMaxSourceBytes) throw malformed(path, "says its frame's source is " + std::to_string(sourceBytes) + " bytes");
  r.need(sourceBytes);
  out.frame.source.assign(payload.begin() + std::ptrdiff_t(r.at), payload.begin() + std::ptrdiff_t(r.at + sourceBytes));
  r.at += sourceBytes;
  for (const auto& [name, value] : settings(config)) {
    const double kept = r.f64();
    if (!(std::abs(kept - value) <= 1e-9 * std::max(1.0, std::abs(value))))
      throw Error("map store: '" + path + "' holds the navigation map's votes cast with " + name + " " +
                  std::to_string(kept) + ", this run has " + std::to_string(value) +
                  ": run with the navigation map's settings the store was made with (navmap keys, --map-* options), "
                  "or give another --map-store");
  }
  const uint32_t chunks = r.u32();
  if (uint64_t(chunks) * 12 > r.left()) throw malformed(path, "says it holds " + std::to_string(chunks) + " grid chunks");
  for (uint32_t i = 0; i < chunks; ++i) {
    const int32_t cx = r.i32(), cy = r.i32();
    decodeChunk(r, out.grid.chunk(cx, cy), path);
  }
  const uint32_t runs = r.u32();
  if (uint64_t(runs) * 18 > r.left()) throw malformed(path, "says it holds " + std::to_string(runs) + " runs of 3D cells");
  for (uint32_t i = 0; i < runs; ++i) {
    const int32_t x = r.i32(), y = r.i32(), z = r.i32();
    const uint16_t n = r.u16();
    if (n == 0 || int64_t(z) + n - 1 > INT32_MAX) throw malformed(path, "holds a run of 3D cells of " + std::to_string(n));
    for (uint16_t j = 0; j < n; ++j) {
      const uint16_t surface = r.u16(), free = r.u16();
      out.cells.add(x, y, z + j, surface, free);
    }
  }
  if (r.left() != 0) throw malformed(path, "has " + std::to_string(r.left()) + " bytes after its 3D cells");
  return out;
}

}  // namespace sb::navmap
