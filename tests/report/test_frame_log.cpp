// Reading frames.jsonl: columns from good lines; bad, truncated and empty logs give problems naming the file
// and line, and the frames that could be read.

#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>

#include "report/frame_log.h"
#include "tests/support/test_data.h"

using sb::report::readFrameLog;

namespace {

std::string writeFile(const std::string& name, const std::string& content) {
  const std::string path = sb::test::scratchDir("report_frame_log_" + name) + "/frames.jsonl";
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

std::string line(int frame, const std::string& extra = "") {
  return "{\"frame\":" + std::to_string(frame) + ",\"timestamp\":" + std::to_string(frame * 0.1) +
         ",\"knobs\":{\"csr\":2,\"icp\":1e-05,\"pd\":[8,5,4]},\"ms\":{\"track\":2.5,\"integrate\":4}," +
         "\"computation_ms\":6.5,\"tracking_attempted\":true,\"tracked\":" + (frame == 1 ? "false" : "true") +
         ",\"velocity_m_per_frame\":0.01" + extra + "}\n";
}

}  // namespace

TEST_CASE("a complete log becomes columns, with triggers and corrections per frame", "[report]") {
  const auto path = writeFile("good", line(0, ",\"triggers\":[\"bootstrap\"],\"corrected\":false") +
                                          line(1, ",\"triggers\":[\"surface\",\"correction\"],\"corrected\":true") +
                                          line(2, ",\"triggers\":[],\"joules\":null,\"level\":2"));
  const auto r = readFrameLog(path);
  CHECK(r.problems.empty());
  const auto& f = r.log;
  REQUIRE(f.size() == 3);
  CHECK(f.frame == std::vector<double>{0, 1, 2});
  CHECK(f.csr[2] == 2);
  CHECK(f.icp[0] == 1e-5);
  CHECK(f.pd0[1] == 8);
  CHECK(f.tracked == std::vector<double>{1, 0, 1});
  REQUIRE(f.stageNames.size() == 2);
  CHECK(f.stageMs[0][1] + f.stageMs[1][1] == 6.5);
  CHECK(f.recordsTriggers);
  CHECK(f.triggerFrames("surface") == std::vector<double>{1});
  CHECK(f.triggerFrames("correction") == std::vector<double>{1});  // from both the list and "corrected"
  CHECK(f.triggerFrames("bootstrap") == std::vector<double>{0});
  CHECK(f.triggerFrames("hold").empty());
  CHECK_FALSE(f.hasColumn(f.joules));
  CHECK(std::isnan(f.level[0]));
  CHECK(f.level[2] == 2);
}

TEST_CASE("a truncated last line is reported with its line number; the frames before it are kept", "[report]") {
  const std::string partial = line(2).substr(0, 40);  // no newline: the writer was interrupted
  const auto path = writeFile("truncated", line(0) + line(1) + partial);
  const auto r = readFrameLog(path);
  CHECK(r.log.size() == 2);
  REQUIRE(r.problems.size() == 1);
  CHECK_THAT(r.problems[0], Catch::Contains(path + " line 3 is incomplete") && Catch::Contains("2 frames"));
}

TEST_CASE("a bad line in the middle is skipped and named; wrong types are named by key", "[report]") {
  const auto path = writeFile("bad", line(0) + "{not json}\n" + "[1,2]\n" +
                                         line(3).replace(line(3).find("\"csr\":2"), 7, "\"csr\":\"two\""));
  const auto r = readFrameLog(path);
  CHECK(r.log.size() == 2);
  REQUIRE(r.problems.size() == 3);
  CHECK_THAT(r.problems[0], Catch::Contains("line 2 is not valid JSON"));
  CHECK_THAT(r.problems[1], Catch::Contains("line 3 is not a JSON object"));
  CHECK_THAT(r.problems[2], Catch::Contains("line 4: 'knobs.csr' should be a number, found string"));
  CHECK(std::isnan(r.log.csr[1]));
}

TEST_CASE("empty and missing logs are problems, many bad lines are capped", "[report]") {
  const auto empty = readFrameLog(writeFile("empty", "\n\n"));
  CHECK(empty.log.size() == 0);
  REQUIRE(empty.problems.size() == 1);
  CHECK_THAT(empty.problems[0], Catch::Contains("is empty"));

  const auto missing = readFrameLog(sb::test::scratchDir("report_frame_log_missing") + "/frames.jsonl");
  REQUIRE(missing.problems.size() == 1);
  CHECK_THAT(missing.problems[0], Catch::Contains("cannot read") && Catch::Contains("frames.jsonl"));

  std::string garbage;
  for (int i = 0; i < 20; ++i) garbage += "garbage\n";
  const auto many = readFrameLog(writeFile("many", garbage));
  REQUIRE(many.problems.size() == 9);
  CHECK(many.problems.back() == "... and 12 more problems");
}

TEST_CASE("a long log is read in bounded memory: the newest frames, and the report says so", "[report]") {
  // Frames 0..9; every frame from 5 on fires "doubt". Kept at most 3 (trimmed whenever 6 are held).
  std::string content;
  for (int i = 0; i < 10; ++i) content += line(i, i >= 5 ? ",\"triggers\":[\"doubt\"]" : ",\"triggers\":[\"bootstrap\"]");
  const auto r = readFrameLog(writeFile("long", content), 3);
  const auto& f = r.log;
  REQUIRE(f.size() == 3);
  CHECK(f.frame == std::vector<double>{7, 8, 9});
  CHECK(f.timestamp.size() == 3);
  CHECK(f.stageMs.size() == 2);
  CHECK(f.stageMs[0].size() == 3);
  CHECK(f.triggerFrames("doubt") == std::vector<double>{7, 8, 9});
  CHECK(f.triggerFrames("bootstrap").empty());
  REQUIRE(r.problems.size() == 1);
  CHECK_THAT(r.problems[0], Catch::Contains("holds 10 frames") && Catch::Contains("newest 3"));
  // 0: the whole log.
  CHECK(readFrameLog(writeFile("long_all", content), 0).log.size() == 10);
}
