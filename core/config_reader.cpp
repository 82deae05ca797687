#include "core/config_reader.h"

#include <algorithm>
#include <sstream>

#include "core/error.h"
#include "core/json_text.h"

namespace sb {

namespace {

using nlohmann::json;

std::string rangeText(double minimum, double maximum) {
  std::ostringstream s;
  s << "[" << minimum << ", " << maximum << "]";
  return s.str();
}

std::string numberText(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

// "\"a\", \"b\"": the allowed strings as they would be written in the file.
std::string quotedList(const std::vector<std::string>& items) {
  std::string list;
  for (const auto& a : items) list += (list.empty() ? "\"" : ", \"") + a + "\"";
  return list;
}

// The value kept when the key is removed, for the message's hint (lists and long strings as a description).
std::string keptText(const json& value) {
  return describeJson(value);
}

}  // namespace

ConfigReader::ConfigReader(const json& j, std::string where, std::string path)
    : j_(j), where_(std::move(where)), path_(std::move(path)) {
  if (j_.is_null()) j_ = json::object();
  if (!j_.is_object())
    throw Error(where_ + ": " + (path_.empty() ? std::string("the settings") : "'" + path_ + "'") +
                " must be a JSON object {\"key\": value, ...}, got " + describeJson(j_));
}

std::string ConfigReader::path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

std::string ConfigReader::at(const std::string& key) const {
  return where_ + ": '" + path(key) + "'";
}

const json* ConfigReader::find(const std::string& key) {
  if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.push_back(key);
  const auto it = j_.find(key);
  return it == j_.end() ? nullptr : &*it;
}

void ConfigReader::reject(const std::string& key, const json& value, const std::string& expected,
                          const std::string& current) const {
  throw Error(at(key) + " = " + describeJson(value) + " is not allowed: expected " + expected +
              "; fix the value" +
              (current.empty() ? std::string() : " or remove the key to keep " + current));
}

void ConfigReader::fail(const std::string& key, const std::string& expected) const {
  const auto it = j_.find(key);
  if (it == j_.end()) throw Error(at(key) + " is not set: expected " + expected + "; add it");
  throw Error(at(key) + " = " + describeJson(*it) + " is not allowed: expected " + expected +
              "; fix the value");
}

const json* ConfigReader::raw(const std::string& key) {
  return find(key);
}

const json* ConfigReader::object(const std::string& key) {
  const json* v = find(key);
  if (v && !v->is_object()) reject(key, *v, "a JSON object {\"key\": value, ...}", "");
  return v;
}

void ConfigReader::number(const std::string& key, double& out, double minimum, double maximum) {
  const json* v = find(key);
  if (!v) return;
  const std::string expected = "a number in " + rangeText(minimum, maximum);
  if (!v->is_number()) reject(key, *v, expected, numberText(out));
  const double x = v->get<double>();
  if (!(x >= minimum && x <= maximum)) reject(key, *v, expected, numberText(out));
  out = x;
}

void ConfigReader::number(const std::string& key, float& out, double minimum, double maximum) {
  double x = out;
  const json* v = j_.contains(key) ? &j_.at(key) : nullptr;
  number(key, x, minimum, maximum);
  if (v) out = static_cast<float>(x);
}

bool ConfigReader::readInteger(const std::string& key, int64_t& out, int64_t minimum, int64_t maximum) {
  const json* v = find(key);
  if (!v) return false;
  const std::string expected =
      "an integer in [" + std::to_string(minimum) + ", " + std::to_string(maximum) + "]";
  const std::string current = std::to_string(out);
  if (!v->is_number_integer()) reject(key, *v, expected, current);
  if (v->is_number_unsigned() && v->get<uint64_t>() > static_cast<uint64_t>(maximum))
    reject(key, *v, expected, current);
  const int64_t x = v->get<int64_t>();
  if (x < minimum || x > maximum) reject(key, *v, expected, current);
  out = x;
  return true;
}

void ConfigReader::boolean(const std::string& key, bool& out) {
  const json* v = find(key);
  if (!v) return;
  if (!v->is_boolean()) reject(key, *v, "true or false", out ? "true" : "false");
  out = v->get<bool>();
}

void ConfigReader::string(const std::string& key, std::string& out, const std::vector<std::string>& allowed) {
  const json* v = find(key);
  if (!v) return;
  const std::string expected = allowed.empty() ? "a string" : "one of " + quotedList(allowed);
  if (!v->is_string()) reject(key, *v, expected, keptText(out));
  const std::string s = v->get<std::string>();
  if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), s) == allowed.end())
    reject(key, *v, expected, keptText(out));
  out = s;
}

void ConfigReader::numbers(const std::string& key, std::vector<double>& out, double minimum, double maximum,
                           size_t minSize, size_t maxSize, const std::string& meaning) {
  const json* v = find(key);
  if (!v) return;
  const std::string count =
      minSize == maxSize ? std::to_string(minSize) : std::to_string(minSize) + ".." + std::to_string(maxSize);
  const std::string expected = "a list of " + count + " numbers" +
                               (meaning.empty() ? "" : " (" + meaning + ")") + ", each in " +
                               rangeText(minimum, maximum);
  const std::string current = keptText(json(out));
  if (!v->is_array() || v->size() < minSize || v->size() > maxSize) reject(key, *v, expected, current);
  std::vector<double> values;
  for (const json& e : *v) {
    if (!e.is_number() || !(e.get<double>() >= minimum && e.get<double>() <= maximum))
      reject(key, *v, expected + " (entry " + describeJson(e) + " is not)", current);
    values.push_back(e.get<double>());
  }
  out = std::move(values);
}

void ConfigReader::integers(const std::string& key, std::vector<int>& out, int minimum, int maximum,
                            size_t minSize, size_t maxSize) {
  const json* v = j_.contains(key) ? &j_.at(key) : nullptr;
  if (v && v->is_array())
    for (const json& e : *v)
      if (!e.is_number_integer())
        reject(key, *v, "a list of integers (entry " + describeJson(e) + " is not)", keptText(json(out)));
  std::vector<double> values(out.begin(), out.end());
  numbers(key, values, minimum, maximum, minSize, maxSize);
  out.assign(values.begin(), values.end());
}

void ConfigReader::strings(const std::string& key, std::vector<std::string>& out,
                           const std::vector<std::string>& allowed, size_t minSize, size_t maxSize) {
  const json* v = find(key);
  if (!v) return;
  std::string expected = "a list of strings";
  if (!allowed.empty()) expected += ", each one of " + quotedList(allowed);
  if (minSize > 0)
    expected += ", at least " + std::to_string(minSize) + (minSize == 1 ? " entry" : " entries");
  if (maxSize != std::numeric_limits<size_t>::max()) expected += ", at most " + std::to_string(maxSize);
  const std::string current = keptText(json(out));
  if (!v->is_array() || v->size() < minSize || v->size() > maxSize) reject(key, *v, expected, current);
  std::vector<std::string> items;
  for (const json& e : *v) {
    const bool ok = e.is_string() && (allowed.empty() || std::find(allowed.begin(), allowed.end(),
                                                                   e.get<std::string>()) != allowed.end());
    if (!ok) reject(key, *v, expected + " (entry " + describeJson(e) + " is not)", current);
    items.push_back(e.get<std::string>());
  }
  out = std::move(items);
}

void ConfigReader::finish() const {
  for (auto it = j_.begin(); it != j_.end(); ++it) {
    if (std::find(known_.begin(), known_.end(), it.key()) != known_.end()) continue;
    std::string list;
    for (const auto& k : known_) list += (list.empty() ? "" : ", ") + k;
    throw Error(where_ + ": unknown key '" + path(it.key().substr(0, 60)) + "' (known keys" +
                (path_.empty() ? "" : " of '" + path_ + "'") + ": " + list +
                "); fix its spelling or remove it");
  }
}

json readJsonConfig(const std::string& path, const std::string& what) {
  // Bounded nesting; errors read "<what> '<path>': not valid JSON at line L, column C: ...".
  json j = parseJson(readTextFile(path, what), what + " '" + path + "'");
  if (!j.is_object())
    throw Error(what + " '" + path + "' must hold a JSON object {\"key\": value, ...}, not " +
                describeJson(j) + "; fix the file");
  return j;
}

}  // namespace sb
