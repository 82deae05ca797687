#include "report/run_summary.h"

#include <cmath>

#include "core/config_reader.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/json_text.h"

namespace sb {

namespace {

using json = nlohmann::json;

// Reads the keys of one object of a summary, checking types; `path` is the object's dotted path.
class Fields {
 public:
  Fields(const json& j, const std::string& where, std::string path = {})
      : j_(j), where_(where), path_(std::move(path)) {
    if (!j_.is_object()) fail("", "an object", j_);
  }
  const json* find(const char* key) const {
    const auto it = j_.find(key);
    return it == j_.end() || it->is_null() ? nullptr : &*it;
  }
  template <typename T>
  void number(const char* key, T& out) const {
    if (const json* v = find(key)) {
      if (!v->is_number()) fail(key, "a number", *v);
      out = v->get<T>();
    }
  }
  template <typename T>
  void count(const char* key, T& out) const {
    if (const json* v = find(key)) {
      if (!v->is_number_integer() || v->get<int64_t>() < 0)
        fail(key, "a count (an integer of at least 0)", *v);
      out = v->get<T>();
    }
  }
  template <typename T>
  void optionalNumber(const char* key, std::optional<T>& out) const {
    if (find(key)) number(key, out.emplace());
  }
  void string(const char* key, std::string& out) const {
    if (const json* v = find(key)) {
      if (!v->is_string()) fail(key, "a string", *v);
      out = v->get<std::string>();
    }
  }
  void boolean(const char* key, bool& out) const {
    if (const json* v = find(key)) {
      if (!v->is_boolean()) fail(key, "true or false", *v);
      out = v->get<bool>();
    }
  }
  void object(const char* key, json& out) const {
    if (const json* v = find(key)) {
      if (!v->is_object()) fail(key, "an object", *v);
      out = *v;
    }
  }
  template <typename T>
  void counts(const char* key, std::map<std::string, T>& out) const {
    if (!find(key)) return;
    const Fields sub = nested(key);
    for (auto it = sub.j_.begin(); it != sub.j_.end(); ++it) {
      if constexpr (std::is_floating_point_v<T>)
        sub.number(it.key().c_str(), out[it.key()]);
      else
        sub.count(it.key().c_str(), out[it.key()]);
    }
  }
  // The nested object `key` (which must be present).
  Fields nested(const char* key) const { return Fields(j_.at(key), where_, dotted(key)); }

  [[noreturn]] void fail(const std::string& key, const char* expected, const json& value) const {
    const std::string name = key.empty() ? path_ : dotted(key);
    throw Error(where_ + ": key \"" + (name.empty() ? "(top level)" : name) + "\" is " + describeJson(value) +
                "; expected " + expected);
  }

 private:
  std::string dotted(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  const json& j_;
  std::string where_, path_;
};

json machineJson(const MachineInfo& m) {
  return {{"host", m.host},
          {"cpu_model", m.cpuModel},
          {"cores_online", m.coresOnline},
          {"threads_used", m.threadsUsed},
          {"backend", m.backend},
          {"device", m.device}};
}

MachineInfo readMachine(const Fields& f) {
  MachineInfo m;
  f.string("host", m.host);
  f.string("cpu_model", m.cpuModel);
  f.count("cores_online", m.coresOnline);
  f.count("threads_used", m.threadsUsed);
  f.string("backend", m.backend);
  f.string("device", m.device);
  return m;
}

json trackingStateJson(const TrackingStateSummary& t) {
  return {{"frames", t.frames},
          {"lost_stretches", t.lostStretches},
          {"longest_lost_frames", t.longestLostFrames},
          {"recoveries", t.recoveries},
          {"mean_frames_to_recover", t.meanFramesToRecover},
          {"longest_frames_to_recover", t.longestFramesToRecover},
          {"lost_at_end", t.lostAtEnd}};
}

TrackingStateSummary readTrackingState(const Fields& f) {
  TrackingStateSummary t;
  f.counts("frames", t.frames);
  f.count("lost_stretches", t.lostStretches);
  f.count("longest_lost_frames", t.longestLostFrames);
  f.count("recoveries", t.recoveries);
  f.number("mean_frames_to_recover", t.meanFramesToRecover);
  f.count("longest_frames_to_recover", t.longestFramesToRecover);
  f.boolean("lost_at_end", t.lostAtEnd);
  return t;
}

AteSummary readAte(const Fields& f) {
  AteSummary a;
  f.number("rmse_m", a.rmseM);
  f.number("mean_m", a.meanM);
  f.number("max_m", a.maxM);
  f.number("median_m", a.medianM);
  f.number("unaligned_mean_m", a.unalignedMeanM);
  f.count("matches", a.matches);
  return a;
}

}  // namespace

double RunSummary::energyNumber(const std::string& key) const {
  if (!energy.is_object()) return NAN;
  const auto it = energy.find(key);
  return it != energy.end() && it->is_number() ? it->get<double>() : NAN;
}

json RunSummary::toJson() const {
  json j = {{"schema_version", schemaVersion},
            {"front_end", frontEnd},
            {"sequence", sequence},
            {"controller", controller},
            {"controller_sections", controllerSections},
            {"knobs", knobs},
            {"config", config},
            {"threads", threads},
            {"frames", frames},
            {"tracking_attempted", trackingAttempted},
            {"tracked", tracked},
            {"tracked_percent", trackedPercent},
            {"integrated", integrated},
            {"corrected", corrected},
            {"half_wish_frames", halfWishFrames},
            {"unconstrained", unconstrained},
            {"retracked", retracked},
            {"half_applied_frames", halfAppliedFrames},
            {"computation_ms_per_frame", computationMsPerFrame},
            {"controller_ms_per_frame", controllerMsPerFrame},
            {"stage_ms_per_frame", json(stageMsPerFrame)},
            {"triggers", json(triggers)},
            {"knob_frames", json(knobFrames)},
            {"controller_frames", json(controllerFrames)},
            {"tracking_state", trackingStateJson(trackingState)}};
  if (machine) j["machine"] = machineJson(*machine);
  if (daemon) j["daemon"] = {{"pass", daemon->pass}, {"cpus", daemon->cpus}, {"threads", daemon->threads}};
  if (ate)
    j["ate"] = {{"rmse_m", ate->rmseM},    {"mean_m", ate->meanM},
                {"max_m", ate->maxM},      {"median_m", ate->medianM},
                {"matches", ate->matches}, {"unaligned_mean_m", ate->unalignedMeanM}};
  if (!ateError.empty()) j["ate_error"] = ateError;
  if (cpuMsPerFrame) j["cpu_ms_per_frame"] = *cpuMsPerFrame;
  if (stopped)
    j["stopped"] = {{"at_frame", stopped->atFrame},
                    {"limit_ms", stopped->limitMs},
                    {"computation_ms", stopped->computationMs}};
  if (interrupted) j["interrupted"] = {{"signal", interrupted->signal}, {"at_frame", interrupted->atFrame}};
  if (!energy.is_null()) j["energy"] = energy;
  if (!modelView.empty()) j["model_view"] = modelView;
  if (!movingVolume.is_null()) j["moving_volume"] = movingVolume;
  if (meshTriangles) j["mesh_triangles"] = *meshTriangles;
  if (meshSlabs) j["mesh_slabs"] = *meshSlabs;
  if (complete) j["complete"] = *complete;
  if (!error.empty()) j["error"] = error;
  return j;
}

RunSummary RunSummary::fromJson(const json& j, const std::string& where) {
  const Fields f(j, where);
  RunSummary s;
  s.schemaVersion = 0;  // a file from before the type has no version
  f.count("schema_version", s.schemaVersion);
  if (s.schemaVersion > kRunSummarySchema)
    throw Error(where + ": schema_version " + std::to_string(s.schemaVersion) + " is newer than this " +
                "slambooster reads (" + std::to_string(kRunSummarySchema) +
                "); use the release that wrote it");
  f.string("front_end", s.frontEnd);
  f.string("sequence", s.sequence);
  f.string("controller", s.controller);
  f.object("controller_sections", s.controllerSections);
  f.object("knobs", s.knobs);
  f.object("config", s.config);
  f.count("threads", s.threads);
  if (f.find("machine")) s.machine = readMachine(f.nested("machine"));
  if (f.find("daemon")) {
    const Fields d = f.nested("daemon");
    DaemonPass& p = s.daemon.emplace();
    d.count("pass", p.pass);
    d.string("cpus", p.cpus);
    d.count("threads", p.threads);
  }
  f.count("frames", s.frames);
  f.count("tracking_attempted", s.trackingAttempted);
  f.count("tracked", s.tracked);
  f.number("tracked_percent", s.trackedPercent);
  f.count("integrated", s.integrated);
  f.count("corrected", s.corrected);
  f.count("half_wish_frames", s.halfWishFrames);
  f.count("unconstrained", s.unconstrained);
  f.count("retracked", s.retracked);
  f.count("half_applied_frames", s.halfAppliedFrames);
  f.number("computation_ms_per_frame", s.computationMsPerFrame);
  f.number("controller_ms_per_frame", s.controllerMsPerFrame);
  f.counts("stage_ms_per_frame", s.stageMsPerFrame);
  f.counts("triggers", s.triggers);
  f.counts("knob_frames", s.knobFrames);
  f.counts("controller_frames", s.controllerFrames);
  if (f.find("tracking_state")) s.trackingState = readTrackingState(f.nested("tracking_state"));
  if (f.find("ate")) s.ate = readAte(f.nested("ate"));
  f.string("ate_error", s.ateError);
  f.optionalNumber("cpu_ms_per_frame", s.cpuMsPerFrame);
  if (f.find("stopped")) {
    const Fields st = f.nested("stopped");
    StoppedSummary& x = s.stopped.emplace();
    st.count("at_frame", x.atFrame);
    st.number("limit_ms", x.limitMs);
    st.number("computation_ms", x.computationMs);
  }
  if (f.find("interrupted")) {
    const Fields in = f.nested("interrupted");
    InterruptedSummary& x = s.interrupted.emplace();
    in.string("signal", x.signal);
    in.count("at_frame", x.atFrame);
  }
  f.object("energy", s.energy);
  f.string("model_view", s.modelView);
  f.object("moving_volume", s.movingVolume);
  if (f.find("mesh_triangles")) f.count("mesh_triangles", s.meshTriangles.emplace());
  if (f.find("mesh_slabs")) f.count("mesh_slabs", s.meshSlabs.emplace());
  if (f.find("complete")) f.boolean("complete", s.complete.emplace());
  f.string("error", s.error);
  return s;
}

bool runSummaryComplete(const std::string& path) {
  try {
    const json j = readJsonConfig(path, "run summary");
    const auto it = j.find("complete");
    return it != j.end() && it->is_boolean() && it->get<bool>();
  } catch (const Error&) {
    return false;
  }
}

RunSummary readRunSummary(const std::string& path) {
  const std::string where = "run summary " + quoteForMessage(path);
  return RunSummary::fromJson(readJsonConfig(path, "run summary"), where);
}

}  // namespace sb
