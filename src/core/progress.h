// Progress of a long stage on a terminal: stage, done/total, rate, ETA.
// Silent when stderr is not a terminal or when quiet is set. A program that
// runs yarnvox (the Python module, `voxelize --progress-lines`) follows it
// through one process-wide observer instead, terminal or not.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>

namespace yv {

/// Where a stage's progress goes besides the terminal: its name, its unit,
/// what is done and the total. Called when the stage begins, at most 10
/// times a second while it runs, and once when it finishes, from whichever
/// thread advanced it. A quiet stage (--quiet, or one inside another's line)
/// tells it nothing, as it draws nothing.
using ProgressObserver =
    std::function<void(const std::string& stage, const std::string& unit, std::uint64_t done, std::uint64_t total)>;

/// Installs `observer` for every Progress made from now on (an empty one
/// removes it); returns the previous one. Not for use while a stage runs.
ProgressObserver setProgressObserver(ProgressObserver observer);

class Progress {
  public:
    Progress(std::string stage, std::uint64_t total, bool quiet, std::string unit = "");
    ~Progress();
    /// Adds `n` units of work; thread-safe and cheap (redraws at most 10 times a second).
    void advance(std::uint64_t n);
    /// Ends the line with the final count and elapsed time.
    void finish();

  private:
    void draw(bool final);
    void tellObserver();
    std::string stage_, unit_;
    std::uint64_t total_;
    bool enabled_;
    ProgressObserver observer_; ///< the one installed when this stage began
    bool finished_ = false;
    std::atomic<std::uint64_t> done_{0};
    std::atomic<std::int64_t> nextDrawNs_{0};
    std::chrono::steady_clock::time_point start_;
    std::mutex drawMutex_;
};

} // namespace yv
