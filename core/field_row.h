#pragma once
// The row of a record's member in its field table (core/pose_fields.h, core/frame_log_fields.h,
// pipeline/knob_fields.h): each table is a forEach(record, visit) that calls visit(row, member) per member; the
// row whose member is `member` is found by address on one default record. A value-initialised Row (every name
// null) when no row has it (the tables' tests check that every member has one).

#include <type_traits>

namespace sb {

template <typename Row, typename Record, typename M, typename ForEach>
Row fieldRowOf(M Record::*member, ForEach&& forEach) {
  static const Record record{};
  Row found{};
  bool seen = false;
  forEach(record, [&](const Row& row, const auto& m) {
    if constexpr (std::is_same_v<std::decay_t<decltype(m)>, M>)
      if (!seen && &m == &(record.*member)) {
        found = row;
        seen = true;
      }
  });
  return found;
}

}  // namespace sb
