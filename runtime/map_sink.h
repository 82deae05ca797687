#pragma once
// The navigation map's seam (issue 45): a run hands its map sink each frame (after the outputs), each slab that
// leaves the moving volume (before the shift clears it) and, at its end, the directory to write the map files
// in. The run knows nothing else of the map (navmap/nav_map_sink.h implements it). All called on the SLAM thread
// (the sink may do a slab's work on a thread of its own, and waits for it before it writes).

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "drivers/frame_source.h"
#include "pipeline/pipeline.h"
#include "pipeline/volume_window.h"
#include "runtime/frame_record.h"

namespace sb {

class MapSink {
 public:
  virtual ~MapSink() = default;
  // After each frame: the sink may read the pipeline's volume (at its own period, never required per frame).
  virtual void onFrame(const FrameRecord& record, const DepthFrame& frame, Pipeline& pipeline) = 0;
  // A slab about to leave the volume (pipeline/volume_window.h), read before the shift clears it: the copy the
  // window made, shared with the slab's mesh worker (runtime/map_slabs.h); the sink may keep it until it is done.
  virtual void onSlab(std::shared_ptr<const VolumeSlab> slab) = 0;
  // Writes the map files into `dir` (each atomically); throws sb::Error naming a file.
  virtual void write(const std::string& dir, Pipeline& pipeline) = 0;
  // summary.json's "navmap" (what was made, or why not; its cost).
  virtual nlohmann::json summaryJson() const = 0;

  // The map kept in a map store (runtime/map_store.h, navmap.bin; issue 55). The payload to keep, empty when
  // there is nothing to keep (no map frame yet): at the end of a run (`final`) with the volume's map, else what
  // left the volume so far. None by default.
  virtual std::vector<uint8_t> keptState(Pipeline& /*pipeline*/, bool /*final*/) { return {}; }
  // Whether there is more to keep than at the last keptState, known without waiting (a slab's votes are in).
  virtual bool keptStateChanged() const { return false; }
  // An earlier run's kept payload (read from `path`): the map continues from it, in its frame. Throws sb::Error
  // naming `path` when it cannot (a malformed payload, other settings).
  virtual void restoreState(const std::vector<uint8_t>& /*payload*/, const std::string& /*path*/) {}
};

}  // namespace sb
