#include "report/frame_log.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/frame_log_fields.h"
#include "core/input_file.h"
#include "core/pose_fields.h"
#include "core/tracking_state.h"
#include "pipeline/knob_fields.h"

namespace sb::report {

namespace {

using nlohmann::json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr size_t kMaxProblems = 8;

class ProblemList {
 public:
  explicit ProblemList(std::vector<std::string>& out) : out_(out) {}
  void add(const std::string& p) {
    if (count_++ < kMaxProblems) out_.push_back(p);
  }
  // Appends the count of problems left out; call once at the end.
  void finish() {
    if (count_ > kMaxProblems) out_.push_back("... and " + std::to_string(count_ - kMaxProblems) + " more problems");
  }

 private:
  std::vector<std::string>& out_;
  size_t count_ = 0;
};

const json* find(const json& j, std::initializer_list<const char*> path) {
  const json* node = &j;
  for (const char* key : path) {
    if (!node->is_object()) return nullptr;
    auto it = node->find(key);
    if (it == node->end()) return nullptr;
    node = &*it;
  }
  return node;
}

const char* typeName(const json& j) { return j.type_name(); }

// A pose field's frames.jsonl key, by the pose record's table (core/pose_fields.h), the one frames.jsonl is
// written from.
template <typename M>
const char* logKey(M PoseFields::*member) {
  return poseField(member).logName;
}

// A knob record field's frames.jsonl key, by the knob record's table (pipeline/knob_fields.h).
template <typename M>
const char* logKey(M KnobFields::*member) {
  return knobRecordField(member).logName;
}

// A tracking or controller field's frames.jsonl key, by core/frame_log_fields.h's table.
template <typename M>
const char* logKey(M FrameLogFields::*member) {
  return frameLogField(member).logName;
}

// Numeric value at `path`; NaN when absent or null; a problem when present with another type.
double number(const json& j, std::initializer_list<const char*> path, const std::string& where, ProblemList& problems) {
  const json* v = find(j, path);
  if (!v || v->is_null()) return kNaN;
  if (v->is_boolean()) return v->get<bool>() ? 1.0 : 0.0;
  if (v->is_number()) return v->get<double>();
  std::string key;
  for (const char* p : path) key += (key.empty() ? "" : ".") + std::string(p);
  problems.add(where + ": '" + key + "' should be a number, found " + typeName(*v));
  return kNaN;
}

void addTrigger(FrameLog& log, const std::string& name, double frame) {
  for (auto& t : log.triggers)
    if (t.name == name) {
      if (t.frames.empty() || t.frames.back() != frame) t.frames.push_back(frame);
      return;
    }
  log.triggers.push_back({name, {frame}});
}

void addPose(FrameLog& log, const json& j) {
  std::array<double, 7> pose;
  pose.fill(kNaN);
  const json* p = find(j, {logKey(&PoseFields::position)});
  const json* q = find(j, {logKey(&PoseFields::quaternion)});
  if (p && q && p->is_array() && q->is_array() && p->size() == 3 && q->size() == 4) {
    for (size_t i = 0; i < 7; ++i) {
      const json& v = i < 3 ? (*p)[i] : (*q)[i - 3];
      if (v.is_number()) pose[i] = v.get<double>();
    }
  }
  log.pose.push_back(pose);
}

// Every field of "odometry": booleans and numbers into columns, strings into text columns, each found by
// name (a new field gets its column at the frame it first appears, earlier frames NaN or "").
void addOdometry(FrameLog& log, const json& j, size_t index, const std::string& where, ProblemList& problems) {
  for (auto& c : log.odometry) c.values.push_back(kNaN);
  for (auto& c : log.odometryText) c.values.emplace_back();
  const char* const odometry = poseField(&PoseFields::odometry).logObject;
  const json* o = find(j, {odometry});
  if (!o) return;
  if (!o->is_object()) {
    problems.add(where + ": '" + odometry + "' should be an object, found " + typeName(*o));
    return;
  }
  log.recordsOdometry = true;
  for (auto it = o->begin(); it != o->end(); ++it) {
    const json& v = *it;
    if (v.is_boolean() || v.is_number()) {
      auto c = std::find_if(log.odometry.begin(), log.odometry.end(), [&](const auto& x) { return x.name == it.key(); });
      if (c == log.odometry.end()) {
        log.odometry.push_back({it.key(), true, std::vector<double>(index + 1, kNaN)});
        c = log.odometry.end() - 1;
      }
      c->boolean &= v.is_boolean();
      c->values[index] = v.is_boolean() ? (v.get<bool>() ? 1.0 : 0.0) : v.get<double>();
    } else if (v.is_string()) {
      auto c = std::find_if(log.odometryText.begin(), log.odometryText.end(),
                            [&](const auto& x) { return x.name == it.key(); });
      if (c == log.odometryText.end()) {
        log.odometryText.push_back({it.key(), std::vector<std::string>(index + 1)});
        c = log.odometryText.end() - 1;
      }
      c->values[index] = v.get<std::string>();
    }  // null, lists and objects: nothing to plot per frame
  }
}

void addFrame(FrameLog& log, const json& j, const std::string& where, ProblemList& problems) {
  const size_t index = log.size();
  double frame = number(j, {logKey(&PoseFields::frame)}, where, problems);
  log.frame.push_back(std::isfinite(frame) ? frame : static_cast<double>(index));
  log.timestamp.push_back(number(j, {logKey(&PoseFields::timestamp)}, where, problems));
  const char* const knobs = logKey(&KnobFields::knobs);
  log.csr.push_back(number(j, {knobs, knobKey(&Knobs::csr).name}, where, problems));
  log.icp.push_back(number(j, {knobs, knobKey(&Knobs::icpThreshold).name}, where, problems));
  const json* pd = find(j, {knobs, kIterationsKnob});
  log.pd0.push_back(pd && pd->is_array() && !pd->empty() && (*pd)[0].is_number() ? (*pd)[0].get<double>() : kNaN);
  log.computationMs.push_back(number(j, {logKey(&KnobFields::computationMs)}, where, problems));
  log.tracked.push_back(number(j, {logKey(&PoseFields::tracked)}, where, problems));
  log.trackingAttempted.push_back(number(j, {logKey(&FrameLogFields::trackingAttempted)}, where, problems));
  log.velocity.push_back(number(j, {logKey(&PoseFields::velocityMPerFrame)}, where, problems));
  double joules = number(j, {"joules"}, where, problems);
  if (!std::isfinite(joules)) joules = number(j, {"energy_j"}, where, problems);
  log.joules.push_back(joules);
  log.powerW.push_back(number(j, {"power_w"}, where, problems));

  for (auto& column : log.stageMs) column.push_back(kNaN);
  if (const json* ms = find(j, {"ms"}); ms && ms->is_object()) {
    for (auto it = ms->begin(); it != ms->end(); ++it) {
      size_t s = 0;
      while (s < log.stageNames.size() && log.stageNames[s] != it.key()) ++s;
      if (s == log.stageNames.size()) {
        log.stageNames.push_back(it.key());
        log.stageMs.emplace_back(index + 1, kNaN);
      }
      if (it->is_number()) log.stageMs[s][index] = it->get<double>();
    }
  }

  log.level.push_back(number(j, {logKey(&FrameLogFields::level)}, where, problems));
  log.conditioning.push_back(number(j, {logKey(&PoseFields::conditioning)}, where, problems));
  log.constrained.push_back(number(j, {logKey(&PoseFields::constrained)}, where, problems));
  log.state.push_back(kNaN);
  if (const json* state = find(j, {logKey(&PoseFields::state)})) {
    if (state->is_string())
      if (const auto s = trackingStateFromName(state->get<std::string>())) log.state.back() = static_cast<double>(*s);
    if (!std::isfinite(log.state.back()))
      problems.add(where + ": 'state' should be good, weak, lost, relocalised or odometry, found " + state->dump());
  }
  const char* const triggersKey = logKey(&FrameLogFields::triggers);
  if (const json* triggers = find(j, {triggersKey})) {
    log.recordsTriggers = true;
    if (triggers->is_array()) {
      for (const auto& t : *triggers)
        if (t.is_string()) addTrigger(log, t.get<std::string>(), log.frame.back());
    } else {
      problems.add(where + ": '" + triggersKey + "' should be a list of names, found " + typeName(*triggers));
    }
  }
  if (const json* corrected = find(j, {logKey(&PoseFields::corrected)}); corrected && corrected->is_boolean()) {
    log.recordsTriggers = true;
    if (corrected->get<bool>()) addTrigger(log, "correction", log.frame.back());
  }
  addPose(log, j);
  addOdometry(log, j, index, where, problems);
}

// Drops the `count` oldest frames from every column (and the trigger frames before the first one kept).
void dropOldest(FrameLog& log, size_t count) {
  count = std::min(count, log.size());
  if (count == 0) return;
  const auto cut = [count](std::vector<double>& column) {
    column.erase(column.begin(), column.begin() + static_cast<std::ptrdiff_t>(std::min(count, column.size())));
  };
  for (auto* column : {&log.frame, &log.timestamp, &log.csr, &log.icp, &log.pd0, &log.computationMs, &log.tracked,
                       &log.trackingAttempted, &log.velocity, &log.joules, &log.powerW, &log.level,
                       &log.conditioning, &log.constrained, &log.state})
    cut(*column);
  for (auto& column : log.stageMs) cut(column);
  for (auto& column : log.odometry) cut(column.values);
  const auto n = static_cast<std::ptrdiff_t>(count);
  for (auto& column : log.odometryText) column.values.erase(column.values.begin(), column.values.begin() + n);
  log.pose.erase(log.pose.begin(), log.pose.begin() + n);
  if (log.frame.empty()) return;
  const double first = log.frame.front();
  for (auto& t : log.triggers)
    t.frames.erase(t.frames.begin(), std::lower_bound(t.frames.begin(), t.frames.end(), first));
}

}  // namespace

const std::vector<double>& FrameLog::triggerFrames(const std::string& name) const {
  static const std::vector<double> none;
  for (const auto& t : triggers)
    if (t.name == name) return t.frames;
  return none;
}

const FrameLog::OdometryColumn* FrameLog::odometryColumn(const std::string& name) const {
  for (const auto& c : odometry)
    if (c.name == name) return &c;
  return nullptr;
}

bool FrameLog::hasColumn(const std::vector<double>& column) const {
  for (double v : column)
    if (std::isfinite(v)) return true;
  return false;
}

FrameLogReadResult readFrameLog(const std::string& path, size_t maxFrames) {
  FrameLogReadResult result;
  const std::string problem = pathProblem(path);  // never opens (nor waits on) a FIFO
  if (!problem.empty()) {
    result.problems.push_back("cannot read '" + path + "': it " + problem + " (no per-frame plots)");
    return result;
  }
  InputFile in(path, "per-frame log");

  // Streamed, one line ahead (to know the last line), never the whole file in memory: a long run's log keeps
  // only its newest maxFrames frames (trimmed whenever twice as many are held).
  ProblemList problems(result.problems);
  size_t nonEmpty = 0, frames = 0;
  std::string line, next;
  bool have = static_cast<bool>(std::getline(in, line));
  bool terminated = !in.eof();  // getline stops at the end of the file without a newline: an unterminated line
  for (size_t n = 0; have; ++n, line.swap(next)) {
    const bool endsWithNewline = terminated;
    const bool last = !std::getline(in, next);
    terminated = !in.eof();
    have = !last;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    ++nonEmpty;
    const std::string where = path + " line " + std::to_string(n + 1);
    json j;
    try {
      j = json::parse(line);
    } catch (const json::exception& e) {
      if (last && !endsWithNewline)
        problems.add(where + " is incomplete (the run was probably interrupted while writing it); the report uses "
                     "the " + std::to_string(result.log.size()) + " frames before it");
      else
        problems.add(where + " is not valid JSON (" + e.what() + "); line skipped");
      continue;
    }
    if (!j.is_object()) {
      problems.add(where + " is not a JSON object (found " + j.type_name() + "); line skipped");
      continue;
    }
    addFrame(result.log, j, where, problems);
    ++frames;
    if (maxFrames > 0 && result.log.size() >= 2 * maxFrames) dropOldest(result.log, result.log.size() - maxFrames);
  }
  if (maxFrames > 0 && result.log.size() > maxFrames) dropOldest(result.log, result.log.size() - maxFrames);
  if (result.log.size() < frames)
    problems.add(path + " holds " + std::to_string(frames) + " frames; the per-frame plots show the newest " +
                 std::to_string(result.log.size()) + " (a report reads a bounded share of a long run)");
  if (nonEmpty == 0) problems.add(path + " is empty: the run recorded no frames (no per-frame plots)");
  problems.finish();
  return result;
}

}  // namespace sb::report
