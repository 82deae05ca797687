// slamboosterd: the SLAMBooster daemon (architecture.md D6 and D7). Exit codes: 0 clean stop, 1 runtime
// failure, 2 bad configuration or usage.

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <iostream>
#include <nlohmann/json.hpp>

#include "core/config_reader.h"
#include "core/error.h"
#include "core/input_file.h"
#include "daemon/daemon.h"
#include "daemon/daemon_config.h"

namespace {

struct Options {
  std::string configPath;
  std::vector<std::string> overrides;  // in command-line order, after the named flags below
  std::string input, out, socket, pacing, atEnd, controller, cpus;
  bool checkOnly = false;
  bool printConfig = false;
};

sb::daemon::DaemonConfig loadConfig(const Options& o) {
  nlohmann::json j = nlohmann::json::object();
  try {  // the one JSON file loader; a missing file, bad JSON or a non-object is a configuration error (exit 2)
    if (!o.configPath.empty()) j = sb::readJsonConfig(o.configPath, "config file");
  } catch (const sb::Error& e) {
    throw sb::daemon::ConfigError(e.what());
  }
  const std::pair<const char*, const std::string*> flags[] = {
      {"source.path", &o.input},    {"output.dir", &o.out},      {"socket.path", &o.socket},
      {"source.pacing", &o.pacing}, {"source.at_end", &o.atEnd}, {"slam.controller", &o.controller},
      {"slam.cpus", &o.cpus}};
  for (const auto& [key, value] : flags)
    if (!value->empty()) sb::daemon::applyOverride(j, std::string(key) + "=" + nlohmann::json(*value).dump());
  for (const auto& assignment : o.overrides) sb::daemon::applyOverride(j, assignment);
  return sb::daemon::parseDaemonConfig(j, o.configPath.empty() ? "command line" : o.configPath);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "slamboosterd: KinectFusion with an online approximation controller, as a service.\n"
      "Publishes pose, knobs and energy on a Unix socket (see docs/protocol.md; client: slamboosterctl)."};
  Options o;
  app.set_version_flag("--version", std::string(SB_VERSION));
  app.add_option("--config", o.configPath, "Daemon config (JSON; keys in config/README.md)");
  app.add_option("--input", o.input, "Sequence to replay (source.path)");
  app.add_option("--out", o.out, "Output directory (output.dir)");
  app.add_option("--socket", o.socket, "Socket path (socket.path)");
  app.add_option("--pacing", o.pacing, "recorded or fast (source.pacing)");
  app.add_option("--at-end", o.atEnd, "stop, loop or exit (source.at_end)");
  app.add_option("--controller", o.controller, "Controller name (slam.controller)");
  app.add_option("--cpus", o.cpus, "CPUs of the SLAM thread: auto, all or a list like 4-7 (slam.cpus)");
  app.add_option("--set", o.overrides, "Any config key: section.key=value, e.g. --set socket.max_clients=16");
  app.add_flag("--check-config", o.checkOnly, "Validate the configuration and the settings files it names, then exit (0 valid, 2 invalid)");
  app.add_flag("--print-config", o.printConfig, "Print the effective configuration as JSON and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }

  sb::daemon::DaemonConfig config;
  try {
    config = loadConfig(o);
  } catch (const std::exception& e) {
    std::cerr << "slamboosterd: configuration error: " << sb::printable(e.what()) << "\n";
    return 2;
  }
  if (o.printConfig) {
    std::cout << sb::daemon::daemonConfigToJson(config).dump(2) << "\n";
    return 0;
  }
  if (o.checkOnly) {
    try {
      sb::daemon::checkConfigFiles(config);
    } catch (const std::exception& e) {  // sb::Error, or a library's exception on an unreadable file
      std::cerr << "slamboosterd: configuration error: " << sb::printable(e.what()) << "\n";
      return 2;
    }
    std::cout << "configuration is valid (the files it names too; the input and devices are not opened)\n";
    return 0;
  }
  spdlog::set_default_logger(spdlog::stderr_color_mt("slamboosterd"));
  spdlog::set_level(spdlog::level::from_str(config.logLevel));

  try {
    sb::daemon::Daemon daemon(
        config, [o] { return loadConfig(o); }, SB_VERSION);
    return daemon.run();
  } catch (const sb::daemon::ConfigError& e) {
    std::cerr << "slamboosterd: configuration error: " << sb::printable(e.what()) << "\n";
    return 2;
  } catch (const sb::Error& e) {
    std::cerr << "slamboosterd: error: " << sb::printable(e.what()) << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "slamboosterd: internal error: " << sb::printable(e.what()) << "\n";
    return 1;
  }
}
