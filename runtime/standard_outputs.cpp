#include "runtime/standard_outputs.h"

#include <filesystem>

#include "core/error.h"

namespace sb {

StandardOutputs addStandardOutputs(SlamRunner& runner, const std::string& dir,
                                   const std::string& groundTruthPath, const RunSummary& header,
                                   const std::string& comment, std::shared_ptr<SegmentStore> segments) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw Error("cannot create output directory '" + dir + "': " + ec.message());
  const fs::path out(dir);
  StandardOutputs o;
  o.trajectory =
      static_cast<TrajectorySink*>(&runner.addSink(std::make_unique<TrajectorySink>(dir, comment, segments)));
  o.frameLog = static_cast<FrameLogSink*>(&runner.addSink(std::make_unique<FrameLogSink>(dir, segments)));
  o.summary = static_cast<SummarySink*>(&runner.addSink(
      std::make_unique<SummarySink>((out / "summary.json").string(), groundTruthPath, header, segments)));
  o.summary->setTrajectorySource([trajectory = o.trajectory] { return trajectory->readBack(); });
  return o;
}

}  // namespace sb
