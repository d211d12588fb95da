// A large memcpy split over threads of its own. The GPU thread copies each
// pass's packed bricks out of the readback buffer (gigabytes a run at 8192)
// while the .vdb writer's threads keep every TBB worker busy encoding: a
// copy handed to TBB there ran mostly on the calling thread (the draped
// garment at 8192: 7.3 GB in 0.93 s of the GPU thread, a third of its
// voxelize stage). Threads that only copy get their share of the cores from
// the scheduler instead, and fault in the destination's fresh pages side by side.
#pragma once

#include <cstddef>

namespace yv {

/// memcpy(to, from, bytes) in pieces on up to kCopyThreads threads (the
/// caller one of them). Small copies, and a copy while another one is under
/// way, run on the calling thread alone. Thread-safe.
void copyInParallel(void* to, const void* from, std::size_t bytes);

/// The most threads a copy uses (the caller included); fewer on machines
/// of fewer than twice as many cores, but never fewer than two.
inline constexpr unsigned kCopyThreads = 6;

/// The threads besides the caller that copyInParallel hands pieces to
/// (starting them, if no copy has yet).
unsigned copyHelperThreads();

} // namespace yv
