// `slambooster record`: write what an OpenNI2 depth camera sees as a TUM-layout sequence (depth/*.png,
// depth.txt, calibration.json), to build trajectory sets of one's own. Stops after --frames N, after
// --seconds S, or at Ctrl-C / SIGTERM; the frames written so far are always a complete, readable sequence.

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <optional>

#include "core/error.h"
#include "drivers/openni2_source.h"
#include "drivers/tum_writer.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {

namespace {

struct RecordArgs {
  std::string out;
  OpenNI2Options camera;
  size_t frames = 0;
  double seconds = 0.0;
  bool overwrite = false;
};

std::atomic<OpenNI2Source*> g_recording{nullptr};

extern "C" void onStopSignal(int) {
  if (OpenNI2Source* s = g_recording.load()) s->stop();  // async-signal-safe: sets a flag
}

// Installs the SIGINT/SIGTERM handler for the lifetime of a recording, and restores the previous ones.
class StopOnSignal {
 public:
  explicit StopOnSignal(OpenNI2Source& source) {
    g_recording = &source;
    struct sigaction sa {};
    sa.sa_handler = onStopSignal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &oldInt_);
    sigaction(SIGTERM, &sa, &oldTerm_);
  }
  ~StopOnSignal() {
    sigaction(SIGINT, &oldInt_, nullptr);
    sigaction(SIGTERM, &oldTerm_, nullptr);
    g_recording = nullptr;
  }
  StopOnSignal(const StopOnSignal&) = delete;
  StopOnSignal& operator=(const StopOnSignal&) = delete;

 private:
  struct sigaction oldInt_ {}, oldTerm_ {};
};

void runRecord(RecordArgs& a) {
  if (a.seconds < 0) throw Error("record: --seconds must be > 0 (got " + std::to_string(a.seconds) + ")");
  a.camera.reconnect = false;  // a recording with a hole is not what was asked for: stop, keep what we have
  OpenNI2Source source(a.camera);
  TumSequenceWriter writer(a.out, source.info(), a.overwrite);
  const SequenceInfo& info = source.info();
  const CameraStats start = source.stats();
  const std::string until = a.frames      ? "stops after " + std::to_string(a.frames) + " frames"
                           : a.seconds > 0 ? "stops after " + std::to_string(a.seconds) + " s"
                                           : "Ctrl-C stops";
  std::printf("record: %s (%s), fx %.1f fy %.1f cx %.1f cy %.1f -> %s; %s\n", start.uri.c_str(), start.mode.c_str(),
              info.intrinsics.fx, info.intrinsics.fy, info.intrinsics.cx, info.intrinsics.cy, a.out.c_str(),
              until.c_str());
  std::fflush(stdout);

  const bool tty = isatty(STDERR_FILENO) != 0;
  StopOnSignal stopper(source);
  std::optional<double> first;
  double last = 0.0;
  size_t written = 0;
  std::string failure;
  try {
    while (a.frames == 0 || written < a.frames) {
      std::optional<DepthFrame> f = source.next();
      if (!f) break;  // Ctrl-C / SIGTERM
      if (!first) first = f->timestamp;
      if (a.seconds > 0 && f->timestamp - *first >= a.seconds) break;
      writer.write(*f);
      last = f->timestamp;
      ++written;
      if (tty && written % 15 == 0)
        std::fprintf(stderr, "\rrecord: %zu frames, %.1f s, %llu dropped", written, last - *first,
                     static_cast<unsigned long long>(source.stats().drops));
    }
  } catch (const Error& e) {
    failure = e.what();
  }
  if (tty) std::fprintf(stderr, "\n");
  writer.finish();
  const CameraStats s = source.stats();
  const double span = first ? last - *first : 0.0;
  std::printf("record: wrote %zu frames (%.2f s, %.1f fps) to %s; %llu frames dropped by the device\n", written, span,
              written > 1 && span > 0 ? (written - 1) / span : 0.0, a.out.c_str(),
              static_cast<unsigned long long>(s.drops));
  if (!failure.empty())
    throw Error("record: " + failure + "; the " + std::to_string(written) + " frames before are complete in " + a.out);
}

}  // namespace

void addRecordCommand(CLI::App& app) {
  auto args = std::make_shared<RecordArgs>();
  auto* sub = app.add_subcommand(
      "record", "Record an OpenNI2 depth camera as a TUM-layout sequence (depth PNGs, depth.txt, calibration.json)");
  OpenNI2Options& c = args->camera;
  sub->add_option("--out", args->out, "Output directory (created; must be empty unless --overwrite)")->required();
  auto* frames = sub->add_option("--frames", args->frames, "Stop after this many frames");
  auto* seconds = sub->add_option("--seconds", args->seconds, "Stop after this many seconds of camera time");
  frames->excludes(seconds);
  sub->add_option("--uri", c.uri, "OpenNI2 device URI (default: the first device found)");
  sub->add_option("--width", c.width, "Depth mode width, pixels")->capture_default_str();
  sub->add_option("--height", c.height, "Depth mode height, pixels")->capture_default_str();
  sub->add_option("--fps", c.fps, "Depth mode frames per second")->capture_default_str();
  sub->add_option("--fx", c.fx, "Focal length x, pixels (default: from the device's field of view)");
  sub->add_option("--fy", c.fy, "Focal length y, pixels (default: from the device's field of view)");
  sub->add_option("--cx", c.cx, "Principal point x, pixels (default: width/2)");
  sub->add_option("--cy", c.cy, "Principal point y, pixels (default: height/2)");
  sub->add_option("--frame-timeout", c.frameTimeoutSeconds, "Seconds without a frame before the camera counts as lost")
      ->capture_default_str();
  sub->add_flag("--overwrite", args->overwrite, "Replace the sequence files in a non-empty --out directory");
  sub->callback([args] { runRecord(*args); });
}

}  // namespace sb::cli
