#include "controller/config_reader.h"

#include <algorithm>
#include <sstream>

#include "core/error.h"

namespace sb {

namespace {

std::string rangeText(double minimum, double maximum) {
  std::ostringstream s;
  s << "[" << minimum << ", " << maximum << "]";
  return s.str();
}

}  // namespace

ConfigReader::ConfigReader(const nlohmann::json& j, std::string where) : j_(j), where_(std::move(where)) {
  if (j_.is_null()) j_ = nlohmann::json::object();
  if (!j_.is_object()) throw Error(where_ + ": must be a JSON object, got " + j_.dump());
}

std::string ConfigReader::at(const std::string& key) const { return where_ + ": '" + key + "'"; }

const nlohmann::json* ConfigReader::find(const std::string& key) {
  known_.push_back(key);
  const auto it = j_.find(key);
  return it == j_.end() ? nullptr : &*it;
}

const nlohmann::json* ConfigReader::raw(const std::string& key) { return find(key); }

void ConfigReader::number(const std::string& key, double& out, double minimum, double maximum) {
  const nlohmann::json* v = find(key);
  if (!v) return;
  if (!v->is_number()) throw Error(at(key) + " must be a number, got " + v->dump());
  const double x = v->get<double>();
  if (!(x >= minimum && x <= maximum))
    throw Error(at(key) + " = " + v->dump() + " is out of range; allowed " + rangeText(minimum, maximum));
  out = x;
}

void ConfigReader::integer(const std::string& key, int& out, int minimum, int maximum) {
  const nlohmann::json* v = find(key);
  if (!v) return;
  if (!v->is_number_integer()) throw Error(at(key) + " must be an integer, got " + v->dump());
  const long long x = v->get<long long>();
  if (x < minimum || x > maximum)
    throw Error(at(key) + " = " + v->dump() + " is out of range; allowed " + rangeText(minimum, maximum));
  out = static_cast<int>(x);
}

void ConfigReader::boolean(const std::string& key, bool& out) {
  const nlohmann::json* v = find(key);
  if (!v) return;
  if (!v->is_boolean()) throw Error(at(key) + " must be true or false, got " + v->dump());
  out = v->get<bool>();
}

void ConfigReader::string(const std::string& key, std::string& out, const std::vector<std::string>& allowed) {
  const nlohmann::json* v = find(key);
  if (!v) return;
  if (!v->is_string()) throw Error(at(key) + " must be a string, got " + v->dump());
  const std::string s = v->get<std::string>();
  if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), s) == allowed.end()) {
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    throw Error(at(key) + " = \"" + s + "\" is not allowed (use one of: " + list + ")");
  }
  out = s;
}

void ConfigReader::numbers(const std::string& key, std::vector<double>& out, double minimum, double maximum,
                           size_t minSize, size_t maxSize) {
  const nlohmann::json* v = find(key);
  if (!v) return;
  if (!v->is_array() || v->size() < minSize || v->size() > maxSize)
    throw Error(at(key) + " must be a list of " + std::to_string(minSize) + ".." + std::to_string(maxSize) +
                " numbers, got " + v->dump());
  std::vector<double> values;
  for (const auto& e : *v) {
    if (!e.is_number()) throw Error(at(key) + " must hold numbers only, got " + e.dump());
    const double x = e.get<double>();
    if (!(x >= minimum && x <= maximum))
      throw Error(at(key) + ": entry " + e.dump() + " is out of range; allowed " + rangeText(minimum, maximum));
    values.push_back(x);
  }
  out = values;
}

void ConfigReader::integers(const std::string& key, std::vector<int>& out, int minimum, int maximum, size_t minSize,
                            size_t maxSize) {
  std::vector<double> values(out.begin(), out.end());
  const nlohmann::json* v = j_.contains(key) ? &j_.at(key) : nullptr;
  if (v && v->is_array())
    for (const auto& e : *v)
      if (!e.is_number_integer()) throw Error(at(key) + " must hold integers only, got " + e.dump());
  numbers(key, values, minimum, maximum, minSize, maxSize);
  out.assign(values.begin(), values.end());
}

void ConfigReader::finish() const {
  for (auto it = j_.begin(); it != j_.end(); ++it) {
    if (std::find(known_.begin(), known_.end(), it.key()) != known_.end()) continue;
    std::string list;
    for (const auto& k : known_) list += (list.empty() ? "" : ", ") + k;
    throw Error(where_ + ": unknown key '" + it.key() + "' (known keys: " + list + ")");
  }
}

}  // namespace sb
