#include "daemon/json_reader.h"

#include <sstream>

#include "core/error.h"
#include "core/json_text.h"

namespace sb::daemon {

JsonObjectReader::JsonObjectReader(const nlohmann::json& j, std::string where)
    : j_(j), where_(std::move(where)) {
  if (!j_.is_object()) throw Error(where_ + ": must be a JSON object, got " + describeJson(j_));
}

const nlohmann::json* JsonObjectReader::find(const char* key) {
  known_.insert(key);
  auto it = j_.find(key);
  return it == j_.end() ? nullptr : &*it;
}

void JsonObjectReader::fail(const char* key, const nlohmann::json& value, const std::string& allowed) const {
  throw Error(where_ + ": '" + key + "' = " + describeJson(value) + " is not allowed; expected " + allowed);
}

void JsonObjectReader::string(const char* key, std::string& out) {
  if (const auto* v = find(key)) {
    if (!v->is_string()) fail(key, *v, "a string");
    out = v->get<std::string>();
  }
}

void JsonObjectReader::boolean(const char* key, bool& out) {
  if (const auto* v = find(key)) {
    if (!v->is_boolean()) fail(key, *v, "true or false");
    out = v->get<bool>();
  }
}

void JsonObjectReader::number(const char* key, double& out, double minimum, double maximum) {
  if (const auto* v = find(key)) {
    std::ostringstream range;
    range << "a number in [" << minimum << ", " << maximum << "]";
    if (!v->is_number()) fail(key, *v, range.str());
    const double d = v->get<double>();
    if (!(d >= minimum && d <= maximum)) fail(key, *v, range.str());
    out = d;
  }
}

void JsonObjectReader::integer(const char* key, int64_t& out, int64_t minimum, int64_t maximum) {
  if (const auto* v = find(key)) {
    const std::string range =
        "an integer in [" + std::to_string(minimum) + ", " + std::to_string(maximum) + "]";
    if (!v->is_number_integer()) fail(key, *v, range);
    if (v->is_number_unsigned() && v->get<uint64_t>() > static_cast<uint64_t>(maximum)) fail(key, *v, range);
    const int64_t i = v->get<int64_t>();
    if (i < minimum || i > maximum) fail(key, *v, range);
    out = i;
  }
}

void JsonObjectReader::choice(const char* key, std::string& out, std::initializer_list<const char*> allowed) {
  if (const auto* v = find(key)) {
    std::string list;
    for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string("\"") + a + "\"";
    if (!v->is_string()) fail(key, *v, "one of " + list);
    const std::string s = v->get<std::string>();
    for (const char* a : allowed)
      if (s == a) {
        out = s;
        return;
      }
    fail(key, *v, "one of " + list);
  }
}

const nlohmann::json* JsonObjectReader::object(const char* key) {
  const auto* v = find(key);
  if (v && !v->is_object()) fail(key, *v, "a JSON object");
  return v;
}

void JsonObjectReader::finish() const {
  for (auto it = j_.begin(); it != j_.end(); ++it) {
    if (known_.count(it.key())) continue;
    std::string keys;
    for (const auto& k : known_) keys += (keys.empty() ? "" : ", ") + k;
    throw Error(where_ + ": unknown key '" + it.key().substr(0, 60) + "' (known keys: " + keys + ")");
  }
}

}  // namespace sb::daemon
