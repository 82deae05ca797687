#include "power/smartpower2.h"

#include <cstdlib>
#include <string>

#include "power/serial_port.h"

namespace sb::power {

namespace {

// An unsigned decimal "123" or "5.102"; nothing else (no sign, exponent, spaces).
bool parseDecimal(std::string_view text, double& value) {
  if (text.empty() || text.size() > 16) return false;
  bool digits = false, point = false;
  for (char c : text) {
    if (c >= '0' && c <= '9') {
      digits = true;
    } else if (c == '.' && !point) {
      point = true;
    } else {
      return false;
    }
  }
  if (!digits || text.front() == '.' || text.back() == '.') return false;
  value = std::strtod(std::string(text).c_str(), nullptr);
  return true;
}

}  // namespace

LineResult parseSmartPower2Line(std::string_view line, LineReading& reading) {
  double fields[4];
  size_t count = 0, start = 0;
  while (start <= line.size()) {
    const size_t comma = line.find(',', start);
    const std::string_view field = line.substr(start, comma == std::string_view::npos ? line.npos : comma - start);
    if (count == 4 || !parseDecimal(field, fields[count])) return LineResult::skipped;
    ++count;
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (count != 4) return LineResult::skipped;
  // The SmartPower2 supplies up to ~5.25 V / 3 A; anything far outside is not a measurement line.
  const double volts = fields[0], amps = fields[1], watts = fields[2];
  if (volts > 30.0 || amps > 20.0 || watts > 300.0) return LineResult::skipped;
  reading = LineReading{};
  reading.volts = volts;
  reading.amps = amps;
  reading.watts = watts;
  return LineResult::sample;
}

void SmartPower2Settings::read(ConfigReader& r, bool) {
  r.string("device", device);
  r.integer("baud", baud, 9600, 921600);
  if (device.empty()) r.fail("device", "a serial device path such as \"/dev/ttyUSB0\"");
  if (!isSupportedBaud(baud)) r.fail("baud", "a supported baud rate (9600 ... 921600; 115200 by default)");
}

nlohmann::json SmartPower2Settings::toJson() const { return {{"device", device}, {"baud", baud}}; }

std::unique_ptr<Meter> openSmartPower2(const SmartPower2Settings& settings, const MeterHostSettings& host,
                                       const Clock& clock) {
  SerialLineOptions o;
  o.name = "smartpower2";
  o.device = settings.device;
  o.baud = settings.baud;
  o.nominalPeriodNs = 1'000'000'000;
  o.reopenMinNs = int64_t(host.reopenMinMs) * 1'000'000;
  o.reopenMaxNs = int64_t(host.reopenMaxMs) * 1'000'000;
  return std::make_unique<SerialLineMeter>(o, parseSmartPower2Line, clock);
}

}  // namespace sb::power
