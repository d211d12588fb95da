// GPU buffers the GL passes share: storage that grows on demand, and the
// host-visible copy target every readback goes through.
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <initializer_list>

namespace yv {

/// A GL buffer that grows on demand (contents are not kept when it grows).
/// `gpuBytes`, where given, tracks the sum of yarnvox's GPU buffers.
class GlBuffer {
  public:
    GlBuffer() = default;
    ~GlBuffer() { release(); }
    GlBuffer(const GlBuffer&) = delete;
    GlBuffer& operator=(const GlBuffer&) = delete;

    void reserve(std::uint64_t bytes, std::uint64_t* gpuBytes);
    void upload(const void* data, std::uint64_t bytes, std::uint64_t* gpuBytes);
    /// Storage of `bytes` the host can map for writing (a staging buffer;
    /// not counted in the GPU's bytes).
    void reserveMappable(std::uint64_t bytes);
    /// Zeroes the first `bytes`.
    void clear(std::uint64_t bytes);
    void bindStorage(GLuint binding) const { glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, id_); }
    GLuint id() const { return id_; }
    std::uint64_t size() const { return size_; }

  private:
    void release();
    GLuint id_ = 0;
    std::uint64_t size_ = 0;
};

/// Host-visible copy target for readback. Reading device buffers directly
/// (glGetBufferSubData) makes the NVIDIA driver migrate them to host memory,
/// which slows every later pass that touches them; copying into this
/// persistently mapped buffer leaves the working buffers in video memory.
class ReadbackBuffer {
  public:
    ReadbackBuffer() = default;
    ~ReadbackBuffer();
    ReadbackBuffer(const ReadbackBuffer&) = delete;
    ReadbackBuffer& operator=(const ReadbackBuffer&) = delete;

    /// A byte range of a GPU buffer.
    struct Range {
        GLuint source;
        std::uint64_t offset, bytes;
    };
    /// Copies the ranges one after another and returns them, once the GPU is
    /// done (one wait for all of them); nullptr when they are empty.
    const void* read(std::initializer_list<Range> ranges, std::uint64_t* gpuBytes) {
        startCopy(ranges, gpuBytes);
        return waitForCopy();
    }
    /// Queues the copies of the ranges behind the GL commands so far and
    /// returns at once; waitForCopy() then waits for them. One copy at a time
    /// per buffer: a second start waits for the first.
    void startCopy(std::initializer_list<Range> ranges, std::uint64_t* gpuBytes);
    /// The copied bytes, once the GPU has them in place (nullptr for empty ranges).
    const void* waitForCopy();
    /// Copies `bytes` from the start of `source` and returns them, once the GPU is done.
    const void* read(GLuint source, std::uint64_t bytes, std::uint64_t* gpuBytes) {
        return read({Range{source, 0, bytes}}, gpuBytes);
    }
    /// Bytes read so far.
    std::uint64_t bytesRead() const { return bytesRead_; }
    /// Host bytes the buffer holds now.
    std::uint64_t capacity() const { return size_; }
    /// Makes room for copies of `bytes` (exactly that, at least 1 MiB), once
    /// the copy in flight is in. startCopy grows the buffer to each copy's
    /// size; a caller that expects its copies to grow reserves ahead.
    void reserve(std::uint64_t bytes, std::uint64_t* gpuBytes);

  private:
    void release();
    GLuint id_ = 0;
    std::uint64_t size_ = 0;
    const void* mapped_ = nullptr;
    std::uint64_t bytesRead_ = 0;
    GLsync fence_ = nullptr; ///< the copy in flight, if any
    bool empty_ = false;     ///< the copy in flight moved no bytes
};

} // namespace yv
