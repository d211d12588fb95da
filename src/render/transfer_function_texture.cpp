#include "render/transfer_function_texture.h"

#include "gpu/gl_program.h"

namespace yv {

TransferFunctionTexture::TransferFunctionTexture(const TransferFunction& tf) : texture_(createTexture(GL_TEXTURE_1D)) {
    glTextureStorage1D(texture_.id(), 1, GL_RGBA32F, GLsizei(tf.size()));
    glTextureParameteri(texture_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(texture_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(texture_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    update(tf);
}

void TransferFunctionTexture::update(const TransferFunction& tf) {
    glTextureSubImage1D(texture_.id(), 0, 0, GLsizei(tf.size()), GL_RGBA, GL_FLOAT, tf.data());
    checkGlError("uploading the transfer function");
}

} // namespace yv
