// SmartPower (v1): the HID reply parser through its seam (no USB device needed), the access-denied message,
// and a clear error when no device is present.

#include <catch2/catch.hpp>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.h"
#include "power/clock.h"
#include "power/smartpower1.h"
#include "power/smartpower1_reply.h"

using namespace sb::power;

namespace {

// A 64-byte report as the device sends it: the echoed request byte, ASCII text, then padding.
std::vector<uint8_t> report(const std::string& text, uint8_t padding = 0) {
  std::vector<uint8_t> r(64, padding);
  std::memcpy(r.data(), text.data(), std::min<size_t>(text.size(), 64));
  return r;
}

}  // namespace

TEST_CASE("smartpower1 reply parser reads volts, amps and watts", "[power][smartpower1]") {
  auto r = report("7 5.000V  0.302 A 1.510W  0.012Wh");
  auto reading = parseSmartPower1Reply(r.data(), r.size());
  REQUIRE(reading);
  CHECK(reading->volts == Approx(5.0));
  CHECK(reading->amps == Approx(0.302));
  CHECK(reading->watts == Approx(1.510));
  CHECK(reading->outputOn);

  r = report("7 5.213V  2.104 A11.031W 12.345Wh", 0xff);  // two-digit watts fill the field; 0xff padding
  reading = parseSmartPower1Reply(r.data(), r.size());
  REQUIRE(reading);
  CHECK(reading->watts == Approx(11.031));
  CHECK(reading->amps == Approx(2.104));
}

TEST_CASE("smartpower1 reply parser: output off reads as 0 W, other replies are refused", "[power][smartpower1]") {
  auto r = report("7 5.000V  -.--- A -.---W  -.---Wh");
  auto reading = parseSmartPower1Reply(r.data(), r.size());
  REQUIRE(reading);
  CHECK_FALSE(reading->outputOn);
  CHECK(reading->watts == 0.0);
  CHECK(reading->volts == Approx(5.0));

  for (const std::string& text : {std::string("8 5.000V  0.302 A 1.510W  0.012Wh"),  // another request's reply
                                  std::string("7 5.000V"), std::string("7 5.000V  0.302 A"),
                                  std::string("7 -.---V  0.302 A 1.510W"), std::string("7 5.0.0V  0.302 A 1.510W"),
                                  std::string("7 5.000V  0.302 A -.---W"), std::string("7 garbage")}) {
    INFO(text);
    r = report(text);
    CHECK_FALSE(parseSmartPower1Reply(r.data(), r.size()));
  }
  CHECK_FALSE(parseSmartPower1Reply(nullptr, 0));
  r = report("7 5.000V  0.302 A 1.510W");
  CHECK_FALSE(parseSmartPower1Reply(r.data(), 1));
}

TEST_CASE("smartpower1: access denied names the udev rule; no device is a clear error", "[power][smartpower1]") {
  const std::string denied = smartPower1OpenError("cannot open the SmartPower (USB 04d8:003f): LIBUSB_ERROR_ACCESS", true);
  CHECK(denied.find(smartPower1UdevRule()) != std::string::npos);
  CHECK(denied.find("/etc/udev/rules.d/") != std::string::npos);
  CHECK(denied.find("plugdev") != std::string::npos);
  CHECK(std::string(smartPower1UdevRule()).find("ATTRS{idVendor}==\"04d8\", ATTRS{idProduct}==\"003f\"") !=
        std::string::npos);
  CHECK(smartPower1OpenError("x", false).find("udev") == std::string::npos);

  // This machine has no SmartPower (if it ever has one, the meter must work instead).
  SmartPower1Settings c;
  try {
    auto meter = openSmartPower1(c, {}, monotonicClock());
    std::vector<PowerSample> samples;
    meter->poll(samples);
    WARN("a SmartPower is attached: read " << samples.size() << " sample(s)");
  } catch (const sb::Error& e) {
    CHECK(std::string(e.what()).find("smartpower1 meter (USB 04d8:003f)") != std::string::npos);
  }
}
