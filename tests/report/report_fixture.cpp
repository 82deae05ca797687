#include "tests/report/report_fixture.h"

#include <catch2/catch.hpp>
#include <fstream>
#include <iterator>
#include <memory>

#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace sb::test {

const ReportRuns& reportRuns(const std::string& scratchName) {
  static std::unique_ptr<ReportRuns> runs;
  if (runs) return *runs;
  const std::string tool = SB_SLAMBOOSTER_BIN;
  const std::string dir = scratchDir(scratchName);
  ReportRuns r{dir + "/seq", dir + "/csr4", dir + "/csr8"};
  const auto synth = runCommand(tool + " synth --out " + r.sequence + " --scene office --builtin-frames 20 --no-noise");
  INFO(synth.output);
  REQUIRE(synth.exitCode == 0);
  const auto a = runCommand(tool + " run " + r.sequence + " --out " + r.runA + " --knobs csr=4 --mesh --quiet");
  INFO(a.output);
  REQUIRE(a.exitCode == 0);
  const auto b = runCommand(tool + " run " + r.sequence + " --out " + r.runB + " --knobs csr=8 --quiet");
  INFO(b.output);
  REQUIRE(b.exitCode == 0);
  runs = std::make_unique<ReportRuns>(r);
  return *runs;
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in.good());
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  REQUIRE(out.good());
  out << text;
}

}  // namespace sb::test
