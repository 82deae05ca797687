#pragma once
// JSON from untrusted places (socket requests, config and calibration files): nesting is bounded before
// nlohmann builds a value, so no later dump, copy or comparison can recurse deeply; errors name the file
// (or request), the line and the column; and values are quoted in messages only as short, flat excerpts.

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace sb {

// Deepest nesting of arrays and objects accepted anywhere (config files use 3 levels, requests 2).
inline constexpr int kMaxJsonDepth = 64;
// Largest settings file read, bytes (config, calibration, controller and power settings are a few KiB).
inline constexpr size_t kMaxJsonFileBytes = 16u << 20;

// Parses `text`; on failure returns nullopt and sets `error` to what is wrong and where ("not valid JSON at
// line L, column C: ..." or "arrays and objects nest deeper than 64 levels (at line L, column C)").
std::optional<nlohmann::json> tryParseJson(std::string_view text, std::string& error,
                                           int maxDepth = kMaxJsonDepth);

// Parses `text`; throws sb::Error "<where>: <the error above>".
nlohmann::json parseJson(std::string_view text, const std::string& where, int maxDepth = kMaxJsonDepth);

// The whole of a regular file. Throws sb::Error naming `what` and the path when the path is missing,
// unreadable, a directory or another non-regular file, or longer than `maxBytes`.
std::string readTextFile(const std::string& path, const std::string& what,
                         size_t maxBytes = kMaxJsonFileBytes);


// A short, flat rendering of `value` for error messages: scalars as JSON (strings cut to `maxChars`),
// arrays and objects as "an array of N elements" / "an object with N keys". Never recurses.
std::string describeJson(const nlohmann::json& value, size_t maxChars = 60);

}  // namespace sb
