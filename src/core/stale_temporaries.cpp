#include "core/stale_temporaries.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <system_error>

namespace yv {
namespace fs = std::filesystem;

bool processAlive(long pid) {
    // EPERM: it exists, under another user.
    return pid > 0 && (::kill(pid_t(pid), 0) == 0 || errno == EPERM);
}

long temporaryOwner(const std::string& name, const std::string& base) {
    if (base.empty() || !name.starts_with(base)) return -1;
    for (const char* marker : {".partial-", ".tmp-", ".old-"}) {
        const std::string prefix = base + marker;
        if (!name.starts_with(prefix)) continue;
        std::size_t end = prefix.size();
        long pid = 0;
        while (end < name.size() && end - prefix.size() < 10 && name[end] >= '0' && name[end] <= '9')
            pid = pid * 10 + (name[end++] - '0');
        if (end == prefix.size()) return -1;
        if (end == name.size() || name[end] == '-' || name[end] == '.') return pid;
        return -1;
    }
    return -1;
}

std::vector<std::string> removeStaleTemporaries(const std::string& path) {
    std::vector<std::string> removed;
    const fs::path target = fs::path(path).lexically_normal();
    const std::string base = target.filename().string();
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        const long pid = temporaryOwner(name, base);
        if (pid <= 0 || pid == long(::getpid()) || processAlive(pid)) continue;
        std::error_code removeEc;
        const fs::file_status status = it->symlink_status(removeEc);
        bool gone = false;
        if (fs::is_regular_file(status)) gone = fs::remove(it->path(), removeEc);
        // A directory is ours only as a report being built (its renders/ is made first).
        else if (fs::is_directory(status) && fs::is_directory(it->path() / "renders", removeEc))
            gone = fs::remove_all(it->path(), removeEc) > 0;
        if (gone) removed.push_back(it->path().string());
    }
    return removed;
}

} // namespace yv
