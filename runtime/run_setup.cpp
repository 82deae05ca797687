#include "runtime/run_setup.h"

#include "core/config_reader.h"
#include "core/error.h"
#include "pipeline/cpu/cpu_backend.h"
#include "runtime/frame_log_sink.h"
#include "runtime/summary_sink.h"

namespace sb {

SettingsFile readSettingsFile(const std::string& path) {
  SettingsFile file;
  file.pipeline = readJsonConfig(path, "config file");
  if (file.pipeline.contains("controller")) {
    file.controller = file.pipeline["controller"];
    file.pipeline.erase("controller");
  }
  if (file.pipeline.contains("odometry")) {
    file.odometry = file.pipeline["odometry"];
    file.pipeline.erase("odometry");
  }
  return file;
}

PipelineConfig pipelineConfigFor(const SequenceInfo& info, const nlohmann::json& pipelineKeys,
                                 const std::string& where) {
  PipelineConfig c;
  if (info.volumeSize) c.volumeSize = static_cast<float>(*info.volumeSize);
  if (info.volumeInitialPosition)
    for (int i = 0; i < 3; ++i) c.initialPosition[i] = static_cast<float>((*info.volumeInitialPosition)[i]);
  const bool keys = !pipelineKeys.is_null() && !pipelineKeys.empty();
  c.volumeHinted.size = info.volumeSize && !(keys && pipelineKeys.contains("volume_size_m"));
  if (keys) c = parseConfig(pipelineKeys, c, where);
  return c;
}

void finishPipelineConfig(PipelineConfig& c, const std::string& where) {
  if (c.volumeMode == VolumeMode::automatic) c.volumeMode = VolumeMode::moving;
  // A sequence's hints size a fixed volume to hold the whole path; a moving volume that took them would spread
  // its voxels over it (a corridor drive's 20.5 m cube: 8 cm voxels at 256^3, against the sensor's centimetres),
  // and tracking against so coarse a model drifts (docs/moving-volume.md "The sequence's hints").
  if (c.movesVolume() && c.volumeHinted.size) c.volumeSize = PipelineConfig{}.volumeSize;
  c.volumeHinted = {};
  try {
    validateConfig(c);
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
}

ControllerSettings controllerSettingsFrom(nlohmann::json section, const std::string& name, bool nameWins,
                                          const ControllerContext& context, const std::string& where) {
  if (section.is_null()) section = name.empty() ? "fixed" : name;
  if (!name.empty()) {
    if (section.is_object() && (nameWins || !section.contains("name")))
      section["name"] = name;
    else if (section.is_string() && nameWins)
      section = name;
  }
  return parseControllerSettings(section, context, where);
}

RunSummary runSummaryHeader(const std::string& frontEnd, const std::string& sequence,
                            const ControllerSettings& settings, const Controller& controller,
                            Pipeline& pipeline, const odometry::OdometryConfig& odometry, unsigned threads) {
  const PipelineConfig& config = pipeline.config();
  RunSummary s;
  s.frontEnd = frontEnd;
  s.sequence = sequence;
  s.controller = settings.name;
  s.controllerSections = settings.sections;
  s.knobs = controller.initialKnobs();
  s.config = configToJson(config);
  s.config["odometry"] = odometry.toJson();
  s.threads = threads;
  if (dynamic_cast<CpuBackend*>(&pipeline.backend())) {
    s.machine = thisMachine(threads, "cpu", cpuModel());
  } else {
    const std::string platform = config.openclPlatform.empty() ? "first with a GPU" : config.openclPlatform;
    const std::string device = config.openclDevice.empty() ? "first GPU" : config.openclDevice;
    s.machine = thisMachine(threads, "opencl", "platform " + platform + ", device " + device);
  }
  return s;
}

}  // namespace sb
