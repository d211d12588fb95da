#include "inspect/report_directory.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/stale_temporaries.h"
#include "inspect/html_page.h"

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <span>

namespace yv {
namespace {

namespace fs = std::filesystem;

/// Whether `dir` may be replaced by a report: an empty directory or an earlier report.
bool replaceable(const fs::path& dir) {
    if (fs::is_empty(dir)) return true;
    std::ifstream in(dir / "index.html");
    std::string first;
    std::getline(in, first);
    return first == kReportMarker;
}

/// `dirText` as the directory to create, refused where it may not be replaced.
fs::path reportPath(const std::string& input, const std::string& dirText) {
    fs::path dir = fs::path(dirText).lexically_normal();
    if (!dir.has_filename() && dir.has_parent_path()) dir = dir.parent_path(); // "report/"
    std::error_code ec;
    if (dir.filename().empty() || dir.filename() == "." || dir.filename() == "..")
        throw Error("--html " + dirText + ": expected the path of a directory to create");
    if (fs::is_symlink(dir, ec)) throw Error("--html " + dirText + ": is a symbolic link: refusing to replace it");
    if (fs::exists(dir, ec)) {
        if (!fs::is_directory(dir)) throw Error("--html " + dirText + ": exists and is not a directory");
        if (!replaceable(dir))
            throw Error("--html " + dirText + ": the directory holds files that are not a yarnvox report: refusing to replace it");
    }
    const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
    if (!fs::is_directory(parent, ec)) throw Error("--html " + dirText + ": the directory " + parent.string() + " does not exist");
    const fs::path inputPath = fs::weakly_canonical(input, ec);
    const fs::path outPath = fs::weakly_canonical(dir, ec);
    if (fs::is_directory(input) &&
        std::mismatch(inputPath.begin(), inputPath.end(), outPath.begin(), outPath.end()).first == inputPath.end())
        throw Error("--html " + dirText + ": is inside the work directory " + input + ": choose a place outside it");
    return dir;
}

/// Puts the built report where `dir` is, the old one (if any) removed after.
void moveIntoPlace(const fs::path& building, const fs::path& dir, const fs::path& parent) {
    std::error_code ec;
    if (fs::exists(dir)) {
        const fs::path old = parent / (dir.filename().string() + ".old-" + std::to_string(::getpid()));
        fs::rename(dir, old);
        fs::rename(building, dir);
        fs::remove_all(old, ec);
    } else {
        fs::rename(building, dir);
    }
}

} // namespace

std::size_t writeReportDirectory(const std::string& input, const std::string& dirText,
                                 const std::function<std::string(const fs::path&)>& build) {
    const fs::path dir = reportPath(input, dirText);
    const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
    // Built beside its final place, renamed into it at the end.
    const fs::path building = parent / (dir.filename().string() + ".tmp-" + std::to_string(::getpid()));
    std::error_code ec;
    fs::remove_all(building, ec);
    removeStaleTemporaries(dir.string()); // what killed runs left: DIR.tmp-PID, DIR.old-PID
    try {
        fs::create_directories(building / "renders");
        const std::string page = build(building);
        writeFileAtomically((building / "index.html").string(),
                            std::span(reinterpret_cast<const std::uint8_t*>(page.data()), page.size()));
        const auto images = std::distance(fs::directory_iterator(building / "renders"), fs::directory_iterator());
        signalAtTestPoint("html-move");
        throwIfInterrupted("before the report was put in place"); // the building directory goes below
        moveIntoPlace(building, dir, parent);
        return std::size_t(images);
    } catch (const fs::filesystem_error& e) {
        fs::remove_all(building, ec);
        throw Error("--html " + dirText + ": " + e.what());
    } catch (...) {
        fs::remove_all(building, ec);
        throw;
    }
}

} // namespace yv
