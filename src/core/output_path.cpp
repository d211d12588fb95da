#include "core/output_path.h"

#include "core/error.h"
#include "core/stale_temporaries.h"

#include <filesystem>
#include <system_error>

namespace yv {
namespace fs = std::filesystem;

std::string nonRegularKind(const std::string& path) {
    std::error_code ec;
    const fs::file_status link = fs::symlink_status(path, ec);
    if (!fs::exists(link) || fs::is_regular_file(link)) return {};
    return fs::is_symlink(link)                                      ? "a symbolic link"
           : fs::is_directory(link)                                  ? "a directory"
           : fs::is_block_file(link) || fs::is_character_file(link) ? "a device"
           : fs::is_fifo(link)                                       ? "a FIFO"
           : fs::is_socket(link)                                     ? "a socket"
                                                                     : "not a regular file";
}

void checkOutputPath(const std::string& path, const std::string& what, const std::vector<std::string>& inputs) {
    std::error_code ec;
    if (const std::string kind = nonRegularKind(path); !kind.empty())
        throw Error(what + " " + path + ": is " + kind + ", not a regular file: refusing to replace it");
    if (fs::exists(fs::symlink_status(path, ec))) {
        for (const std::string& input : inputs)
            if (fs::equivalent(path, input, ec))
                throw Error(what + " " + path + ": is the same file as " + input + ": refusing to overwrite it");
    }
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty() && !fs::is_directory(parent, ec))
        throw Error(what + " " + path + ": the directory " + parent.string() + " does not exist");
    // The place is good: what an earlier, killed run left beside it goes.
    removeStaleTemporaries(path);
}

} // namespace yv
