// The wall-clock stages of a run, one after another ("read", "slices",
// "plan", "voxelize", "write" or "merge", "finish"): for --stats, the work
// dir's manifest and the trace (not the .vdb: its bytes are the same run
// after run).
#pragma once

#include "core/stage_seconds.h"
#include "core/stats.h"
#include "core/trace.h"

#include <chrono>
#include <string>

namespace yv {

class StageTimer {
  public:
    /// Ends the stage `stage` now (it began where the last one ended) and returns its seconds.
    double lap(const std::string& stage) {
        traceSpanSince(stage, last_);
        const auto now = std::chrono::steady_clock::now();
        const double s = std::chrono::duration<double>(now - last_).count();
        last_ = now;
        laps_.emplace_back(stage, s);
        return s;
    }
    const StageSeconds& laps() const { return laps_; }
    /// {"read": s, "slices": s, ...} for --stats.
    JsonObject json() const { return stageSecondsObject(laps_); }

  private:
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
    StageSeconds laps_;
};

} // namespace yv
