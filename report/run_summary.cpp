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
  template <typename T, size_t N>
  void numbers(const char* key, std::array<T, N>& out) const {
    if (const json* v = find(key)) {
      const std::string expected = "an array of " + std::to_string(N) + " numbers";
      if (!v->is_array() || v->size() != N) fail(key, expected.c_str(), *v);
      for (size_t i = 0; i < N; ++i) {
        if (!(*v)[i].is_number()) fail(key, expected.c_str(), *v);
        out[i] = (*v)[i].get<T>();
      }
    }
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

// Each section's keys and members, listed once: `field(key, member)` per key. Written by Writer, read by Reader
// (which checks each value's type by the member's: string, bool, floating point number, count, map of counts).
template <typename Field>
void fieldsOf(MachineInfo& m, Field field) {
  field("host", m.host);
  field("cpu_model", m.cpuModel);
  field("cores_online", m.coresOnline);
  field("threads_used", m.threadsUsed);
  field("backend", m.backend);
  field("device", m.device);
}

template <typename Field>
void fieldsOf(DaemonPass& d, Field field) {
  field("pass", d.pass);
  field("cpus", d.cpus);
  field("threads", d.threads);
}

template <typename Field>
void fieldsOf(TrackingStateSummary& t, Field field) {
  field("frames", t.frames);
  field("lost_stretches", t.lostStretches);
  field("longest_lost_frames", t.longestLostFrames);
  field("recoveries", t.recoveries);
  field("mean_frames_to_recover", t.meanFramesToRecover);
  field("longest_frames_to_recover", t.longestFramesToRecover);
  field("lost_at_end", t.lostAtEnd);
}

template <typename Field>
void fieldsOf(AteSummary& a, Field field) {
  field("rmse_m", a.rmseM);
  field("mean_m", a.meanM);
  field("max_m", a.maxM);
  field("median_m", a.medianM);
  field("matches", a.matches);
  field("unaligned_mean_m", a.unalignedMeanM);
}

template <typename Field>
void fieldsOf(OdometrySummary& o, Field field) {
  field("source", o.source);
  field("samples", o.samples);
  field("frames_with_pose", o.framesWithPose);
  field("path_m", o.pathM);
  field("scale_error", o.scaleError);
  field("yaw_scale_error", o.yawScaleError);
  field("yaw_bias_deg_per_s", o.yawBiasDegPerS);
  field("calibration_frames", o.calibrationFrames);
  field("mount_error_deg", o.mountErrorDeg);
  field("mount_learnt_from", o.mountLearntFrom);
  field("mount_turn_seen_deg", o.mountTurnSeenDeg);
  field("mount_floor_frames", o.mountFloorFrames);
  field("time_offset_s", o.timeOffsetS);
  field("time_offset_learnt", o.timeOffsetLearnt);
  field("calibration_from", o.calibrationFrom);
  field("start_scale_error", o.startScaleError);
  field("start_yaw_scale_error", o.startYawScaleError);
  field("start_yaw_bias_deg_per_s", o.startYawBiasDegPerS);
  field("start_calibration_frames", o.startCalibrationFrames);
  field("start_mount_error_deg", o.startMountErrorDeg);
  field("start_time_offset_s", o.startTimeOffsetS);
  field("start_mount_change_deg", o.startMountChangeDeg);
  field("start_mount_refused", o.startMountRefused);
}

template <typename Field>
void fieldsOf(EnergySummary& e, Field field) {
  field("meter", e.meter);
  field("device", e.device);
  field("frames", e.frames);
  field("known_frames", e.knownFrames);
  field("unknown_frames", e.unknownFrames);
  field("joules", e.joules);
  field("joules_per_frame", e.joulesPerFrame);
  field("mean_watts", e.meanWatts);
  field("seconds", e.seconds);
  field("idle_watts", e.idleWatts);
  field("joules_above_idle", e.joulesAboveIdle);
  field("span_seconds", e.spanSeconds);
  field("span_known_seconds", e.spanKnownSeconds);
  field("span_joules", e.spanJoules);
  field("span_mean_watts", e.spanMeanWatts);
  field("unknown_reasons", e.unknownReasons);
}

template <typename Field>
void fieldsOf(Knobs& k, Field field) {
  forEachKnobField(k, field);
}

template <typename Field>
void fieldsOf(MovingVolumeSummary& m, Field field) {
  field("shifts", m.shifts);
  field("shift_ms", m.shiftMs);
  field("slab_ms", m.slabMs);
  field("corner_m", m.cornerM);
  field("slab_worker_ms", m.slabWorkerMs);
  field("slab_wait_ms", m.slabWaitMs);
  field("slab_queue_peak_mib", m.slabQueuePeakMib);
  field("slab_files_removed", m.slabFilesRemoved);
}

template <typename Field>
void fieldsOf(StoppedSummary& x, Field field) {
  field("at_frame", x.atFrame);
  field("limit_ms", x.limitMs);
  field("computation_ms", x.computationMs);
}

template <typename Field>
void fieldsOf(InterruptedSummary& x, Field field) {
  field("signal", x.signal);
  field("at_frame", x.atFrame);
}

template <typename T>
struct IsOptional : std::false_type {};
template <typename T>
struct IsOptional<std::optional<T>> : std::true_type {};
template <typename T>
struct IsArray : std::false_type {};
template <typename T, size_t N>
struct IsArray<std::array<T, N>> : std::true_type {};

struct Writer {
  json& j;
  template <typename T>
  void operator()(const char* key, const T& value) const {
    if constexpr (IsOptional<T>::value) {
      if (value) (*this)(key, *value);  // absent: no key
    } else if constexpr (std::is_floating_point_v<T>) {
      j[key] = std::isnan(value) ? json(nullptr) : json(value);  // unknown: null
    } else {
      j[key] = value;
    }
  }
};

struct Reader {
  Fields f;
  template <typename T>
  void operator()(const char* key, T& out) const {
    if constexpr (IsOptional<T>::value) {
      if (f.find(key)) (*this)(key, out.emplace());
    } else if constexpr (IsArray<T>::value) {
      f.numbers(key, out);
    } else if constexpr (std::is_same_v<T, std::string>)
      f.string(key, out);
    else if constexpr (std::is_same_v<T, bool>)
      f.boolean(key, out);
    else if constexpr (std::is_floating_point_v<T>)
      f.number(key, out);
    else if constexpr (std::is_integral_v<T>)
      f.count(key, out);
    else
      f.counts(key, out);
  }
};

template <typename Section>
json sectionJson(const Section& section) {
  json j = json::object();
  fieldsOf(const_cast<Section&>(section), Writer{j});  // the writer only reads the members
  return j;
}

// Reads the nested object `key` into `out` when present.
template <typename Section>
void readSection(const Fields& f, const char* key, std::optional<Section>& out) {
  if (f.find(key)) fieldsOf(out.emplace(), Reader{f.nested(key)});
}

}  // namespace

double RunSummary::constrainedMinConditioning() const {
  if (!config.is_object()) return NAN;
  const auto it = config.find("constrained_min_conditioning");
  return it != config.end() && it->is_number() ? it->get<double>() : NAN;
}

json RunSummary::toJson() const {
  json j = {{"schema_version", schemaVersion},
            {"front_end", frontEnd},
            {"sequence", sequence},
            {"controller", controller},
            {"controller_sections", controllerSections},
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
            {"work", json(work)},
            {"triggers", json(triggers)},
            {"knob_frames", json(knobFrames)},
            {"controller_frames", json(controllerFrames)},
            {"tracking_state", sectionJson(trackingState)}};
  if (knobs) j["knobs"] = sectionJson(*knobs);
  if (machine) j["machine"] = sectionJson(*machine);
  if (daemon) j["daemon"] = sectionJson(*daemon);
  if (odometry) j["odometry"] = sectionJson(*odometry);
  if (ate) j["ate"] = sectionJson(*ate);
  if (!ateError.empty()) j["ate_error"] = ateError;
  if (cpuMsPerFrame) j["cpu_ms_per_frame"] = *cpuMsPerFrame;
  if (stopped) j["stopped"] = sectionJson(*stopped);
  if (interrupted) j["interrupted"] = sectionJson(*interrupted);
  if (energy) j["energy"] = sectionJson(*energy);
  if (!modelView.empty()) j["model_view"] = modelView;
  if (movingVolume) j["moving_volume"] = sectionJson(*movingVolume);
  if (!navmap.is_null()) j["navmap"] = navmap;
  if (!mapStore.is_null()) j["map_store"] = mapStore;
  if (meshTriangles) j["mesh_triangles"] = *meshTriangles;
  if (meshSlabs) j["mesh_slabs"] = *meshSlabs;
  if (complete) j["complete"] = *complete;
  if (!error.empty()) j["error"] = error;
  if (!errorFile.empty()) j["error_file"] = errorFile;
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
  readSection(f, "knobs", s.knobs);
  f.object("config", s.config);
  if (f.find("config")) {  // the one key code reads (constrainedMinConditioning): a number or absent
    double conditioning = NAN;
    f.nested("config").number("constrained_min_conditioning", conditioning);
  }
  f.count("threads", s.threads);
  readSection(f, "machine", s.machine);
  readSection(f, "daemon", s.daemon);
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
  f.counts("work", s.work);
  f.counts("triggers", s.triggers);
  f.counts("knob_frames", s.knobFrames);
  f.counts("controller_frames", s.controllerFrames);
  if (f.find("tracking_state")) fieldsOf(s.trackingState, Reader{f.nested("tracking_state")});
  readSection(f, "odometry", s.odometry);
  readSection(f, "ate", s.ate);
  f.string("ate_error", s.ateError);
  f.optionalNumber("cpu_ms_per_frame", s.cpuMsPerFrame);
  readSection(f, "stopped", s.stopped);
  readSection(f, "interrupted", s.interrupted);
  readSection(f, "energy", s.energy);
  f.string("model_view", s.modelView);
  readSection(f, "moving_volume", s.movingVolume);
  f.object("navmap", s.navmap);
  f.object("map_store", s.mapStore);
  if (f.find("mesh_triangles")) f.count("mesh_triangles", s.meshTriangles.emplace());
  if (f.find("mesh_slabs")) f.count("mesh_slabs", s.meshSlabs.emplace());
  if (f.find("complete")) f.boolean("complete", s.complete.emplace());
  f.string("error", s.error);
  f.string("error_file", s.errorFile);
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

RunSummary readRunDirSummary(const std::string& run, const std::string& hint) {
  const bool file = run.size() > 5 && run.compare(run.size() - 5, 5, ".json") == 0;
  const std::string path = file ? run : run + "/summary.json";
  const std::string problem = pathProblem(path);
  if (!problem.empty())
    throw Error("run summary " + quoteForMessage(path) + " " + problem + (hint.empty() ? "" : ": " + hint));
  return readRunSummary(path);
}

}  // namespace sb
