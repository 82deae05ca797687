#pragma once
// The energy of a sequence of frames from one power sampler (power/power_sampler.h), across one or more runs:
// each frame's processing interval goes in, the frames whose energy is known (or known to be unknown, with the
// reason) come out in frame order, lagging the frames by up to one meter period; the totals cover every frame
// since the account was opened. A Run borrows an account (runtime/run.h); the daemon keeps one across passes,
// `slambooster run` one per run.
//
//   auto sampler = sb::openSampler(sb::power::loadPowerConfig(path), outDir);  // nullptr for meter "none"
//   sampler->start();
//   sb::EnergyAccount account(*sampler);  ... runs borrow it ...  account.drain();  account.totals();

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "power/power_config.h"
#include "power/power_sampler.h"
#include "report/run_summary.h"
#include "runtime/frame_record.h"

namespace sb {

class EnergyAccount {
 public:
  // Borrows `sampler` (started; must outlive the account).
  explicit EnergyAccount(power::PowerSampler& sampler);
  // The frame's interval in; the results resolved so far out (never waits for the meter).
  std::vector<power::FrameEnergy> add(const FrameRecord& record);
  // End of the frames: waits up to the sampler's drain timeout for samples after the last frame and returns
  // the rest. Later calls return nothing.
  std::vector<power::FrameEnergy> drain();
  // The totals over every frame so far, with the meter's name and device (summary.json's "energy").
  EnergySummary totals() const;

 private:
  std::vector<power::FrameEnergy> counted(std::vector<power::FrameEnergy> results);

  power::PowerSampler& sampler_;
  std::map<std::string, size_t> unknownReasons_;  // reason -> frames
  bool drained_ = false;
};

// The sampler for `config`, tracing to DIR/power.csv (rotated into `segments` when given), or nullptr when
// config.meter is "none". Opens the meter (throws sb::Error naming the device and what to do) and measures
// the idle baseline when config.idleBaselineS > 0 (blocks that long).
std::unique_ptr<power::PowerSampler> openSampler(const power::PowerConfig& config, const std::string& dir,
                                                 std::shared_ptr<SegmentStore> segments = nullptr);

}  // namespace sb
