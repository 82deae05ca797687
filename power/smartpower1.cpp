// The only file that includes libusb.h.
#include "power/smartpower1.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "core/error.h"
#include "power/smartpower1_reply.h"

#if SB_HAVE_LIBUSB
#include <libusb.h>
#endif

namespace sb::power {

void SmartPower1Settings::read(ConfigReader& r, bool) { r.integer("poll_interval_ms", pollIntervalMs, 10, 10000); }

nlohmann::json SmartPower1Settings::toJson() const { return {{"poll_interval_ms", pollIntervalMs}}; }

const char* smartPower1UdevRule() {
  return "SUBSYSTEM==\"usb\", ATTRS{idVendor}==\"04d8\", ATTRS{idProduct}==\"003f\", MODE=\"0660\", GROUP=\"plugdev\"";
}

std::string smartPower1OpenError(const std::string& error, bool accessDenied) {
  std::string message = "smartpower1 meter (USB 04d8:003f): " + error;
  if (accessDenied)
    message += ". The user needs write access to the device: install the udev rule\n  " +
               std::string(smartPower1UdevRule()) +
               "\nas /etc/udev/rules.d/99-slambooster-smartpower.rules, add the user to the 'plugdev' group, run "
               "'sudo udevadm control --reload' and replug the meter";
  return message;
}

#if SB_HAVE_LIBUSB

namespace {

constexpr int kReportBytes = 64;
constexpr unsigned kTimeoutMs = 100;

std::string usbError(int code) { return libusb_error_name(code); }

struct UsbContext {
  libusb_context* ctx = nullptr;
  UsbContext() {
    const int rc = libusb_init(&ctx);
    if (rc != 0) throw Error(smartPower1OpenError("libusb_init failed: " + usbError(rc), false));
  }
  ~UsbContext() { libusb_exit(ctx); }
  UsbContext(const UsbContext&) = delete;
  UsbContext& operator=(const UsbContext&) = delete;
};

// An open, claimed SmartPower with its interrupt endpoints.
struct UsbDevice {
  libusb_device_handle* handle = nullptr;
  unsigned char in = 0, out = 0;
  ~UsbDevice() {
    if (handle) {
      libusb_release_interface(handle, 0);
      libusb_close(handle);
    }
  }
};

// Opens the first 04d8:003f device. Returns nullptr with `error` set when there is none or it cannot be used.
std::unique_ptr<UsbDevice> openDevice(libusb_context* ctx, std::string& error, bool& accessDenied) {
  accessDenied = false;
  libusb_device** list = nullptr;
  const ssize_t count = libusb_get_device_list(ctx, &list);
  if (count < 0) {
    error = "cannot list USB devices: " + usbError(static_cast<int>(count));
    return nullptr;
  }
  std::unique_ptr<UsbDevice> device;
  error = "no SmartPower (USB 04d8:003f) found: is it plugged in? ('lsusb -d 04d8:003f' lists it)";
  for (ssize_t i = 0; i < count && !device; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
    if (d.idVendor != kSmartPower1Vendor || d.idProduct != kSmartPower1Product) continue;
    auto candidate = std::make_unique<UsbDevice>();
    const int rc = libusb_open(list[i], &candidate->handle);
    if (rc != 0) {
      candidate->handle = nullptr;
      accessDenied = rc == LIBUSB_ERROR_ACCESS;
      error = "cannot open the SmartPower (USB 04d8:003f): " + usbError(rc);
      continue;
    }
    libusb_config_descriptor* config = nullptr;
    if (libusb_get_active_config_descriptor(list[i], &config) == 0 && config->bNumInterfaces > 0 &&
        config->interface[0].num_altsetting > 0) {
      const libusb_interface_descriptor& alt = config->interface[0].altsetting[0];
      for (int e = 0; e < alt.bNumEndpoints; ++e) {
        const libusb_endpoint_descriptor& ep = alt.endpoint[e];
        if ((ep.bmAttributes & 0x03) != LIBUSB_TRANSFER_TYPE_INTERRUPT) continue;
        ((ep.bEndpointAddress & LIBUSB_ENDPOINT_IN) ? candidate->in : candidate->out) = ep.bEndpointAddress;
      }
    }
    if (config) libusb_free_config_descriptor(config);
    if (candidate->in == 0 || candidate->out == 0) {
      error = "the USB device 04d8:003f has no interrupt IN/OUT endpoints: not a SmartPower?";
      continue;
    }
    libusb_set_auto_detach_kernel_driver(candidate->handle, 1);
    const int claim = libusb_claim_interface(candidate->handle, 0);
    if (claim != 0) {
      accessDenied = claim == LIBUSB_ERROR_ACCESS;
      error = "cannot claim the SmartPower's HID interface: " + usbError(claim) +
              (claim == LIBUSB_ERROR_BUSY ? " (another program uses it)" : "");
      continue;  // the UsbDevice destructor closes it
    }
    device = std::move(candidate);
  }
  libusb_free_device_list(list, 1);
  return device;
}

class SmartPower1Meter final : public Meter {
 public:
  SmartPower1Meter(const SmartPower1Settings& settings, const MeterHostSettings& host, const Clock& clock)
      : clock_(clock) {
    info_.name = "smartpower1";
    info_.device = "usb:04d8:003f";
    info_.kind = SampleKind::instantaneous;
    info_.nominalPeriodNs = int64_t(settings.pollIntervalMs) * 1'000'000;
    reopenMinNs_ = int64_t(host.reopenMinMs) * 1'000'000;
    reopenMaxNs_ = int64_t(host.reopenMaxMs) * 1'000'000;
    std::string error;
    bool denied = false;
    device_ = openDevice(usb_.ctx, error, denied);
    if (!device_) throw Error(smartPower1OpenError(error, denied));
    status_.sinceNs = clock_.nowNs();
  }

  const MeterInfo& info() const override { return info_; }
  MeterStatus status() const override { return status_; }

  void poll(std::vector<PowerSample>& out) override {
    const int64_t now = clock_.nowNs();
    if (!device_) {
      if (now < nextRetryNs_) return;
      std::string error;
      bool denied = false;
      device_ = openDevice(usb_.ctx, error, denied);
      if (!device_) {
        backoffNs_ = std::min(reopenMaxNs_, backoffNs_ * 2);
        nextRetryNs_ = now + backoffNs_;
        status_.message = error;
        return;
      }
      spdlog::info("smartpower1 meter: device back after {:.1f} s", nsToSeconds(now - status_.sinceNs));
      status_.connected = true;
      status_.sinceNs = now;
      status_.message.clear();
      ++status_.reconnects;
    }
    unsigned char report[kReportBytes] = {kSmartPower1RequestData};
    int transferred = 0;
    int rc = libusb_interrupt_transfer(device_->handle, device_->out, report, kReportBytes, &transferred, kTimeoutMs);
    if (rc == 0) {
      std::fill(report, report + kReportBytes, 0);
      rc = libusb_interrupt_transfer(device_->handle, device_->in, report, kReportBytes, &transferred, kTimeoutMs);
    }
    if (rc == LIBUSB_ERROR_NO_DEVICE || rc == LIBUSB_ERROR_IO || rc == LIBUSB_ERROR_PIPE) {
      lose(usbError(rc));
      return;
    }
    if (rc != 0) {  // a timeout: no reply this time
      ++status_.rejected;
      return;
    }
    const auto reading = parseSmartPower1Reply(report, static_cast<size_t>(transferred));
    if (!reading) {
      ++status_.rejected;
      return;
    }
    PowerSample s;
    s.tNs = clock_.nowNs();
    if (s.tNs <= lastSampleNs_) return;
    s.watts = reading->watts;
    s.volts = reading->volts;
    s.amps = reading->amps;
    s.gapBefore = gapPending_;
    gapPending_ = false;
    lastSampleNs_ = s.tNs;
    ++status_.samples;
    out.push_back(s);
  }

 private:
  void lose(const std::string& why) {
    device_.reset();
    status_.connected = false;
    status_.sinceNs = clock_.nowNs();
    status_.message = why;
    backoffNs_ = reopenMinNs_;
    nextRetryNs_ = status_.sinceNs + backoffNs_;
    gapPending_ = true;
    spdlog::warn("smartpower1 meter: device lost ({}); reopening with backoff", why);
  }

  const Clock& clock_;
  MeterInfo info_;
  MeterStatus status_;
  UsbContext usb_;
  std::unique_ptr<UsbDevice> device_;
  int64_t reopenMinNs_ = 0, reopenMaxNs_ = 0, backoffNs_ = 0, nextRetryNs_ = 0, lastSampleNs_ = 0;
  bool gapPending_ = false;
};

}  // namespace

std::unique_ptr<Meter> openSmartPower1(const SmartPower1Settings& settings, const MeterHostSettings& host,
                                       const Clock& clock) {
  return std::make_unique<SmartPower1Meter>(settings, host, clock);
}

#else  // built without libusb-1.0

std::unique_ptr<Meter> openSmartPower1(const SmartPower1Settings&, const MeterHostSettings&, const Clock&) {
  throw Error(smartPower1OpenError("this build has no libusb-1.0 support; install libusb-1.0-0-dev and rebuild", false));
}

#endif

}  // namespace sb::power
