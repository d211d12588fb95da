// Owning handles for GL object names (textures, vertex arrays, framebuffers,
// renderbuffers, queries, shader stages), beside GlBuffer: each deletes its name when it goes out of
// scope, so no pass or renderer frees GL objects by hand. They need the GL
// context current where they are made and destroyed.
#pragma once

#include <epoxy/gl.h>

#include <utility>

namespace yv {

/// One GL object name of a kind whose glDelete* takes (count, names).
template <void (*Delete)(GLsizei, const GLuint*)>
class GlName {
  public:
    GlName() = default;
    /// Takes ownership of `id` (0 is no object).
    explicit GlName(GLuint id) : id_(id) {}
    ~GlName() { reset(); }
    GlName(GlName&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
    GlName& operator=(GlName&& other) noexcept {
        if (this != &other) {
            reset();
            id_ = std::exchange(other.id_, 0);
        }
        return *this;
    }
    GlName(const GlName&) = delete;
    GlName& operator=(const GlName&) = delete;

    GLuint id() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    /// Deletes the object now (and owns `id` from then on).
    void reset(GLuint id = 0) {
        if (id_ != 0) Delete(1, &id_);
        id_ = id;
    }
    /// Gives up ownership without deleting.
    GLuint release() { return std::exchange(id_, 0); }

  private:
    GLuint id_ = 0;
};

namespace gl_detail {
// epoxy's entry points are function pointers resolved at first call: wrap
// them so the template takes a plain function.
inline void deleteTextures(GLsizei n, const GLuint* ids) { glDeleteTextures(n, ids); }
inline void deleteVertexArrays(GLsizei n, const GLuint* ids) { glDeleteVertexArrays(n, ids); }
inline void deleteFramebuffers(GLsizei n, const GLuint* ids) { glDeleteFramebuffers(n, ids); }
inline void deleteRenderbuffers(GLsizei n, const GLuint* ids) { glDeleteRenderbuffers(n, ids); }
inline void deleteQueries(GLsizei n, const GLuint* ids) { glDeleteQueries(n, ids); }
inline void deleteBuffers(GLsizei n, const GLuint* ids) { glDeleteBuffers(n, ids); }
inline void deleteShaders(GLsizei n, const GLuint* ids) {
    for (GLsizei i = 0; i < n; ++i) glDeleteShader(ids[i]);
}
} // namespace gl_detail

using GlTexture = GlName<gl_detail::deleteTextures>;
using GlVertexArray = GlName<gl_detail::deleteVertexArrays>;
using GlFramebuffer = GlName<gl_detail::deleteFramebuffers>;
using GlRenderbuffer = GlName<gl_detail::deleteRenderbuffers>;
using GlQuery = GlName<gl_detail::deleteQueries>;
/// A buffer of fixed storage used once (a picture's pixel-pack buffer);
/// GlBuffer is the one that grows.
using GlBufferName = GlName<gl_detail::deleteBuffers>;
/// A compiled shader stage (GlProgram links them).
using GlShader = GlName<gl_detail::deleteShaders>;

/// A new texture of `target` (glCreateTextures: storage comes after).
inline GlTexture createTexture(GLenum target) {
    GLuint id = 0;
    glCreateTextures(target, 1, &id);
    return GlTexture(id);
}
/// A new vertex array object.
inline GlVertexArray createVertexArray() {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    return GlVertexArray(id);
}
/// A new framebuffer object.
inline GlFramebuffer createFramebuffer() {
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    return GlFramebuffer(id);
}

} // namespace yv
