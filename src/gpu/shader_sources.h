// Shader texts embedded at build time from shaders/ (see cmake/EmbedFiles.cmake).
#pragma once

namespace yv {

/// The text of shaders/<name> (e.g. "slice.vert"), or nullptr when there is none.
const char* shaderSource(const char* name);

} // namespace yv
