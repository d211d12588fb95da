#include "pipeline/region_destination.h"

#include "core/process_memory.h"

#include <algorithm>
#include <thread>

namespace yv {

std::size_t writerQueueBytes() {
    return static_cast<std::size_t>(std::min<std::uint64_t>(physicalMemoryBytes() / 8, std::uint64_t(4) << 30));
}

unsigned writerThreads() { return std::max(2u, std::thread::hardware_concurrency() / 2); }

} // namespace yv
