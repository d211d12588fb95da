#include "gpu/gl_buffer.h"

#include "core/error.h"
#include "core/trace.h"
#include "gpu/gl_program.h"

#include <algorithm>

namespace yv {

void GlBuffer::reserve(std::uint64_t bytes, std::uint64_t* gpuBytes) {
    if (bytes <= size_ && id_) return;
    const TraceSpan span("allocate a GPU buffer");
    if (gpuBytes) *gpuBytes -= size_;
    release();
    size_ = std::max<std::uint64_t>(bytes, 16);
    glCreateBuffers(1, &id_);
    glNamedBufferStorage(id_, static_cast<GLsizeiptr>(size_), nullptr, GL_DYNAMIC_STORAGE_BIT);
    checkGlError("allocating a GPU buffer");
    if (gpuBytes) *gpuBytes += size_;
}

void GlBuffer::reserveMappable(std::uint64_t bytes) {
    release();
    size_ = std::max<std::uint64_t>(bytes, 16);
    glCreateBuffers(1, &id_);
    glNamedBufferStorage(id_, static_cast<GLsizeiptr>(size_), nullptr, GL_MAP_WRITE_BIT);
    checkGlError("allocating a GPU staging buffer");
}

void GlBuffer::upload(const void* data, std::uint64_t bytes, std::uint64_t* gpuBytes) {
    reserve(bytes, gpuBytes);
    glNamedBufferSubData(id_, 0, static_cast<GLsizeiptr>(bytes), data);
}

void GlBuffer::clear(std::uint64_t bytes) {
    const GLuint zero = 0;
    glClearNamedBufferSubData(id_, GL_R32UI, 0, static_cast<GLsizeiptr>(bytes), GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
}

void GlBuffer::release() {
    if (id_) glDeleteBuffers(1, &id_);
    id_ = 0;
    size_ = 0;
}

ReadbackBuffer::~ReadbackBuffer() {
    if (fence_) glDeleteSync(fence_);
    release();
}

void ReadbackBuffer::reserve(std::uint64_t bytes, std::uint64_t* gpuBytes) {
    if (bytes <= size_) return;
    if (fence_) waitForCopy();
    const TraceSpan span("allocate a readback buffer");
    if (gpuBytes) *gpuBytes -= size_;
    release();
    size_ = std::max<std::uint64_t>(bytes, 1 << 20);
    glCreateBuffers(1, &id_);
    const GLbitfield flags = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_CLIENT_STORAGE_BIT;
    glNamedBufferStorage(id_, static_cast<GLsizeiptr>(size_), nullptr, flags);
    mapped_ = glMapNamedBufferRange(id_, 0, static_cast<GLsizeiptr>(size_), GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT);
    checkGlError("mapping the readback buffer");
    if (gpuBytes) *gpuBytes += size_;
}

void ReadbackBuffer::startCopy(std::initializer_list<Range> ranges, std::uint64_t* gpuBytes) {
    if (fence_) waitForCopy();
    std::uint64_t bytes = 0;
    for (const Range& r : ranges) bytes += r.bytes;
    empty_ = bytes == 0;
    if (empty_) return;
    bytesRead_ += bytes;
    reserve(bytes, gpuBytes);
    std::uint64_t at = 0;
    for (const Range& r : ranges) {
        if (r.bytes)
            glCopyNamedBufferSubData(r.source, id_, static_cast<GLintptr>(r.offset), static_cast<GLintptr>(at),
                                     static_cast<GLsizeiptr>(r.bytes));
        at += r.bytes;
    }
    glMemoryBarrier(GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
    fence_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glFlush(); // so that the copy starts while the host goes on
}

const void* ReadbackBuffer::waitForCopy() {
    if (!fence_) return empty_ ? nullptr : mapped_;
    const GLenum waited = glClientWaitSync(fence_, GL_SYNC_FLUSH_COMMANDS_BIT, GLuint64(600) * 1000000000);
    glDeleteSync(fence_);
    fence_ = nullptr;
    if (waited != GL_ALREADY_SIGNALED && waited != GL_CONDITION_SATISFIED)
        throw Error("GPU readback did not finish within 10 minutes (driver hang or lost device)");
    return mapped_;
}

void ReadbackBuffer::release() {
    if (!id_) return;
    glUnmapNamedBuffer(id_);
    glDeleteBuffers(1, &id_);
    id_ = 0;
    size_ = 0;
    mapped_ = nullptr;
}

} // namespace yv
