#include "core/voxel_statistics.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <vector>
#include <map>


namespace yv {
namespace {

using Integer = FixedPointSum::Integer;

/// Decimal text of a 128-bit integer (the standard library prints none).
std::string integerText(Integer v) {
    if (v == 0) return "0";
    const bool negative = v < 0;
    // Digits of the magnitude, least significant first; unsigned so the most negative value works too.
    __extension__ unsigned __int128 m = negative ? ~static_cast<unsigned __int128>(v) + 1 : static_cast<unsigned __int128>(v);
    std::string digits;
    for (; m; m /= 10) digits.push_back(char('0' + int(m % 10)));
    if (negative) digits.push_back('-');
    std::reverse(digits.begin(), digits.end());
    return digits;
}

bool parseInteger(const std::string& s, Integer& out) {
    std::size_t i = 0;
    const bool negative = !s.empty() && s[0] == '-';
    i += negative;
    if (i == s.size() || s.size() - i > 38) return false; // 38 digits always fit
    Integer v = 0;
    for (; i < s.size(); ++i) {
        if (s[i] < '0' || s[i] > '9') return false;
        v = v * 10 + (s[i] - '0');
    }
    out = negative ? -v : v;
    return true;
}

bool parseUnsigned(const std::string& s, std::uint64_t& out) {
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && end == s.data() + s.size() && !s.empty();
}

/// "fixed:outside": the exact fixed-point integer and the double kept outside it ("%a", exact).
std::string sumText(const FixedPointSum& sum) {
    char outside[64];
    std::snprintf(outside, sizeof outside, "%a", sum.outside);
    return integerText(sum.fixed) + ":" + outside;
}

bool parseSum(const std::string& s, FixedPointSum& out) {
    const std::size_t colon = s.find(':');
    if (colon == std::string::npos || !parseInteger(s.substr(0, colon), out.fixed)) return false;
    const std::string rest = s.substr(colon + 1);
    char* end = nullptr;
    out.outside = std::strtod(rest.c_str(), &end);
    return !rest.empty() && end == rest.c_str() + rest.size();
}

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> parts;
    std::size_t from = 0;
    for (std::size_t at; (at = s.find(sep, from)) != std::string::npos; from = at + 1) parts.push_back(s.substr(from, at - from));
    parts.push_back(s.substr(from));
    return parts;
}

} // namespace

VoxelStatistics& VoxelStatistics::operator+=(const VoxelStatistics& o) {
    for (int i = 0; i < kBins; ++i) histogram[std::size_t(i)] += o.histogram[std::size_t(i)];
    activeVoxels += o.activeVoxels;
    aboveOne += o.aboveOne;
    densitySums += o.densitySums;
    densityMax = std::max(densityMax, o.densityMax);
    unitAxes += o.unitAxes;
    for (int k = 0; k < 3; ++k) axisSums[std::size_t(k)] += o.axisSums[std::size_t(k)];
    return *this;
}

std::string statisticsRecord(const VoxelStatistics& s, std::uint64_t leaves) {
    std::string histogram;
    for (const std::uint64_t n : s.histogram) histogram += (histogram.empty() ? "" : ",") + std::to_string(n);
    char densityMax[64];
    std::snprintf(densityMax, sizeof densityMax, "%a", double(s.densityMax));
    return "version=1 leaves=" + std::to_string(leaves) + " active_voxels=" + std::to_string(s.activeVoxels) +
           " histogram=" + histogram + " above_one=" + std::to_string(s.aboveOne) + " density_max=" + densityMax +
           " density_sum=" + sumText(s.densitySums) + " unit_axes=" + std::to_string(s.unitAxes) + " axis_sums=" +
           sumText(s.axisSums[0]) + "," + sumText(s.axisSums[1]) + "," + sumText(s.axisSums[2]);
}

std::optional<RecordedStatistics> parseStatisticsRecord(const std::string& text, std::string& why) {
    std::map<std::string, std::string> words;
    for (const std::string& word : split(text, ' ')) {
        const std::size_t eq = word.find('=');
        if (eq == std::string::npos || !words.emplace(word.substr(0, eq), word.substr(eq + 1)).second) {
            why = "a word that is not NAME=VALUE, or a name twice";
            return std::nullopt;
        }
    }
    static const char* const names[] = {"version",    "leaves",      "active_voxels", "histogram", "above_one",
                                        "density_max", "density_sum", "unit_axes",     "axis_sums"};
    if (words.size() != std::size(names)) {
        why = "not the " + std::to_string(std::size(names)) + " items of version 1";
        return std::nullopt;
    }
    for (const char* name : names)
        if (!words.count(name)) {
            why = std::string("no ") + name;
            return std::nullopt;
        }
    if (words["version"] != "1") {
        why = "version " + words["version"] + " (this yarnvox reads version 1)";
        return std::nullopt;
    }
    RecordedStatistics r;
    VoxelStatistics& v = r.voxels;
    const std::vector<std::string> bins = split(words["histogram"], ','), axes = split(words["axis_sums"], ',');
    bool ok = parseUnsigned(words["leaves"], r.leaves) && parseUnsigned(words["active_voxels"], v.activeVoxels) &&
              parseUnsigned(words["above_one"], v.aboveOne) && parseUnsigned(words["unit_axes"], v.unitAxes) &&
              parseSum(words["density_sum"], v.densitySums) && bins.size() == VoxelStatistics::kBins && axes.size() == 3;
    for (std::size_t i = 0; ok && i < bins.size(); ++i) ok = parseUnsigned(bins[i], v.histogram[i]);
    for (std::size_t k = 0; ok && k < 3; ++k) ok = parseSum(axes[k], v.axisSums[k]);
    char* end = nullptr;
    const std::string& maxText = words["density_max"];
    v.densityMax = float(std::strtod(maxText.c_str(), &end));
    ok = ok && !maxText.empty() && end == maxText.c_str() + maxText.size();
    std::uint64_t binned = 0;
    for (const std::uint64_t n : v.histogram) binned += n;
    if (ok && (binned != v.activeVoxels || v.aboveOne > v.activeVoxels || v.unitAxes > v.activeVoxels)) {
        why = "counts that contradict each other";
        return std::nullopt;
    }
    if (!ok) {
        why = "a value that is not a number of its kind";
        return std::nullopt;
    }
    return r;
}

} // namespace yv
