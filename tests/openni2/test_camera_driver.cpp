// A test-only OpenNI2 driver (loaded by libOpenNI2 from its driver repository, see CMakeLists.txt): a depth
// camera without a sensor that streams the box room of room_scene.h, deterministically.
//
// Devices: those named by the environment variable SB_TESTCAM_ANNOUNCE (URIs separated by ';'; unset: one,
// "sbtest://cam") are announced at start-up; any other "sbtest://NAME?PARAMS" URI opens on demand. NAME
// "busy" and "denied" fail to open the way the PrimeSense driver does (its error texts); "absent" does not
// exist. PARAMS (key=value joined by '&'):
//   disconnect_after=N  after N frames the camera is unplugged (once): frames stop, the driver reports the
//                       disconnect, and the camera reappears unplugged_ms later (default 500)
//   drop_every=K        every K-th device frame number is skipped (a frame lost on the wire)
//   freeze_after=N      after N frames the stream goes silent (once), with no disconnect reported
// Modes: 640x480@30, 320x240@30 and 320x240@60 in 1 mm units, 160x120@30 in 100 um units only. Like a
// PrimeSense camera it starts mirrored and with depth-to-colour registration on (registration shifts the
// image 8 pixels); the frames match room_scene.h only when both are off.
// The environment is read here only: this is test equipment, not product code.

#include <Driver/OniDriverAPI.h>

#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "tests/openni2/room_scene.h"

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kRegistrationShiftPx = 8;

struct UriParams {
  std::string name;
  int disconnectAfter = 0;
  int unpluggedMs = 500;
  int dropEvery = 0;
  int freezeAfter = 0;
};

UriParams parseUri(const std::string& uri) {
  UriParams p;
  const std::string prefix = "sbtest://";
  const std::string rest = uri.substr(prefix.size());
  const auto q = rest.find('?');
  p.name = rest.substr(0, q);
  std::string query = q == std::string::npos ? "" : rest.substr(q + 1);
  while (!query.empty()) {
    const auto amp = query.find('&');
    const std::string kv = query.substr(0, amp);
    query = amp == std::string::npos ? "" : query.substr(amp + 1);
    const auto eq = kv.find('=');
    if (eq == std::string::npos) continue;
    const int value = std::atoi(kv.c_str() + eq + 1);
    const std::string key = kv.substr(0, eq);
    if (key == "disconnect_after") p.disconnectAfter = value;
    if (key == "unplugged_ms") p.unpluggedMs = value;
    if (key == "drop_every") p.dropEvery = value;
    if (key == "freeze_after") p.freezeAfter = value;
  }
  return p;
}

OniVideoMode mode(int w, int h, int fps, OniPixelFormat f) {
  OniVideoMode m;
  m.resolutionX = w;
  m.resolutionY = h;
  m.fps = fps;
  m.pixelFormat = f;
  return m;
}

OniVideoMode g_modes[] = {mode(640, 480, 30, ONI_PIXEL_FORMAT_DEPTH_1_MM), mode(320, 240, 30, ONI_PIXEL_FORMAT_DEPTH_1_MM),
                          mode(320, 240, 60, ONI_PIXEL_FORMAT_DEPTH_1_MM),
                          mode(160, 120, 30, ONI_PIXEL_FORMAT_DEPTH_100_UM)};

class TestDriver;

// Per-URI state that outlives a device: plugged in or not, how often unplugged, where the camera is.
struct UriState {
  bool unplugged = false;
  int unplugs = 0;
  int freezes = 0;
  long shots = 0;  // device frames numbered so far, over every connection (the camera position)
};

class DepthStream : public oni::driver::StreamBase {
 public:
  DepthStream(TestDriver& driver, std::string uri, const bool& registration)
      : driver_(driver), uri_(std::move(uri)), params_(parseUri(uri_)), registration_(registration) {}
  ~DepthStream() override { stop(); }

  OniStatus start() override {
    running_ = true;
    thread_ = std::thread([this] { run(); });
    return ONI_STATUS_OK;
  }
  void stop() override {
    {
      std::lock_guard lock(mutex_);
      running_ = false;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  int getRequiredFrameSize() override { return mode_.resolutionX * mode_.resolutionY * 2; }

  OniBool isPropertySupported(int id) override {
    return id == ONI_STREAM_PROPERTY_VIDEO_MODE || id == ONI_STREAM_PROPERTY_MIRRORING ||
           id == ONI_STREAM_PROPERTY_HORIZONTAL_FOV || id == ONI_STREAM_PROPERTY_VERTICAL_FOV;
  }
  OniStatus getProperty(int id, void* data, int* size) override {
    if (id == ONI_STREAM_PROPERTY_VIDEO_MODE && *size == sizeof(OniVideoMode)) {
      *static_cast<OniVideoMode*>(data) = mode_;
    } else if (id == ONI_STREAM_PROPERTY_MIRRORING && *size == sizeof(OniBool)) {
      *static_cast<OniBool*>(data) = mirroring_;
    } else if (id == ONI_STREAM_PROPERTY_HORIZONTAL_FOV && *size == sizeof(float)) {
      *static_cast<float*>(data) = static_cast<float>(sb::test::kHorizontalFovRad);
    } else if (id == ONI_STREAM_PROPERTY_VERTICAL_FOV && *size == sizeof(float)) {
      *static_cast<float*>(data) = static_cast<float>(sb::test::kVerticalFovRad);
    } else {
      return ONI_STATUS_NOT_SUPPORTED;
    }
    return ONI_STATUS_OK;
  }
  OniStatus setProperty(int id, const void* data, int size) override {
    if (id == ONI_STREAM_PROPERTY_MIRRORING && size == sizeof(OniBool)) {
      mirroring_ = *static_cast<const OniBool*>(data);
      return ONI_STATUS_OK;
    }
    if (id == ONI_STREAM_PROPERTY_VIDEO_MODE && size == sizeof(OniVideoMode)) {
      const auto& m = *static_cast<const OniVideoMode*>(data);
      for (const auto& s : g_modes)
        if (s.resolutionX == m.resolutionX && s.resolutionY == m.resolutionY && s.fps == m.fps &&
            s.pixelFormat == m.pixelFormat) {
          mode_ = m;
          return ONI_STATUS_OK;
        }
      return ONI_STATUS_BAD_PARAMETER;
    }
    return ONI_STATUS_NOT_SUPPORTED;
  }

 private:
  void run();

  TestDriver& driver_;
  std::string uri_;
  UriParams params_;
  const bool& registration_;
  OniVideoMode mode_ = g_modes[0];
  OniBool mirroring_ = TRUE;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool running_ = false;
  std::thread thread_;
};

class Device : public oni::driver::DeviceBase {
 public:
  Device(TestDriver& driver, std::string uri) : driver_(driver), uri_(std::move(uri)) {
    sensor_.sensorType = ONI_SENSOR_DEPTH;
    sensor_.numSupportedVideoModes = sizeof g_modes / sizeof g_modes[0];
    sensor_.pSupportedVideoModes = g_modes;
  }
  OniStatus getSensorInfoList(OniSensorInfo** infos, int* count) override {
    *infos = &sensor_;
    *count = 1;
    return ONI_STATUS_OK;
  }
  oni::driver::StreamBase* createStream(OniSensorType type) override {
    return type == ONI_SENSOR_DEPTH ? new DepthStream(driver_, uri_, registration_) : nullptr;
  }
  void destroyStream(oni::driver::StreamBase* stream) override { delete stream; }
  OniBool isImageRegistrationModeSupported(OniImageRegistrationMode) override { return TRUE; }
  OniBool isPropertySupported(int id) override { return id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION; }
  OniStatus setProperty(int id, const void* data, int size) override {
    if (id != ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION || size != sizeof(OniImageRegistrationMode))
      return ONI_STATUS_NOT_SUPPORTED;
    registration_ = *static_cast<const OniImageRegistrationMode*>(data) != ONI_IMAGE_REGISTRATION_OFF;
    return ONI_STATUS_OK;
  }
  OniStatus getProperty(int id, void* data, int* size) override {
    if (id != ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION || *size != sizeof(OniImageRegistrationMode))
      return ONI_STATUS_NOT_SUPPORTED;
    *static_cast<OniImageRegistrationMode*>(data) =
        registration_ ? ONI_IMAGE_REGISTRATION_DEPTH_TO_COLOR : ONI_IMAGE_REGISTRATION_OFF;
    return ONI_STATUS_OK;
  }

 private:
  TestDriver& driver_;
  std::string uri_;
  OniSensorInfo sensor_{};
  bool registration_ = true;
};

class TestDriver : public oni::driver::DriverBase {
 public:
  explicit TestDriver(OniDriverServices* services) : DriverBase(services) {}

  OniStatus initialize(oni::driver::DeviceConnectedCallback connected, oni::driver::DeviceDisconnectedCallback
                       disconnected, oni::driver::DeviceStateChangedCallback changed, void* cookie) override {
    DriverBase::initialize(connected, disconnected, changed, cookie);
    hotplug_ = std::thread([this] { runHotplug(); });
    const char* announce = std::getenv("SB_TESTCAM_ANNOUNCE");
    std::string list = announce ? announce : "sbtest://cam";
    while (!list.empty()) {
      const auto semi = list.find(';');
      const std::string uri = list.substr(0, semi);
      list = semi == std::string::npos ? "" : list.substr(semi + 1);
      if (uri.rfind("sbtest://", 0) == 0) announce_(uri);
    }
    return ONI_STATUS_OK;
  }

  OniStatus tryDevice(const char* uri) override {
    const std::string u = uri ? uri : "";
    if (u.rfind("sbtest://", 0) != 0 || parseUri(u).name == "absent") return ONI_STATUS_ERROR;
    {
      std::lock_guard lock(mutex_);
      if (uris_[u].unplugged) return ONI_STATUS_ERROR;
    }
    announce_(u);
    return ONI_STATUS_OK;
  }

  oni::driver::DeviceBase* deviceOpen(const char* uri, const char*) override {
    const std::string u = uri ? uri : "";
    const std::string name = u.rfind("sbtest://", 0) == 0 ? parseUri(u).name : "";
    if (name == "busy") {
      getServices().errorLoggerAppend("Could not open \"%s\": Failed to set USB interface!", uri);
      return nullptr;
    }
    if (name == "denied") {
      getServices().errorLoggerAppend("Could not open \"%s\": Failed to open the USB device!", uri);
      return nullptr;
    }
    std::lock_guard lock(mutex_);
    if (name.empty() || uris_[u].unplugged) {
      getServices().errorLoggerAppend("Could not open \"%s\": USB device not found", uri);
      return nullptr;
    }
    return new Device(*this, u);
  }
  void deviceClose(oni::driver::DeviceBase* device) override { delete device; }

  void shutdown() override {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    if (hotplug_.joinable()) hotplug_.join();
  }

  // Called by a stream: the next device frame number (false once the camera is unplugged).
  bool nextShot(const std::string& uri, const UriParams& p, int framesSent, long* shot) {
    std::lock_guard lock(mutex_);
    UriState& s = uris_[uri];
    if (s.unplugged) return false;
    if (p.disconnectAfter > 0 && framesSent >= p.disconnectAfter && s.unplugs == 0) {
      s.unplugged = true;
      ++s.unplugs;
      const auto now = Clock::now();
      events_.push_back({now, uri, false});
      events_.push_back({now + std::chrono::milliseconds(p.unpluggedMs), uri, true});
      wake_.notify_all();
      return false;
    }
    if (p.freezeAfter > 0 && framesSent >= p.freezeAfter && s.freezes == 0) {
      ++s.freezes;
      return false;
    }
    *shot = s.shots++;
    return true;
  }

 private:
  struct Event {
    Clock::time_point due;
    std::string uri;
    bool plug;  // true: reappears; false: disconnects
  };

  static OniDeviceInfo describe(const std::string& uri) {
    OniDeviceInfo info{};
    std::strncpy(info.uri, uri.c_str(), ONI_MAX_STR - 1);
    std::strncpy(info.vendor, "SLAMBooster tests", ONI_MAX_STR - 1);
    std::strncpy(info.name, "synthetic box room", ONI_MAX_STR - 1);
    return info;
  }
  void announce_(const std::string& uri) {
    const OniDeviceInfo info = describe(uri);
    deviceConnected(&info);
  }

  // Hot-plug events are raised from this thread, never from a stream's thread (as a USB driver does).
  void runHotplug() {
    std::unique_lock lock(mutex_);
    while (!stopping_) {
      if (events_.empty()) {
        wake_.wait(lock);
        continue;
      }
      const Event e = events_.front();
      if (Clock::now() < e.due) {
        wake_.wait_until(lock, e.due);
        continue;
      }
      events_.pop_front();
      if (e.plug) uris_[e.uri].unplugged = false;
      lock.unlock();
      const OniDeviceInfo info = describe(e.uri);
      if (e.plug) {
        deviceConnected(&info);
      } else {
        deviceDisconnected(&info);
      }
      lock.lock();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::map<std::string, UriState> uris_;
  std::deque<Event> events_;
  bool stopping_ = false;
  std::thread hotplug_;
};

void DepthStream::run() {
  const int w = mode_.resolutionX, h = mode_.resolutionY, fps = mode_.fps;
  const double units = mode_.pixelFormat == ONI_PIXEL_FORMAT_DEPTH_100_UM ? 10000.0 : 1000.0;
  const auto start = Clock::now();
  const uint64_t startMicros = 7000000000ull;  // the device clock has nothing to do with the host's
  int deviceIndex = 0, sent = 0;
  while (true) {
    long shot = 0;
    if (!driver_.nextShot(uri_, params_, sent, &shot)) return;  // unplugged: no more frames
    ++deviceIndex;
    if (params_.dropEvery > 0 && deviceIndex % params_.dropEvery == 0) continue;  // lost on the wire
    {
      std::unique_lock lock(mutex_);
      const auto due = start + std::chrono::microseconds(static_cast<long>(1e6 * sent / fps));
      if (wake_.wait_until(lock, due, [&] { return !running_; })) return;
    }
    OniFrame* frame = getServices().acquireFrame();
    if (!frame) continue;
    auto* depth = static_cast<uint16_t*>(frame->data);
    const double cameraX = sb::test::kStepMetres * static_cast<double>(shot);
    const int shift = registration_ ? kRegistrationShiftPx : 0;
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        const int su = mirroring_ ? w - 1 - u : u;
        depth[v * w + u] = su + shift < w ? sb::test::roomDepthRaw(su + shift, v, w, h, cameraX, units) : 0;
      }
    frame->dataSize = w * h * 2;
    frame->sensorType = ONI_SENSOR_DEPTH;
    frame->frameIndex = deviceIndex;
    frame->timestamp = startMicros + static_cast<uint64_t>(1e6 * (deviceIndex - 1) / fps);
    frame->videoMode = mode_;
    frame->width = w;
    frame->height = h;
    frame->croppingEnabled = FALSE;
    frame->cropOriginX = frame->cropOriginY = 0;
    frame->stride = w * 2;
    raiseNewFrame(frame);
    getServices().releaseFrame(frame);
    ++sent;
  }
}

}  // namespace

#define XN_NEW(type, arg) new type(arg)
#define XN_DELETE(p) delete (p)
ONI_EXPORT_DRIVER(TestDriver)
