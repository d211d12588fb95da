// The GL backend's second pass over a work item: every sample item the raster
// appended sampled (sample.comp), one thread an item, and each sample's share
// of fibre appended to the fragment list.
#pragma once

#include "garment/cross_section.h"
#include "gpu/cross_section_texture.h"
#include "gpu/gl_buffer.h"
#include "gpu/gl_objects.h"
#include "gpu/gl_program.h"
#include "gpu/gpu_timer.h"
#include "gpu/sample_lists.h"
#include "gpu/work_item.h"

#include <cstdint>

namespace yv {

/// The cross-section as the sampling reads it, and with --albedo its colour.
struct SampleTextures {
    GlTexture density, albedo;
};

/// Uploads the cross-section's textures (the colour's with `albedo`),
/// adding their bytes to `gpuBytes`.
SampleTextures uploadSampleTextures(const CrossSection& xs, TexelReads reads, bool albedo, std::uint64_t* gpuBytes);

class SamplePass {
  public:
    /// `reads` (not Auto) as `textures` were uploaded; `albedo`: the ALBEDO
    /// variant, which also writes each fragment's colour.
    SamplePass(const CrossSection& xs, TexelReads reads, SampleTextures textures, bool albedo, GLuint maxGroups,
               bool timerQueries);

    /// Samples the items in `lists` (their count on the GPU: the dispatch is
    /// sized there, so the host never waits between the raster and this)
    /// with the slices `slices`; the fragments go to `lists`.
    void run(const WorkItem& item, const SamplingUniforms& uniforms, const SampleLists& lists, const GlBuffer& slices);

    /// GPU seconds of the sampling so far.
    double seconds() { return timer_.seconds(); }

  private:
    SampleTextures textures_;
    bool albedo_;
    GLuint maxGroups_;
    GlProgram sample_, dispatch_;
    GpuTimer timer_;
};

} // namespace yv
