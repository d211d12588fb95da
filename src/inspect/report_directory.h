// Where `inspect --html DIR` puts its report: DIR must be absent, empty or an
// earlier report (never a foreign directory, a link or a place inside the
// work directory reported on). The report is built in a temporary directory
// beside DIR and renamed into place, so DIR is either the old report, absent,
// or the complete new one.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>

namespace yv {

/// Builds the report of `input` at `dirText`: `build` gets the directory
/// being built (with an empty renders/ in it), writes its pictures there and
/// returns the page, written as index.html. Returns the files in renders/.
/// Throws yv::Error naming --html DIR when DIR may not be replaced or a file
/// operation fails; on failure no DIR is left that looks complete.
std::size_t writeReportDirectory(const std::string& input, const std::string& dirText,
                                 const std::function<std::string(const std::filesystem::path&)>& build);

} // namespace yv
