#include "core/trace.h"

#include "core/error.h"
#include "core/stats.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace yv {
namespace {

struct TraceEvent {
    std::string name;
    long long startNs, endNs;
    int thread;
};

struct TraceLog {
    std::mutex mutex;
    std::vector<TraceEvent> events;
    std::atomic<int> threads{0};
    const std::chrono::steady_clock::time_point origin = std::chrono::steady_clock::now();
};

TraceLog& traceLog() {
    static TraceLog log;
    return log;
}

/// Small numbers for the threads, in the order they first record a span.
int threadNumber() {
    thread_local const int number = traceLog().threads.fetch_add(1);
    return number;
}

const char* tracePath() {
    static const char* path = [] {
        // The timeline's origin and its thread 0: the first to ask, main().
        threadNumber();
        const char* p = std::getenv("YV_TRACE");
        return p && *p ? p : nullptr;
    }();
    return path;
}

long long sinceOrigin(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(t - traceLog().origin).count();
}

long long nowNs() { return sinceOrigin(std::chrono::steady_clock::now()); }

void record(std::string name, long long startNs, long long endNs) {
    TraceEvent event{std::move(name), startNs, endNs, threadNumber()};
    TraceLog& log = traceLog();
    const std::lock_guard lock(log.mutex);
    log.events.push_back(std::move(event));
}

} // namespace

bool traceEnabled() { return tracePath() != nullptr; }

TraceSpan::TraceSpan(const char* name) : name_(name) {
    if (traceEnabled()) startNs_ = nowNs();
}

TraceSpan::~TraceSpan() {
    if (startNs_ >= 0) record(name_, startNs_, nowNs());
}

void traceSpanSince(const std::string& name, std::chrono::steady_clock::time_point start) {
    if (traceEnabled()) record(name, sinceOrigin(start), nowNs());
}

void writeTrace() {
    if (!traceEnabled()) return;
    TraceLog& log = traceLog();
    std::vector<JsonObject> events;
    {
        const std::lock_guard lock(log.mutex);
        events.reserve(log.events.size());
        for (const TraceEvent& e : log.events)
            events.push_back(JsonObject()
                                 .set("name", e.name)
                                 .set("ph", "X")
                                 .set("pid", 1)
                                 .set("tid", e.thread)
                                 .set("ts", double(e.startNs) * 1e-3)
                                 .set("dur", double(e.endNs - e.startNs) * 1e-3));
    }
    // Where the timeline starts on the host's monotonic clock (CLOCK_MONOTONIC,
    // Python's time.monotonic()): a script that times the process from
    // outside sees what its start and its exit took.
    const double origin = std::chrono::duration<double>(log.origin.time_since_epoch()).count();
    const std::string text = JsonObject()
                                 .set("traceEvents", events)
                                 .set("otherData", JsonObject().set("origin_monotonic_seconds", origin))
                                 .dump() +
                             "\n";
    try {
        writeTextFileAtomically(tracePath(), text);
    } catch (const Error& e) {
        std::fprintf(stderr, "yarnvox: warning: YV_TRACE: cannot write %s (%s)\n", tracePath(), e.what());
    }
}

} // namespace yv
