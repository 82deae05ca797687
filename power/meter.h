#pragma once
// The power meter interface (chrony's driver/host split): a driver only reads its device and returns
// timestamped samples; the energy ledger (energy_ledger.h) does all accounting. A new meter is one file pair
// plus one line in meter_registry.cpp: the pair holds the driver and its settings (a struct with
// read(ConfigReader&, bool selected) for its section of the power config, and toJson(); see meter_registry.h).
//
// Threading: a Meter is used by one thread at a time (the sampler's); it never blocks for long in poll().

#include <cstdint>
#include <string>
#include <vector>

#include "power/sample.h"

namespace sb::power {

struct MeterInfo {
  std::string name;              // registry name, e.g. "smartpower2"
  std::string device;            // what it reads, e.g. "/dev/ttyUSB0" or "/sys/class/powercap/intel-rapl:0"
  SampleKind kind = SampleKind::instantaneous;
  int64_t nominalPeriodNs = 0;   // expected time between samples (sets the default gap limit and poll rate)
};

// What the driver knows about its device right now.
struct MeterStatus {
  bool connected = true;         // false while the device is gone (unplugged) and being reopened
  int64_t sinceNs = 0;           // when `connected` last changed (the gap starts at the last sample before it)
  std::string message;           // why it is disconnected, or empty
  uint64_t samples = 0;          // samples returned so far
  uint64_t rejected = 0;         // lines/replies skipped: banner, debug output, garbage, partial lines
  uint64_t checksumErrors = 0;   // lines refused because their checksum did not match (meters with checksums)
  uint64_t reconnects = 0;       // successful reopen after a loss
};

// What the host's power config gives every meter besides the meter's own settings (power_config.h).
struct MeterHostSettings {
  int reopenMinMs = 250;         // ms: first retry after a device is lost; doubles up to reopenMaxMs
  int reopenMaxMs = 8000;
};

class Meter {
 public:
  virtual ~Meter() = default;

  virtual const MeterInfo& info() const = 0;

  // Reads what the device has now without blocking for long and appends the new samples (in time order,
  // timestamped when read). Device loss is not an exception: it shows in status(), and the first sample after
  // the device is back has gapBefore set. Throws sb::Error only for failures a user must fix.
  virtual void poll(std::vector<PowerSample>& out) = 0;

  virtual MeterStatus status() const = 0;

  // A descriptor that becomes readable when poll() has something to read, or -1: then poll at the period.
  virtual int waitFd() const { return -1; }

  // How long the sampler may wait before calling poll() again, ns.
  virtual int64_t pollPeriodNs() const { return info().nominalPeriodNs; }
};

}  // namespace sb::power
