#include "reloc/fern_encoder.h"

#include <random>

#include "core/error.h"

namespace sb {

double FernCode::dissimilarity(const FernCode& other) const {
  if (codes.empty() || codes.size() != other.codes.size()) return 1.0;
  size_t differ = 0;
  for (size_t i = 0; i < codes.size(); ++i) differ += codes[i] != other.codes[i];
  return double(differ) / double(codes.size());
}

FernEncoder::FernEncoder(const FernParams& p) : params_(p) {
  if (p.cellsX < 1 || p.cellsY < 1 || p.samplesPerCellSide < 1 || p.ferns < 1 || p.testsPerFern < 1 ||
      p.testsPerFern > 8 || !(p.thresholdRangeM > 0) || !(p.minValidCells >= 0 && p.minValidCells <= 1))
    throw Error("FernEncoder: invalid parameters (cells, samples and ferns >= 1, 1..8 tests per fern, a positive "
                "threshold range, minValidCells in [0, 1])");
  std::mt19937 rng(p.seed);
  std::uniform_int_distribution<int> cell(0, p.cellsX * p.cellsY - 1);
  std::uniform_real_distribution<float> threshold(float(-p.thresholdRangeM), float(p.thresholdRangeM));
  tests_.reserve(static_cast<size_t>(p.ferns) * p.testsPerFern);
  for (int i = 0; i < p.ferns * p.testsPerFern; ++i) {
    const int c = cell(rng);
    tests_.push_back({c, threshold(rng)});
  }
}

FernCode FernEncoder::encode(const DepthRaw& depth, double metresPerUnit) const {
  const FernParams& p = params_;
  const int w = depth.width(), h = depth.height();
  if (w < p.cellsX || h < p.cellsY) return {};
  // The small image: per cell, the mean of the valid readings on a samples x samples grid of its pixels.
  std::vector<float> cells(static_cast<size_t>(p.cellsX) * p.cellsY, 0.0f);
  std::vector<uint8_t> valid(cells.size(), 0);
  int validCells = 0;
  double sum = 0.0;
  const int n = p.samplesPerCellSide;
  for (int cy = 0; cy < p.cellsY; ++cy) {
    const int y0 = cy * h / p.cellsY, y1 = (cy + 1) * h / p.cellsY;
    for (int cx = 0; cx < p.cellsX; ++cx) {
      const int x0 = cx * w / p.cellsX, x1 = (cx + 1) * w / p.cellsX;
      double cellSum = 0.0;
      int count = 0;
      for (int sy = 0; sy < n; ++sy) {
        const int y = y0 + ((2 * sy + 1) * (y1 - y0)) / (2 * n);
        for (int sx = 0; sx < n; ++sx) {
          const int x = x0 + ((2 * sx + 1) * (x1 - x0)) / (2 * n);
          const uint16_t raw = depth(x, y);
          if (raw == 0) continue;
          cellSum += raw;
          ++count;
        }
      }
      if (count * 2 < n * n) continue;  // a cell needs half of its samples
      const size_t i = static_cast<size_t>(cy) * p.cellsX + cx;
      cells[i] = static_cast<float>(cellSum / count * metresPerUnit);
      valid[i] = 1;
      sum += cells[i];
      ++validCells;
    }
  }
  if (validCells == 0 || validCells < p.minValidCells * double(cells.size())) return {};
  const float mean = static_cast<float>(sum / validCells);
  FernCode code;
  code.codes.resize(static_cast<size_t>(p.ferns));
  for (int f = 0; f < p.ferns; ++f) {
    uint8_t bits = 0;
    for (int t = 0; t < p.testsPerFern; ++t) {
      const Test& test = tests_[static_cast<size_t>(f) * p.testsPerFern + t];
      // A cell without depth reads as "far" (the sensor sees nothing near there).
      const bool deeper = !valid[test.cell] || cells[test.cell] - mean > test.threshold;
      bits = static_cast<uint8_t>(bits | (deeper ? 1u << t : 0u));
    }
    code.codes[f] = bits;
  }
  return code;
}

}  // namespace sb
