#pragma once
// The knob record of one frame: the knobs it ran with, the controller that chose them, its computation time and
// the knobs pinned over the controller's choice, as the daemon's KNOBS carries them (docs/protocol.md) and
// frames.jsonl writes them (runtime/frame_log_sink.h). Each field is written once, in forEachKnobRecordField's table
// (its KNOBS name, its frames.jsonl name, its member, its unit), as core/pose_fields.h keeps the pose record.
// Both encoders are made from the table: frames.jsonl's (frameRecordToJson) and KNOBS's (daemon/protocol.cpp,
// knobsMessage); runtime/frame_log_sink.h's knobFieldsOf makes the record from a frame's FrameRecord, the one
// projection both use. The readers name the fields by the table too (knobRecordField): KNOBS's in
// ros/daemon_reports.cpp, frames.jsonl's in report/frame_log.cpp. tests/daemon/test_frame_report.cpp checks every
// row against both encodings.
//
// Every field is always written (an empty controller name, an empty pin list included). The knob set is one
// row: frames.jsonl holds it as an object ("knobs": {"csr": 1, ...}), KNOBS holds its members themselves
// ("csr": 1, ...), each under its name in pipeline/knobs.h's key table (knobsToJson).

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>
#include <vector>

#include "core/field_row.h"
#include "pipeline/knobs.h"

namespace sb {

struct KnobFields {
  uint64_t frame = 0;
  std::string controller;            // the controller that chose the knobs
  double computationMs = 0.0;        // preprocessing + tracking + integration + raycast
  Knobs knobs;                       // the knobs the frame ran with
  std::vector<std::string> pinned;   // the knobs pinned over the controller's choice (the daemon's ?CONTROL)
};

// One row of the table.
struct KnobRecordField {
  const char* name;     // KNOBS's member; nullptr: the knob set, whose members KNOBS holds themselves
  const char* logName;  // frames.jsonl's key for the same value; nullptr: not in frames.jsonl
  const char* unit;     // "" for names, counts and knob sets
};

// Calls field(row, member) for each field, in the table's order. `K` is KnobFields or const KnobFields. The
// frame is the pose record's too (core/pose_fields.h): frames.jsonl has one "frame", written by both tables.
template <typename K, typename Field>
void forEachKnobRecordField(K& k, Field&& field) {
  field(KnobRecordField{"frame", "frame", ""}, k.frame);
  field(KnobRecordField{"controller", "controller", ""}, k.controller);
  field(KnobRecordField{"computation_ms", "computation_ms", "ms"}, k.computationMs);
  field(KnobRecordField{nullptr, "knobs", ""}, k.knobs);
  field(KnobRecordField{"pinned", nullptr, ""}, k.pinned);
}

// The row of a member: knobRecordField(&KnobFields::computationMs).logName is "computation_ms". Every member has a row
// (tests/daemon/test_frame_report.cpp).
template <typename M>
KnobRecordField knobRecordField(M KnobFields::*member) {
  return fieldRowOf<KnobRecordField>(member,
                                     [](const KnobFields& r, auto&& visit) { forEachKnobRecordField(r, visit); });
}

// Calls write(row, value) for each field, the value as JSON (the knob set by knobsToJson), in the table's order:
// what both encoders write.
template <typename Write>
void forEachKnobRecordValue(const KnobFields& k, Write&& write) {
  forEachKnobRecordField(k, [&](const KnobRecordField& row, const auto& member) {
    if constexpr (std::is_same_v<std::decay_t<decltype(member)>, Knobs>)
      write(row, knobsToJson(member));
    else
      write(row, nlohmann::json(member));
  });
}

}  // namespace sb
