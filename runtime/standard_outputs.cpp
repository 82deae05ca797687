#include "runtime/standard_outputs.h"

#include <filesystem>

#include "core/error.h"

namespace sb {

StandardOutputs addStandardOutputs(SlamRunner& runner, const std::string& dir, const std::string& groundTruthPath,
                                   const nlohmann::json& extra, const std::string& comment) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw Error("cannot create output directory '" + dir + "': " + ec.message());
  const fs::path out(dir);
  StandardOutputs o;
  o.trajectory = static_cast<TrajectorySink*>(
      &runner.addSink(std::make_unique<TrajectorySink>((out / "trajectory.tum").string(), comment)));
  o.frameLog = static_cast<FrameLogSink*>(&runner.addSink(std::make_unique<FrameLogSink>((out / "frames.jsonl").string())));
  o.summary = static_cast<SummarySink*>(
      &runner.addSink(std::make_unique<SummarySink>((out / "summary.json").string(), groundTruthPath, extra)));
  return o;
}

}  // namespace sb
