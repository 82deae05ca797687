#include "power/smartpower3.h"

#include <cstdint>

#include "core/error.h"
#include "power/serial_port.h"

namespace sb::power {

namespace {

constexpr size_t kFields = 17;
constexpr size_t kFirstChecksumField = 15;

bool parseUnsigned(std::string_view text, int base, uint64_t& value) {
  if (text.empty() || text.size() > 10) return false;
  value = 0;
  for (char c : text) {
    int digit;
    if (c >= '0' && c <= '9') digit = c - '0';
    else if (base == 16 && c >= 'a' && c <= 'f') digit = c - 'a' + 10;
    else if (base == 16 && c >= 'A' && c <= 'F') digit = c - 'A' + 10;
    else return false;
    value = value * static_cast<uint64_t>(base) + static_cast<uint64_t>(digit);
  }
  return true;
}

}  // namespace

SmartPower3Channel parseSmartPower3Channel(const std::string& name) {
  if (name == "1") return SmartPower3Channel::output1;
  if (name == "2") return SmartPower3Channel::output2;
  if (name == "both") return SmartPower3Channel::both;
  if (name == "input") return SmartPower3Channel::input;
  throw Error("smartpower3.channel \"" + name + "\" must be \"1\", \"2\", \"both\" or \"input\"");
}

LineResult parseSmartPower3Line(std::string_view line, SmartPower3Channel channel, LineReading& reading) {
  std::string_view fields[kFields];
  size_t count = 0, start = 0, checksummedBytes = 0;
  for (;;) {
    const size_t comma = line.find(',', start);
    if (count == kFields) return LineResult::skipped;
    if (count == kFirstChecksumField) checksummedBytes = start;
    fields[count++] = line.substr(start, comma == std::string_view::npos ? line.npos : comma - start);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (count != kFields) return LineResult::skipped;
  uint64_t v[kFields];
  for (size_t i = 0; i < kFields; ++i) {
    const bool hex = i == 9 || i == 14 || i >= kFirstChecksumField;
    if (!parseUnsigned(fields[i], hex ? 16 : 10, v[i])) return LineResult::skipped;
  }
  uint8_t sum = 0, xorSum = 0;
  for (size_t i = 0; i < checksummedBytes; ++i) {
    sum = static_cast<uint8_t>(sum + static_cast<uint8_t>(line[i]));
    xorSum = static_cast<uint8_t>(xorSum ^ static_cast<uint8_t>(line[i]));
  }
  const uint8_t twosComplement = static_cast<uint8_t>(~sum + 1);
  if (v[15] != twosComplement || v[16] != xorSum) return LineResult::checksumError;

  reading = LineReading{};
  reading.deviceMs = static_cast<int64_t>(v[0]);
  auto take = [&](size_t first) {  // first = index of the mV field of a group
    reading.volts = static_cast<double>(v[first]) * 1e-3;
    reading.amps = static_cast<double>(v[first + 1]) * 1e-3;
    reading.watts = static_cast<double>(v[first + 2]) * 1e-3;
  };
  switch (channel) {
    case SmartPower3Channel::input: take(1); break;
    case SmartPower3Channel::output1: take(5); break;
    case SmartPower3Channel::output2: take(10); break;
    case SmartPower3Channel::both:
      reading.watts = static_cast<double>(v[7] + v[12]) * 1e-3;
      break;
  }
  return LineResult::sample;
}

void SmartPower3Settings::read(ConfigReader& r, bool) {
  r.string("device", device);
  r.integer("baud", baud, 9600, 921600);
  r.string("channel", channel, {"1", "2", "both", "input"});
  r.integer("log_interval_ms", logIntervalMs, 5, 1000);
  if (device.empty()) r.fail("device", "a serial device path such as \"/dev/ttyUSB0\"");
  if (!isSupportedBaud(baud))
    r.fail("baud", "a supported baud rate (the SmartPower3 offers 9600 ... 921600; 921600 by default)");
}

nlohmann::json SmartPower3Settings::toJson() const {
  return {{"device", device}, {"baud", baud}, {"channel", channel}, {"log_interval_ms", logIntervalMs}};
}

std::unique_ptr<Meter> openSmartPower3(const SmartPower3Settings& settings, const MeterHostSettings& host,
                                       const Clock& clock) {
  const SmartPower3Channel channel = parseSmartPower3Channel(settings.channel);
  SerialLineOptions o;
  o.name = "smartpower3";
  o.device = settings.device;
  o.baud = settings.baud;
  o.nominalPeriodNs = int64_t(settings.logIntervalMs) * 1'000'000;
  o.reopenMinNs = int64_t(host.reopenMinMs) * 1'000'000;
  o.reopenMaxNs = int64_t(host.reopenMaxMs) * 1'000'000;
  auto parser = [channel](std::string_view line, LineReading& reading) {
    return parseSmartPower3Line(line, channel, reading);
  };
  return std::make_unique<SerialLineMeter>(o, parser, clock);
}

}  // namespace sb::power
