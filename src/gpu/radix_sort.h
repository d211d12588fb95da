// Sorting pairs of 32-bit keys and values on the GPU, by key, ascending and
// stable: a least-significant-digit radix sort, four passes of 8 bits, each
// a histogram per tile of 2048 pairs (radix_histogram.comp), an exclusive
// scan of the histograms (gpu/gpu_scan.h) and a scatter that sorts each
// tile in shared memory and writes it where the scan says
// (radix_scatter.comp). The first pass also leaves out the pairs whose
// value is kDropped, so that a pass before the sort can cull by marking
// them. Nothing is read back; the context must be current.
#pragma once

#include "gpu/gl_buffer.h"
#include "gpu/gl_program.h"
#include "gpu/gpu_scan.h"

#include <cstdint>

namespace yv {

class RadixSort {
  public:
    /// A value that marks its pair as left out of the sort.
    static constexpr std::uint32_t kDropped = 0xffffffffu;
    /// Pairs one tile of a pass sorts in shared memory (256 threads, 8 each).
    static constexpr std::uint32_t kTile = 2048;

    /// Room for `capacity` pairs; `maxGroups`: the work groups a dispatch may have.
    RadixSort(std::uint64_t capacity, GLuint maxGroups);
    /// Makes room for `capacity` pairs (never shrinks; what keys() and
    /// values() held is lost when they grow).
    void reserve(std::uint64_t capacity);

    /// Where the pairs to sort go: `capacity` keys and as many values.
    const GlBuffer& keys() const { return keys_[0]; }
    const GlBuffer& values() const { return values_[0]; }

    /// Sorts the first `count` pairs of keys() and values() (which it
    /// overwrites), leaving out the dropped ones, and writes the kept pairs'
    /// values in key order, equal keys in their order before the sort, to
    /// the start of `out` (room for `count` words). Queued on the GPU.
    /// `withKeys`: keys() holds the kept pairs' keys in that order after it.
    void sort(std::uint32_t count, const GlBuffer& out, bool withKeys = false);
    /// Word 0: the pairs the last sort kept, once it has run.
    const GlBuffer& kept() const { return kept_; }

  private:
    GLuint groupsFor(std::uint64_t groups) const;

    GLuint maxGroups_;
    GlProgram histogram_, scatter_;
    GpuScan scan_;
    GlBuffer keys_[2], values_[2], histogramCounts_, kept_;
};

} // namespace yv
