#include "pipeline/region_destination.h"

#include "core/error.h"
#include "core/process_memory.h"

#include <algorithm>
#include <cstdlib>
#include <string>
#include <thread>

namespace yv {

std::size_t writerQueueBytes() {
    return static_cast<std::size_t>(std::min<std::uint64_t>(physicalMemoryBytes() / 8, std::uint64_t(4) << 30));
}

unsigned writerThreads(bool hostRasterizes, int processesHere) {
    if (const char* text = std::getenv("YV_WRITER_THREADS")) {
        char* end = nullptr;
        const long n = std::strtol(text, &end, 10);
        if (end == text || *end != '\0' || n < 1 || n > 256)
            throw Error(std::string("YV_WRITER_THREADS=") + text + ": not a count of threads (1 to 256)");
        return static_cast<unsigned>(n);
    }
    const unsigned cores = std::thread::hardware_concurrency() / unsigned(std::max(1, processesHere));
    return std::max(2u, hostRasterizes ? cores / 2 : (cores > 2 ? cores - 2 : 0u));
}

} // namespace yv
