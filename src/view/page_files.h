// The page of `yarnvox view` (page/ in the source tree), packed into the
// binary at build time as the shaders are (cmake/EmbedFiles.cmake).
#pragma once

namespace yv {

/// The text of page/<name> ("view.html", "view.js"), or nullptr when there is none.
const char* pageFile(const char* name);

} // namespace yv
