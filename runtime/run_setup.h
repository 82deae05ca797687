#pragma once
// The setup of one run, shared by both front ends (`slambooster run` and every pass of slamboosterd;
// issue 32): the pipeline config from the sequence's hints and a settings file, the controller settings from
// a section of that file or the controller file, and the first fields of summary.json. What differs between
// the front ends is only where the names and files come from (command-line flags, the daemon's config).
//
//   SettingsFile file = readSettingsFile(path);                    // pipeline keys + "controller" section
//   PipelineConfig c = pipelineConfigFor(info, file.pipeline, path);  // hints < file
//   ... command-line overrides ...;  finishPipelineConfig(c, "run options");
//   ControllerSettings s = controllerSettingsFrom(file.controller, name, nameWins, {c.knobs}, where);
//   RunSummary header = runSummaryHeader("run", sequence, s, *controller, *pipeline, threads);

#include <nlohmann/json.hpp>
#include <string>

#include "controller/registry.h"
#include "drivers/frame_source.h"
#include "odometry/odometry_config.h"
#include "pipeline/config.h"
#include "pipeline/pipeline.h"
#include "report/run_summary.h"

namespace sb {

// A settings file: one JSON object whose "controller" key, when present, is the controller section (a name
// or a settings object, config/controller.json), whose "odometry" key is the platform's physics and the
// odometry's noise (odometry/odometry_config.h), and whose other keys are pipeline keys (config/pipeline.json).
struct SettingsFile {
  nlohmann::json pipeline = nlohmann::json::object();  // every key but "controller" and "odometry"
  nlohmann::json controller;                           // the "controller" value; null when absent
  nlohmann::json odometry;  // the "odometry" value (odometry/odometry_config.h); null when absent
};
// Reads `path` with readJsonConfig (the one JSON file loader). Throws sb::Error naming the file.
SettingsFile readSettingsFile(const std::string& path);

// defaults < the sequence's volume hints (side, first camera position) < `pipelineKeys` (from `where`).
PipelineConfig pipelineConfigFor(const SequenceInfo& sequence, const nlohmann::json& pipelineKeys,
                                 const std::string& where);
// After every layer: volume_mode "automatic" becomes "moving" (docs/moving-volume.md) and the config is
// validated. Throws sb::Error "<where>: ...".
void finishPipelineConfig(PipelineConfig& config, const std::string& where);

// The controller settings of `section` (null, a name, or a settings object read from `where`). `name` (""
// = none) is the front end's choice: with `nameWins` it replaces the section's own "name" (`run
// --controller`), otherwise it applies only when the section names none (the daemon's slam.controller beside
// its controller file). No name anywhere: "fixed". Validated; throws sb::Error naming `where` and the key.
ControllerSettings controllerSettingsFrom(nlohmann::json section, const std::string& name, bool nameWins,
                                          const ControllerContext& context, const std::string& where);

// The first fields of summary.json, the same for both front ends: the front end ("run", "daemon"), the
// sequence, the controller, its sections and initial knobs, the pipeline config (its "odometry" key the
// odometry's), the worker threads and the
// machine the run is timed on (the CPU backend names this CPU; OpenCL the config's device selectors).
RunSummary runSummaryHeader(const std::string& frontEnd, const std::string& sequence,
                            const ControllerSettings& settings, const Controller& controller,
                            Pipeline& pipeline, const odometry::OdometryConfig& odometry, unsigned threads);

}  // namespace sb
