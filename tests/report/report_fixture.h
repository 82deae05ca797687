#pragma once
// Shared by the report system tests: a short synthetic sequence reconstructed twice by the real
// `slambooster` (built once per test process), and small file helpers.

#include <string>

namespace sb::test {

struct ReportRuns {
  std::string sequence;  // 20-frame synthetic sequence with ground truth
  std::string runA;      // csr=4, with mesh.ply
  std::string runB;      // csr=8
};

// Renders and runs on first use (about 10 s); fails the calling test (REQUIRE) if a command fails.
const ReportRuns& reportRuns(const std::string& scratchName);

std::string readText(const std::string& path);
void writeText(const std::string& path, const std::string& text);

}  // namespace sb::test
