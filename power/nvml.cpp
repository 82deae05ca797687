#include "power/nvml.h"

#include <dlfcn.h>

#include <string>

#include "core/error.h"
#include "power/energy_counter.h"

namespace sb::power {

namespace {

// The few NVML entry points used, declared by their C ABI (nvml.h is not needed to build).
using NvmlReturn = int;
using NvmlDevice = struct NvmlDeviceOpaque*;
constexpr NvmlReturn kNvmlSuccess = 0;

struct NvmlApi {
  NvmlReturn (*init)() = nullptr;
  NvmlReturn (*shutdown)() = nullptr;
  const char* (*errorString)(NvmlReturn) = nullptr;
  NvmlReturn (*handleByIndex)(unsigned, NvmlDevice*) = nullptr;
  NvmlReturn (*name)(NvmlDevice, char*, unsigned) = nullptr;
  NvmlReturn (*totalEnergy)(NvmlDevice, unsigned long long*) = nullptr;  // mJ since the driver loaded
  NvmlReturn (*powerUsage)(NvmlDevice, unsigned*) = nullptr;             // mW
};

class Library {
 public:
  explicit Library(const std::string& path) {
    handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle_) {
      const char* why = dlerror();
      throw Error("nvml meter: cannot load '" + path + "' (" + (why ? why : "unknown error") +
                  "): the NVIDIA driver's NVML library is not installed; install the NVIDIA driver (e.g. the "
                  "libnvidia-ml1 package) or set nvml.library to its path");
    }
  }
  ~Library() { dlclose(handle_); }
  Library(const Library&) = delete;
  Library& operator=(const Library&) = delete;

  template <typename F>
  void bind(F& function, const char* symbol, const std::string& path) {
    void* address = dlsym(handle_, symbol);
    if (!address) throw Error("nvml meter: '" + path + "' has no symbol " + symbol + " (too old a driver?)");
    function = reinterpret_cast<F>(address);
  }

 private:
  void* handle_ = nullptr;
};

class NvmlMeter final : public Meter {
 public:
  NvmlMeter(const NvmlSettings& config, const Clock& clock) : clock_(clock), library_(config.library), counter_(1e-3) {
    library_.bind(api_.init, "nvmlInit_v2", config.library);
    library_.bind(api_.shutdown, "nvmlShutdown", config.library);
    library_.bind(api_.errorString, "nvmlErrorString", config.library);
    library_.bind(api_.handleByIndex, "nvmlDeviceGetHandleByIndex_v2", config.library);
    library_.bind(api_.name, "nvmlDeviceGetName", config.library);
    library_.bind(api_.totalEnergy, "nvmlDeviceGetTotalEnergyConsumption", config.library);
    library_.bind(api_.powerUsage, "nvmlDeviceGetPowerUsage", config.library);
    check(api_.init(), "nvmlInit");
    initialised_ = true;
    check(api_.handleByIndex(static_cast<unsigned>(config.deviceIndex), &device_),
          "nvmlDeviceGetHandleByIndex(" + std::to_string(config.deviceIndex) + ")");
    char name[96] = {};
    api_.name(device_, name, sizeof name);
    info_.name = "nvml";
    info_.device = "gpu " + std::to_string(config.deviceIndex) + " (" + name + ")";
    info_.nominalPeriodNs = int64_t(config.pollIntervalMs) * 1'000'000;
    unsigned long long mJ = 0;
    useCounter_ = api_.totalEnergy(device_, &mJ) == kNvmlSuccess;
    info_.kind = useCounter_ ? SampleKind::intervalAverage : SampleKind::instantaneous;
    if (useCounter_) counter_.update(clock_.nowNs(), mJ);
    status_.sinceNs = clock_.nowNs();
  }
  ~NvmlMeter() override {
    if (initialised_) api_.shutdown();
  }

  const MeterInfo& info() const override { return info_; }
  MeterStatus status() const override { return status_; }

  void poll(std::vector<PowerSample>& out) override {
    const int64_t now = clock_.nowNs();
    if (useCounter_) {
      unsigned long long mJ = 0;
      check(api_.totalEnergy(device_, &mJ), "nvmlDeviceGetTotalEnergyConsumption");
      if (auto s = counter_.update(now, mJ)) push(*s, out);
      return;
    }
    unsigned mW = 0;
    check(api_.powerUsage(device_, &mW), "nvmlDeviceGetPowerUsage");
    PowerSample s;
    s.tNs = now;
    s.watts = mW * 1e-3;
    if (now > lastNs_) push(s, out);
  }

 private:
  void push(const PowerSample& s, std::vector<PowerSample>& out) {
    lastNs_ = s.tNs;
    ++status_.samples;
    out.push_back(s);
  }
  void check(NvmlReturn rc, const std::string& call) const {
    if (rc != kNvmlSuccess)
      throw Error("nvml meter: " + call + " failed: " + (api_.errorString ? api_.errorString(rc) : "error") +
                  " (code " + std::to_string(rc) + ")");
  }

  const Clock& clock_;
  Library library_;
  NvmlApi api_;
  bool initialised_ = false;
  NvmlDevice device_ = nullptr;
  MeterInfo info_;
  MeterStatus status_;
  EnergyCounter counter_;
  bool useCounter_ = false;
  int64_t lastNs_ = 0;
};

}  // namespace

void NvmlSettings::read(ConfigReader& r, bool) {
  r.string("library", library);
  r.integer("device_index", deviceIndex, 0, 63);
  r.integer("poll_interval_ms", pollIntervalMs, 1, 10000);
}

nlohmann::json NvmlSettings::toJson() const {
  return {{"library", library}, {"device_index", deviceIndex}, {"poll_interval_ms", pollIntervalMs}};
}

std::unique_ptr<Meter> openNvml(const NvmlSettings& settings, const MeterHostSettings&, const Clock& clock) {
  return std::make_unique<NvmlMeter>(settings, clock);
}

}  // namespace sb::power
