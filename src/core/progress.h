// Progress of a long stage on a terminal: stage, done/total, rate, ETA.
// Silent when stderr is not a terminal or when quiet is set.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace yv {

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
    std::string stage_, unit_;
    std::uint64_t total_;
    bool enabled_;
    bool finished_ = false;
    std::atomic<std::uint64_t> done_{0};
    std::atomic<std::int64_t> nextDrawNs_{0};
    std::chrono::steady_clock::time_point start_;
    std::mutex drawMutex_;
};

} // namespace yv
