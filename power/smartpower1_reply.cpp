#include "power/smartpower1_reply.h"

#include <cstdlib>
#include <string>

namespace sb::power {

namespace {

// One "<number><spaces><unit>" field starting at or after `pos`; number is "d.ddd" or "-.---".
bool readField(const std::string& text, size_t& pos, const std::string& unit, double& value, bool& dashes) {
  while (pos < text.size() && text[pos] == ' ') ++pos;
  const size_t start = pos;
  while (pos < text.size() && ((text[pos] >= '0' && text[pos] <= '9') || text[pos] == '.' || text[pos] == '-')) ++pos;
  const std::string number = text.substr(start, pos - start);
  while (pos < text.size() && text[pos] == ' ') ++pos;
  if (number.empty() || text.compare(pos, unit.size(), unit) != 0) return false;
  pos += unit.size();
  dashes = number.find('-') != std::string::npos;
  if (dashes) {
    if (number.find_first_not_of("-.") != std::string::npos) return false;
    value = 0.0;
    return true;
  }
  if (number.find('.') != number.rfind('.')) return false;
  value = std::strtod(number.c_str(), nullptr);
  return true;
}

}  // namespace

std::optional<SmartPower1Reading> parseSmartPower1Reply(const uint8_t* report, size_t size) {
  if (report == nullptr || size < 2 || report[0] != kSmartPower1RequestData) return std::nullopt;
  std::string text;
  for (size_t i = 1; i < size && report[i] != 0; ++i) {
    if (report[i] < 0x20 || report[i] > 0x7e) break;  // the text ends where the padding starts
    text.push_back(static_cast<char>(report[i]));
  }
  SmartPower1Reading r;
  size_t pos = 0;
  bool voltsOff = false, ampsOff = false, wattsOff = false;
  if (!readField(text, pos, "V", r.volts, voltsOff) || voltsOff) return std::nullopt;
  if (!readField(text, pos, "A", r.amps, ampsOff)) return std::nullopt;
  if (!readField(text, pos, "W", r.watts, wattsOff)) return std::nullopt;
  if (ampsOff != wattsOff) return std::nullopt;
  r.outputOn = !wattsOff;
  return r;
}

}  // namespace sb::power
