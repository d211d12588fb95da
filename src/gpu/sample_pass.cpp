#include "gpu/sample_pass.h"

#include "gpu/gl_bindings.h"

#include <string>
#include <utility>
#include <vector>

namespace yv {
namespace {

constexpr GLuint kSampleGroup = 128; // sample.comp's local_size_x

std::vector<std::string> sampleDefines(const CrossSection& xs, TexelReads reads, bool albedo) {
    std::vector<std::string> defines = crossSectionDefines(xs, reads);
    // --albedo compiles variants of their own (ALBEDO), so runs without it
    // keep the programs, fragments and brick words they always had.
    if (albedo) defines.push_back("ALBEDO 1");
    return defines;
}

} // namespace

SampleTextures uploadSampleTextures(const CrossSection& xs, TexelReads reads, bool albedo, std::uint64_t* gpuBytes) {
    SampleTextures textures;
    textures.density = uploadCrossSectionTexture(xs, reads);
    *gpuBytes += reads == TexelReads::Quad ? std::uint64_t(xs.size + 1) * (xs.size + 1) * 4 : std::uint64_t(xs.size) * xs.size;
    if (albedo) {
        textures.albedo = uploadAlbedoTexture(xs);
        *gpuBytes += std::uint64_t(xs.size) * xs.size * 12;
    }
    checkGlError("uploading the cross-section");
    return textures;
}

SamplePass::SamplePass(const CrossSection& xs, TexelReads reads, SampleTextures textures, bool albedo,
                       GLuint maxGroups, bool timerQueries)
    : textures_(std::move(textures)), albedo_(albedo), maxGroups_(maxGroups),
      sample_(GlProgram::compute("sample.comp", sampleDefines(xs, reads, albedo))),
      dispatch_(GlProgram::compute("sample_dispatch.comp")), timer_(timerQueries) {}

void SamplePass::run(const WorkItem& item, const SamplingUniforms& uniforms, const SampleLists& lists,
                     const GlBuffer& slices) {
    timer_.begin();
    // One thread per item, the work groups counted on the GPU from the items.
    dispatch_.use();
    glUniform1ui(dispatch_.uniform("uItemCapacity"), static_cast<GLuint>(lists.itemSlots()));
    glUniform1ui(dispatch_.uniform("uGroupSize"), kSampleGroup);
    glUniform1ui(dispatch_.uniform("uMaxGroups"), maxGroups_);
    lists.itemCounter().bindStorage(kItemCounterBinding);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);

    sample_.use();
    uniforms.set(sample_, item);
    glUniform1ui(sample_.uniform("uCapacity"), static_cast<GLuint>(lists.fragmentSlots()));
    glUniform1ui(sample_.uniform("uItemCapacity"), static_cast<GLuint>(lists.itemSlots()));
    lists.fragments().bindStorage(kFragmentsBinding);
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, kFragmentCountAtomic, lists.fragmentCounter().id());
    lists.fragmentCounter().bindStorage(kFragmentCounterBinding); // the wrap flag
    glBindTextureUnit(kCrossSectionUnit, textures_.density.id());
    if (albedo_) {
        lists.albedoFragments().bindStorage(kAlbedoFragmentsBinding);
        glBindTextureUnit(kAlbedoUnit, textures_.albedo.id());
    }
    slices.bindStorage(kSlicesBinding);
    lists.items().bindStorage(kItemsBinding);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, lists.itemCounter().id());
    glDispatchComputeIndirect(16);
    timer_.end();
    checkGlError("sampling pass");
}

} // namespace yv
