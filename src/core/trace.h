// A timeline of one run, for finding where its time goes: with YV_TRACE=FILE
// in the environment, named spans of every host thread are recorded and
// written to FILE as Chrome trace events when the command ends (open it in
// ui.perfetto.dev or chrome://tracing). Without it a span costs a branch.
#pragma once

#include <chrono>
#include <string>

namespace yv {

/// Whether YV_TRACE names a file (read once).
bool traceEnabled();

/// One span on the calling thread's row, from construction to destruction.
/// `name` must outlive the program (a string literal).
class TraceSpan {
  public:
    explicit TraceSpan(const char* name);
    ~TraceSpan();
    TraceSpan(const TraceSpan&) = delete;
    TraceSpan& operator=(const TraceSpan&) = delete;

  private:
    const char* name_;
    long long startNs_ = -1; ///< -1: tracing is off
};

/// Records a span that began at `start` and ends now, on the calling thread's
/// row (for times a caller measures anyway, such as a run's stages).
void traceSpanSince(const std::string& name, std::chrono::steady_clock::time_point start);

/// Writes the spans so far to YV_TRACE's file; nothing when tracing is off.
/// A file that cannot be written is a warning on stderr, never an error of
/// the command that was traced.
void writeTrace();

} // namespace yv
