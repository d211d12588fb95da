// GPU time of a pass, summed over a run without stalling it.
#pragma once

#include "gpu/gl_objects.h"

#include <chrono>
#include <vector>

namespace yv {

/// Time of the GL commands between begin() and end(), summed. On a GPU
/// (EGL's device platform) by timer queries, read at the end of the run, so
/// that timing never stalls the pipeline; on llvmpipe, whose timer queries
/// answer garbage, both ends wait for the GPU to drain (glFinish), so there
/// it is what the pass costs the pipeline.
class GpuTimer {
  public:
    /// `useQueries`: timer queries (GlInfo::hardware()), else glFinish at both ends.
    explicit GpuTimer(bool useQueries) : useQueries_(useQueries) {}

    void begin();
    void end();
    /// Seconds so far (waits for the queries still running).
    double seconds();

  private:
    bool useQueries_;
    std::vector<GlQuery> queries_; ///< begun and not yet read
    std::chrono::steady_clock::time_point start_;
    double seconds_ = 0.0;
};

} // namespace yv
