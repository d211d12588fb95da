#include "core/progress.h"

#include <cstdio>
#include <unistd.h>

namespace yv {
namespace {

ProgressObserver& installedObserver() {
    static ProgressObserver observer;
    return observer;
}

} // namespace

ProgressObserver setProgressObserver(ProgressObserver observer) {
    std::swap(installedObserver(), observer);
    return observer;
}

Progress::Progress(std::string stage, std::uint64_t total, bool quiet, std::string unit)
    : stage_(std::move(stage)), unit_(std::move(unit)), total_(total),
      enabled_(!quiet && isatty(STDERR_FILENO)), observer_(quiet ? ProgressObserver() : installedObserver()),
      start_(std::chrono::steady_clock::now()) {
    if (observer_) tellObserver(); // the stage's total, before any work
}

Progress::~Progress() { finish(); }

void Progress::advance(std::uint64_t n) {
    const std::uint64_t done = done_.fetch_add(n, std::memory_order_relaxed) + n;
    (void)done;
    if (!enabled_ && !observer_) return;
    const std::int64_t now =
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start_).count();
    std::int64_t next = nextDrawNs_.load(std::memory_order_relaxed);
    if (now < next || !nextDrawNs_.compare_exchange_strong(next, now + 100'000'000)) return;
    if (enabled_) draw(false);
    if (observer_) tellObserver();
}

void Progress::finish() {
    if (finished_) return;
    finished_ = true;
    if (enabled_) draw(true);
    if (observer_) tellObserver();
}

void Progress::tellObserver() {
    std::lock_guard<std::mutex> lock(drawMutex_);
    observer_(stage_, unit_, done_.load(std::memory_order_relaxed), total_);
}

void Progress::draw(bool final) {
    std::lock_guard<std::mutex> lock(drawMutex_);
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const std::uint64_t done = done_.load(std::memory_order_relaxed);
    const double rate = elapsed > 0 ? done / elapsed : 0.0;
    char line[256];
    if (final) {
        std::snprintf(line, sizeof line, "\r%-12s %llu %s in %.2f s (%.3g/s)\x1b[K\n", stage_.c_str(),
                      static_cast<unsigned long long>(done), unit_.c_str(), elapsed, rate);
    } else {
        const double eta = rate > 0 && total_ > done ? (total_ - done) / rate : 0.0;
        std::snprintf(line, sizeof line, "\r%-12s %llu/%llu %s  %5.1f%%  %.3g/s  ETA %.0f s\x1b[K", stage_.c_str(),
                      static_cast<unsigned long long>(done), static_cast<unsigned long long>(total_), unit_.c_str(),
                      total_ ? 100.0 * done / total_ : 100.0, rate, eta);
    }
    std::fputs(line, stderr);
    std::fflush(stderr);
}

} // namespace yv
