#pragma once
// The tracking and controller record of one frame, as frames.jsonl writes it (runtime/frame_log_sink.h): what
// ICP did, what the controller decided and why, what the relocaliser did. Each field is written once, in
// forEachFrameLogField's table (its frames.jsonl name, the object that holds it, its member, its unit), as
// core/pose_fields.h keeps the pose record and pipeline/knob_fields.h the knob record; frameRecordToJson
// writes the record from it (runtime/frame_log_sink.h's frameLogFieldsOf makes the record from a FrameRecord)
// and report/frame_log.cpp reads its fields by the table's names (frameLogField).
// tests/daemon/test_frame_report.cpp checks every row against frames.jsonl, and every key of a line against
// the three tables and the few objects still written by hand (stage times, half precision, the odometry's
// verdict, the work counts, the next knobs).
//
// The rule: a field without a value (an empty std::optional, an empty string) is absent. A row with an object
// makes that object when it has a value (frames.jsonl's relocalisation: only on frames the relocaliser ran).

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "core/field_row.h"

namespace sb {

struct FrameLogFields {
  // Tracking (pipeline/pipeline.h's FrameResult).
  bool trackingAttempted = false;  // false in the bootstrap frames and on frames skipped by the tracking rate
  bool integrated = false;
  int icpIterations = 0;           // all levels (both passes when retracked)
  double residualM = 0.0;          // RMS point-to-plane residual of the last ICP pass
  double inliers = 0.0;            // fraction of the pixels at the compute size
  double trackedVelocityMPerFrame = 0.0;  // of the tracked pose, before any correction
  std::optional<std::array<int, 3>> icpLevelIterations;  // finest, mid, coarsest: when tracking was attempted
  std::optional<double> icpUpdateNorm;                   // when tracking was attempted
  std::optional<double> icpConditioning;                 // per pixel, when ICP's quality is known
  std::optional<double> pairAgreement;                   // when tracking was attempted
  std::optional<double> modelCoverage;                   // when tracking was attempted
  // The controller.
  double controllerMs = 0.0;
  std::vector<std::string> triggers;
  bool halfWish = false;
  bool knobsPinned = false;     // the next knobs were overridden by pinned knobs
  std::optional<int> level;     // when the controller has levels
  std::string reason;           // the decision in words, when the controller gives one
  // The relocaliser, on frames it ran.
  std::optional<int> relocalisationTries;
  std::optional<int> relocalisationConfirmed;
  std::optional<std::string> relocalisationWhy;  // written when it ran, even empty
  // The keyframes and the motion's plausibility.
  std::optional<bool> keyframeAdded;  // true, or absent
  uint64_t keyframes = 0;
  std::string implausible;            // why the motion is one the platform cannot make, or empty
};

// One row of the table.
struct FrameLogField {
  const char* logName;    // frames.jsonl's key
  const char* logObject;  // the object that holds it (nullptr: the line itself)
  const char* unit;       // "" for flags, names and counts
};

// Calls field(row, member) for each field, in the table's order. `F` is FrameLogFields or const FrameLogFields.
template <typename F, typename Field>
void forEachFrameLogField(F& f, Field&& field) {
  field(FrameLogField{"tracking_attempted", nullptr, ""}, f.trackingAttempted);
  field(FrameLogField{"integrated", nullptr, ""}, f.integrated);
  field(FrameLogField{"icp_iterations", nullptr, ""}, f.icpIterations);
  field(FrameLogField{"residual_m", nullptr, "m"}, f.residualM);
  field(FrameLogField{"inliers", nullptr, ""}, f.inliers);
  field(FrameLogField{"tracked_velocity_m_per_frame", nullptr, "m/frame"}, f.trackedVelocityMPerFrame);
  field(FrameLogField{"icp_level_iterations", nullptr, ""}, f.icpLevelIterations);
  field(FrameLogField{"icp_update_norm", nullptr, ""}, f.icpUpdateNorm);
  field(FrameLogField{"icp_conditioning", nullptr, ""}, f.icpConditioning);
  field(FrameLogField{"pair_agreement", nullptr, ""}, f.pairAgreement);
  field(FrameLogField{"model_coverage", nullptr, ""}, f.modelCoverage);
  field(FrameLogField{"controller_ms", nullptr, "ms"}, f.controllerMs);
  field(FrameLogField{"triggers", nullptr, ""}, f.triggers);
  field(FrameLogField{"half_wish", nullptr, ""}, f.halfWish);
  field(FrameLogField{"knobs_pinned", nullptr, ""}, f.knobsPinned);
  field(FrameLogField{"level", nullptr, ""}, f.level);
  field(FrameLogField{"reason", nullptr, ""}, f.reason);
  field(FrameLogField{"tries", "relocalisation", ""}, f.relocalisationTries);
  field(FrameLogField{"confirmed", "relocalisation", ""}, f.relocalisationConfirmed);
  field(FrameLogField{"why", "relocalisation", ""}, f.relocalisationWhy);
  field(FrameLogField{"keyframe_added", nullptr, ""}, f.keyframeAdded);
  field(FrameLogField{"keyframes", nullptr, ""}, f.keyframes);
  field(FrameLogField{"implausible", nullptr, ""}, f.implausible);
}

// The row of a member: frameLogField(&FrameLogFields::level).logName is "level". Every member has a row
// (tests/daemon/test_frame_report.cpp).
template <typename M>
FrameLogField frameLogField(M FrameLogFields::*member) {
  return fieldRowOf<FrameLogField>(member,
                                   [](const FrameLogFields& r, auto&& visit) { forEachFrameLogField(r, visit); });
}

// Calls write(row, value) for each field that has a value, the value as JSON, in the table's order.
template <typename Write>
void forEachFrameLogValue(const FrameLogFields& f, Write&& write) {
  forEachFrameLogField(f, [&](const FrameLogField& row, const auto& member) {
    using T = std::decay_t<decltype(member)>;
    if constexpr (std::is_same_v<T, std::string>) {
      if (!member.empty()) write(row, nlohmann::json(member));
    } else if constexpr (std::is_same_v<T, std::optional<std::array<int, 3>>> ||
                         std::is_same_v<T, std::optional<double>> || std::is_same_v<T, std::optional<int>> ||
                         std::is_same_v<T, std::optional<bool>> || std::is_same_v<T, std::optional<std::string>>) {
      if (member) write(row, nlohmann::json(*member));
    } else {
      write(row, nlohmann::json(member));
    }
  });
}

}  // namespace sb
