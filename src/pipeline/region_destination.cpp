#include "pipeline/region_destination.h"

#include "core/environment_count.h"
#include "core/process_memory.h"

#include <algorithm>
#include <optional>
#include <thread>

namespace yv {

std::size_t writerQueueBytes() {
    return static_cast<std::size_t>(std::min<std::uint64_t>(physicalMemoryBytes() / 8, std::uint64_t(4) << 30));
}

unsigned writerThreads(bool hostRasterizes, int processesHere) {
    if (const std::optional<long> n = countFromEnvironment("YV_WRITER_THREADS", 1, 256, "threads"))
        return static_cast<unsigned>(*n);
    const unsigned cores = std::thread::hardware_concurrency() / unsigned(std::max(1, processesHere));
    return std::max(2u, hostRasterizes ? cores / 2 : (cores > 2 ? cores - 2 : 0u));
}

} // namespace yv
