// The pose record's table (core/pose_fields.h) and the knob record's (pipeline/knob_fields.h): both encoders of
// each, frames.jsonl's (runtime/frame_log_sink.h) and POSE's or KNOBS's (daemon/protocol.h), write every row
// under its names with the same value. A row one encoder leaves out or names otherwise, a field written past the
// table, or a field the ROS bridge reads under another name (ros/daemon_reports.h), fails here; so does a
// frames.jsonl key in none of the tables (core/frame_log_fields.h has the tracking and controller fields) nor
// among the objects still written by hand.
#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "core/frame_log_fields.h"
#include "core/pose_fields.h"
#include "daemon/frame_report.h"
#include "pipeline/knob_fields.h"
#include "report/frame_log.h"
#include "ros/daemon_reports.h"
#include "runtime/frame_log_sink.h"
#include "runtime/knob_pins.h"
#include "tests/support/test_data.h"
#include "report/run_summary.h"

using namespace sb;
using namespace sb::daemon;

namespace {

FrameRecord sampleRecord() {
  FrameRecord rec;
  FrameResult& r = rec.result;
  r.frame = 42;
  r.timestamp = 1234.5;
  r.T_camera_to_world = Eigen::Translation3d(1.0, -2.0, 3.5) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY());
  r.trackingAttempted = true;
  r.tracked = true;
  r.poseOverridden = true;
  r.velocity = 0.031;
  r.quality.known = true;
  r.quality.conditioning = 0.0021;
  r.quality.weakest = WeakDirection::tz;
  r.quality.constrained = false;
  r.knobs.csr = 4;
  r.knobs.trackingRate = 1;
  r.knobs.integrationRate = 5;
  r.times.ms[static_cast<int>(Stage::track)] = 7.25;
  rec.state = TrackingState::odometry;
  rec.controller = "adaptive";
  rec.odometry.available = true;
  rec.odometry.used = true;
  rec.odometry.driftM = 0.75;
  rec.odometry.fault = sb::odometry::WheelFault::kidnapped;
  rec.keptMap = KeptMap::localised;
  return rec;
}

}  // namespace

TEST_CASE("every row of the pose table is written by both encoders, under its POSE and frames.jsonl names",
          "[daemon][protocol]") {
  const FrameRecord rec = sampleRecord();  // every pose field has a value
  const nlohmann::json pose = poseMessage(frameReport(rec, {"csr"}));
  const nlohmann::json log = frameRecordToJson(rec);

  // POSE's fields, every one: a field added to POSE must be named here (and in docs/protocol.md).
  std::set<std::string> poseKeys;
  for (auto it = pose.begin(); it != pose.end(); ++it) poseKeys.insert(it.key());
  CHECK(poseKeys == std::set<std::string>{"class", "conditioning", "constrained", "corrected", "frame", "kept_map",
                                          "odometry", "odometry_drift_m", "odometry_fault", "position", "quaternion",
                                          "state", "timestamp", "tracked", "velocity", "velocity_m_per_frame",
                                          "weakest_motion"});
  // Each row: in POSE under its name, in frames.jsonl under its log name (in its object), the same value. A field
  // written past the table, or a row one encoder leaves out or names otherwise, fails here.
  std::set<std::string> rows{"class"}, logKeys;
  const PoseFields fields = poseFieldsOf(rec);
  forEachPoseField(fields, [&](const PoseField& row, const auto&) {
    INFO(row.name);
    CHECK(rows.insert(row.name).second);  // each POSE name once
    REQUIRE(row.unit != nullptr);
    REQUIRE(pose.contains(row.name));
    if (!row.logName) return;
    const nlohmann::json& object = row.logObject ? log.at(row.logObject) : log;
    REQUIRE(object.contains(row.logName));
    CHECK(object.at(row.logName) == pose.at(row.name));
    logKeys.insert(row.logObject ? std::string(row.logObject) + "." + row.logName : row.logName);
  });
  CHECK(rows == poseKeys);
  // frames.jsonl's names of the rows (report/ and the scripts read them): a row renamed in the table fails here.
  CHECK(logKeys == std::set<std::string>{"conditioning", "constrained", "corrected", "frame", "kept_map",
                                         "odometry.available", "odometry.drift_m", "odometry.fault", "position",
                                         "quaternion", "state", "timestamp", "tracked", "velocity_m_per_frame",
                                         "weakest_motion"});
  // The values themselves, where a projection could drop them.
  CHECK(pose.at("velocity") == log.at("velocity_m_per_frame"));
  CHECK(log.at("odometry").at("fault") == "kidnapped");
  CHECK(pose.at("state") == "odometry");
  CHECK(pose.at("kept_map") == "localised");
  CHECK(pose.at("constrained") == false);
  CHECK(pose.at("odometry_drift_m") == 0.75);
}

TEST_CASE("a pose field without a value is absent from both encodings; frames.jsonl's conditions hold",
          "[daemon][protocol]") {
  FrameRecord rec = sampleRecord();
  rec.result.quality.known = false;  // ICP did not run: no conditioning, weakest motion, constrained in the log
  rec.odometry = FrameOdometry{};    // a run without odometry: no odometry object in the log
  rec.keptMap = KeptMap::none;
  const nlohmann::json pose = poseMessage(frameReport(rec, {}));
  const nlohmann::json log = frameRecordToJson(rec);
  for (const char* key : {"conditioning", "weakest_motion", "odometry_fault", "kept_map"}) {
    INFO(key);
    CHECK_FALSE(pose.contains(key));
  }
  CHECK(pose.at("constrained") == true);  // POSE: true when the conditioning is not known
  CHECK(pose.at("odometry") == false);
  CHECK(pose.at("odometry_drift_m") == 0.0);
  for (const char* key : {"conditioning", "weakest_motion", "constrained", "kept_map", "odometry"}) {
    INFO(key);
    CHECK_FALSE(log.contains(key));
  }
  // Odometry without a fault: the object with the table's available and drift_m, no fault.
  rec.odometry.available = true;
  rec.odometry.driftM = 0.25;
  const nlohmann::json withOdometry = frameRecordToJson(rec);
  REQUIRE(withOdometry.contains("odometry"));
  CHECK(withOdometry.at("odometry").at("available") == true);
  CHECK(withOdometry.at("odometry").at("drift_m") == 0.25);
  CHECK_FALSE(withOdometry.at("odometry").contains("fault"));
}

TEST_CASE("the readers name the pose fields by the table: report/ reads frames.jsonl's, the bridge POSE's",
          "[daemon][protocol][report][ros]") {
  // Every member has its row (poseField finds it), each with both names where both encoders write it.
  CHECK(poseField(&PoseFields::frame).name == std::string("frame"));
  CHECK(poseField(&PoseFields::velocityMPerFrame).name == std::string("velocity_m_per_frame"));  // the first row
  CHECK(poseField(&PoseFields::odometryDriftM).logObject == std::string("odometry"));
  for (const PoseField& row :
       {poseField(&PoseFields::timestamp), poseField(&PoseFields::position), poseField(&PoseFields::quaternion),
        poseField(&PoseFields::tracked), poseField(&PoseFields::corrected), poseField(&PoseFields::state),
        poseField(&PoseFields::conditioning), poseField(&PoseFields::weakestMotion),
        poseField(&PoseFields::constrained), poseField(&PoseFields::odometry), poseField(&PoseFields::odometryFault),
        poseField(&PoseFields::keptMap)}) {
    REQUIRE(row.name != nullptr);
    CHECK(row.logName != nullptr);
  }

  // report/frame_log.cpp reads frames.jsonl as frameRecordToJson writes it.
  FrameRecord rec = sampleRecord();
  rec.odometry.fault = sb::odometry::WheelFault::none;  // fault-free: the state stays odometry
  const std::string path = sb::test::scratchDir("frame_report_readers") + "/frames.jsonl";
  std::ofstream(path) << frameRecordToJson(rec).dump() << "\n";
  const auto read = report::readFrameLog(path);
  CHECK(read.problems.empty());
  REQUIRE(read.log.size() == 1);
  const PoseFields p = poseFieldsOf(rec);
  CHECK(read.log.frame[0] == 42);
  CHECK(read.log.timestamp[0] == 1234.5);
  CHECK(read.log.tracked[0] == 1.0);
  CHECK(read.log.trackingAttempted[0] == 1.0);
  CHECK(read.log.velocity[0] == p.velocityMPerFrame);
  CHECK(read.log.conditioning[0] == *p.conditioning);
  CHECK(read.log.constrained[0] == 0.0);
  CHECK(read.log.state[0] == static_cast<double>(TrackingState::odometry));
  CHECK(read.log.triggerFrames("correction") == std::vector<double>{42});  // "corrected": true
  for (size_t i = 0; i < 3; ++i) CHECK(read.log.pose[0][i] == p.position[i]);
  for (size_t i = 0; i < 4; ++i) CHECK(read.log.pose[0][3 + i] == p.quaternion[i]);
  REQUIRE(read.log.odometryColumn("drift_m"));
  CHECK(read.log.odometryColumn("drift_m")->values[0] == 0.75);

  // A POSE of a daemon before protocol 1.3 (the velocity under its older name alone) still gives the velocity.
  nlohmann::json old = poseMessage(frameReport(rec, {}));
  old.erase("velocity_m_per_frame");
  CHECK(ros_bridge::parsePose(old).velocityMPerFrame == p.velocityMPerFrame);
}

TEST_CASE("every row of the knob table is written by both encoders, under its KNOBS and frames.jsonl names",
          "[daemon][protocol]") {
  const FrameRecord rec = sampleRecord();
  const nlohmann::json knobs = knobsMessage(frameReport(rec, {"csr"}));
  const nlohmann::json log = frameRecordToJson(rec);
  // KNOBS's fields, every one: a field added to KNOBS must be named here (and in docs/protocol.md).
  std::set<std::string> knobsKeys;
  for (auto it = knobs.begin(); it != knobs.end(); ++it) knobsKeys.insert(it.key());
  CHECK(knobsKeys == std::set<std::string>{"class", "computation_ms", "controller", "csr", "frame", "icp", "ir",
                                           "pd", "pinned", "tr"});
  // Each row: in KNOBS under its name (the knob set: each knob a member), in frames.jsonl under its log name,
  // the same value. A field written past the table, or a row one encoder leaves out or names otherwise, fails.
  std::set<std::string> rows{"class"}, logKeys;
  const KnobFields fields = frameReport(rec, {"csr"}).knobs;
  forEachKnobRecordField(fields, [&](const KnobRecordField& row, const auto&) {
    INFO((row.name ? row.name : "(the knob set)"));
    REQUIRE(row.unit != nullptr);
    nlohmann::json value;
    if (row.name) {
      CHECK(rows.insert(row.name).second);  // each KNOBS name once
      REQUIRE(knobs.contains(row.name));
      value = knobs.at(row.name);
    } else {
      value = nlohmann::json::object();
      Knobs names;
      forEachKnobField(names, [&](const char* name, const auto&) {  // pipeline/knobs.h's names: csr .. ir
        CHECK(rows.insert(name).second);
        REQUIRE(knobs.contains(name));
        value[name] = knobs.at(name);
      });
    }
    if (!row.logName) return;
    REQUIRE(log.contains(row.logName));
    CHECK(log.at(row.logName) == value);
    logKeys.insert(row.logName);
  });
  CHECK(rows == knobsKeys);
  // frames.jsonl's names of the rows (report/ and the scripts read them): a row renamed in the table fails here.
  CHECK(logKeys == std::set<std::string>{"computation_ms", "controller", "frame", "knobs"});
  // Every member has its row (knobRecordField finds it), the values where a projection could drop them.
  CHECK(knobRecordField(&KnobFields::frame).name == std::string("frame"));
  CHECK(knobRecordField(&KnobFields::controller).logName == std::string("controller"));
  CHECK(knobRecordField(&KnobFields::computationMs).unit == std::string("ms"));
  CHECK(knobRecordField(&KnobFields::knobs).logName == std::string("knobs"));
  CHECK(knobRecordField(&KnobFields::pinned).name == std::string("pinned"));
  CHECK(knobs.at("pinned") == nlohmann::json{"csr"});
  CHECK(knobs.at("controller") == "adaptive");
  CHECK(knobs.at("csr") == 4);
  CHECK(log.at("computation_ms") == rec.result.times.computationMs());
  CHECK(log.at("frame") == 42);
  CHECK_FALSE(log.contains("pinned"));  // KNOBS's alone: frames.jsonl says knobs_pinned (a flag)
}

TEST_CASE("every row of the tracking and controller table is in frames.jsonl; every key of a line is a table's",
          "[daemon][report]") {
  FrameRecord rec = sampleRecord();  // every field has a value
  rec.result.icpIterations = 12;
  rec.decision.level = 2;
  rec.decision.reason = "steady";
  rec.decision.triggers = 1u;
  rec.relocalising = true;
  rec.relocalisation.tries = 3;
  rec.relocalisation.confirmed = 1;
  rec.relocalisation.why = "candidate held";
  rec.keyframeAdded = true;
  rec.keyframes = 7;
  rec.implausible = "faster than the platform";
  const nlohmann::json log = frameRecordToJson(rec);
  const FrameLogFields fields = frameLogFieldsOf(rec);
  const PoseFields pose = poseFieldsOf(rec);
  const KnobFields knobs = knobFieldsOf(rec);
  std::set<std::string> keys, tables;
  forEachFrameLogField(fields, [&](const FrameLogField& row, const auto&) {
    INFO(row.logName);
    REQUIRE(row.unit != nullptr);
    const nlohmann::json& object = row.logObject ? log.at(row.logObject) : log;
    REQUIRE(object.contains(row.logName));  // a row the writer skips fails here
    CHECK(keys.insert(row.logObject ? std::string(row.logObject) + "." + row.logName : row.logName).second);
    tables.insert(row.logObject ? row.logObject : row.logName);
  });
  // frames.jsonl's names of the rows (report/ and the scripts read them): a row renamed in the table fails here.
  CHECK(keys == std::set<std::string>{"controller_ms", "half_wish", "icp_conditioning", "icp_iterations",
                                      "icp_level_iterations", "icp_update_norm", "implausible", "inliers",
                                      "integrated", "keyframe_added", "keyframes", "knobs_pinned", "level",
                                      "model_coverage", "pair_agreement", "reason", "relocalisation.confirmed", "relocalisation.tries",
                                      "relocalisation.why", "residual_m", "tracked_velocity_m_per_frame",
                                      "tracking_attempted", "triggers"});
  CHECK(log.at("relocalisation") == nlohmann::json{{"tries", 3}, {"confirmed", 1}, {"why", "candidate held"}});
  CHECK(log.at("level") == 2);
  CHECK(log.at("triggers") == triggerNames(1u));
  CHECK(log.at("keyframes") == 7);
  CHECK(frameLogField(&FrameLogFields::relocalisationWhy).logObject == std::string("relocalisation"));
  // Every key of the line is a row of one of the three tables or one of the objects still written by hand.
  forEachPoseField(pose, [&](const PoseField& row, const auto&) {
    if (row.logName) tables.insert(row.logObject ? row.logObject : row.logName);
  });
  forEachKnobRecordField(knobs, [&](const KnobRecordField& row, const auto&) {
    if (row.logName) tables.insert(row.logName);
  });
  const std::set<std::string> byHand{"ms",   "device_ms", "half",          "next_knobs",   "retracked_from",
                                     "work", "odometry",  "t_start_mono_ns", "t_end_mono_ns"};
  for (auto it = log.begin(); it != log.end(); ++it) {
    INFO(it.key());
    CHECK((tables.count(it.key()) || byHand.count(it.key())));
  }
  // Without values: absent.
  FrameRecord plain = sampleRecord();
  plain.result.trackingAttempted = false;
  plain.result.quality.known = false;
  const nlohmann::json bare = frameRecordToJson(plain);
  for (const char* key : {"icp_level_iterations", "icp_update_norm", "icp_conditioning", "pair_agreement", "model_coverage", "level",
                          "reason", "relocalisation", "keyframe_added", "implausible"}) {
    INFO(key);
    CHECK_FALSE(bare.contains(key));
  }
}

TEST_CASE("the ROS bridge reads every POSE and KNOBS field the daemon writes", "[daemon][protocol][ros]") {
  const FrameRecord rec = sampleRecord();
  const FrameReport report = frameReport(rec, {});
  const ros_bridge::PoseReport p = ros_bridge::parsePose(poseMessage(report));
  CHECK(p.frame == 42);
  CHECK(p.timestamp == 1234.5);
  CHECK(p.position == report.pose.position);
  CHECK(p.quaternion == report.pose.quaternion);
  CHECK(p.tracked);
  CHECK(p.corrected);
  CHECK(p.velocityMPerFrame == Approx(0.031));
  CHECK(p.constrained == false);
  REQUIRE(p.conditioning);
  CHECK(*p.conditioning == 0.0021);
  CHECK(p.weakestMotion == "tz");
  CHECK(p.state == TrackingState::odometry);  // one enum: the daemon's
  CHECK(p.odometry);
  CHECK(p.odometryDriftM == 0.75);
  CHECK(p.odometryFault == "kidnapped");
  CHECK(p.keptMap == "localised");
  // Every state the daemon can send is one the bridge knows by name.
  for (int s = 0; s < kTrackingStateCount; ++s) {
    FrameRecord other = rec;
    other.state = static_cast<TrackingState>(s);
    CHECK(ros_bridge::parsePose(poseMessage(frameReport(other, {}))).state == other.state);
  }
  const FrameReport pinned = frameReport(rec, {"csr", "tr"});
  const ros_bridge::KnobsReport k = ros_bridge::parseKnobs(knobsMessage(pinned));
  CHECK(k.frame == 42);
  CHECK(k.pinned == std::vector<std::string>{"csr", "tr"});
  CHECK(k.controller == "adaptive");
  CHECK(k.knobs.csr == 4);
  CHECK(k.knobs.integrationRate == 5);
  CHECK(k.knobs == rec.result.knobs);
  CHECK(k.computationMs == rec.result.times.computationMs());
  // Whole records: what the bridge read, written again, is what the daemon wrote (every row of both tables).
  FrameReport back;
  back.pose = p;
  back.knobs = k;
  CHECK(poseMessage(back) == poseMessage(report));
  CHECK(knobsMessage(back) == knobsMessage(pinned));
}

// Every knob of pipeline/knobs.h's key table, moved off its default alone, through every writer and reader of a
// knob set: a writer or reader that leaves a knob out, or names it otherwise, fails here.
TEST_CASE("every knob of the key table survives each encoder and parser", "[daemon][protocol][ros][knobs]") {
  REQUIRE(std::size(kKnobKeys) == 7);
  for (const KnobKey& key : kKnobKeys) {
    INFO(key.name);
    Knobs k;
    // A valid value other than the default: the next power of two, a tenth of the range, or one more.
    const double before = key.value(k);
    const double v = key.powerOfTwo ? before * 2 : key.isWhole() ? before + 1 : key.maximum / 10;
    key.set(k, v);
    REQUIRE(key.value(k) == v);
    REQUIRE(k != Knobs{});
    REQUIRE_NOTHROW(validateKnobs(k));

    // Knob strings.
    CHECK(parseKnobs(formatKnobs(k)) == k);
    // The pins (?CONTROL): one knob pinned over the defaults.
    KnobPins pins;
    pins.pin(key.name, v);
    CHECK(pins.apply(Knobs{}) == k);
    CHECK(KnobPins::all(k).apply(Knobs{}) == k);
    // frames.jsonl's knobs and next_knobs, and summary.json's knobs read back.
    FrameRecord rec = sampleRecord();
    rec.result.knobs = k;
    rec.decision.next = k;
    const nlohmann::json log = frameRecordToJson(rec);
    CHECK(log.at("knobs") == knobsToJson(k));
    CHECK(log.at("next_knobs") == knobsToJson(k));
    RunSummary s;
    s.knobs = k;
    const RunSummary back = RunSummary::fromJson(nlohmann::json::parse(s.toJson().dump()), "summary.json");
    REQUIRE(back.knobs);
    CHECK(*back.knobs == k);
    // KNOBS: the record's knobs as frames.jsonl writes them, read back by the ROS bridge.
    const nlohmann::json message = knobsMessage(frameReport(rec, {}));
    for (auto it = log.at("knobs").begin(); it != log.at("knobs").end(); ++it) CHECK(message.at(it.key()) == *it);
    const ros_bridge::KnobsReport report = ros_bridge::parseKnobs(nlohmann::json::parse(message.dump()));
    CHECK(report.knobs == k);
    // The bridge's diagnostics name each knob as the table does.
    const auto values = ros_bridge::knobValues(report);
    REQUIRE(values.size() == 5);
    CHECK(values[0] == std::pair<std::string, std::string>{"csr", std::to_string(k.csr)});
    CHECK(values[2].first == "pd");
    CHECK(values[2].second == std::to_string(k.pyramidIterations[0]) + "," + std::to_string(k.pyramidIterations[1]) +
                                  "," + std::to_string(k.pyramidIterations[2]));
  }
}
