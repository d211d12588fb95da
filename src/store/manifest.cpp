// The manifest text (formats/brick-store.md, "Manifest"); file I/O is in brick_store.cpp.
#include "store/manifest.h"

#include "core/error.h"
#include "core/text.h"

#include <algorithm>
#include <charconv>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string_view>
#include <vector>

namespace yv {
namespace {

// 2: yarnvox_version and sampling_code lines.
constexpr std::uint64_t kVersion = 2;
constexpr const char* kManifestTitle = "yarnvox brick store";

std::string num(double v) {
    char s[40];
    std::snprintf(s, sizeof s, "%.17g", v);
    return s;
}

class ManifestParser {
  public:
    ManifestParser(std::string path, std::string_view text) : path_(std::move(path)), text_(text) {}

    bool atEnd() const { return pos_ >= text_.size(); }
    /// Whether the next line starts with `key` and a space.
    bool nextIs(std::string_view key) const {
        return !atEnd() && text_.substr(pos_).starts_with(key) && text_.substr(pos_ + key.size()).starts_with(' ');
    }

    /// The next line, without its newline.
    std::string_view rawLine(const std::string& shape) {
        line_ = nextLine_;
        if (atEnd()) fail("expected \"" + shape + "\", file ends");
        const std::size_t nl = text_.find('\n', pos_);
        const std::size_t end = nl == std::string_view::npos ? text_.size() : nl;
        const std::string_view line = text_.substr(pos_, end - pos_);
        pos_ = end + 1;
        ++nextLine_;
        return line;
    }
    /// Words after `key` on the next line, which must hold exactly `count` of them.
    std::vector<std::string> line(const std::string& key, std::size_t count, const std::string& shape) {
        const std::string_view text = rawLine(shape);
        std::istringstream words{std::string(text)};
        std::vector<std::string> w;
        for (std::string s; words >> s;) w.push_back(s);
        if (w.size() != count + 1 || w[0] != key)
            fail("expected \"" + shape + "\", found \"" + std::string(text) + "\"");
        return {w.begin() + 1, w.end()};
    }
    /// `n` bytes taken verbatim (they may hold newlines), then a newline.
    std::string blob(std::uint64_t n, const std::string& what) {
        line_ = nextLine_;
        if (pos_ >= text_.size() || text_.size() - pos_ <= n || text_[pos_ + n] != '\n')
            fail("expected " + std::to_string(n) + " bytes of " + what + " and a newline");
        const std::string b(text_.substr(pos_, n));
        nextLine_ += std::count(b.begin(), b.end(), '\n') + 1;
        pos_ += n + 1;
        return b;
    }

    std::uint64_t u64(const std::string& s, int base = 10) const {
        std::uint64_t v = 0;
        const char* first = s.data();
        if (base == 16) {
            if (!s.starts_with("0x")) bad(s);
            first += 2;
        }
        const auto [ptr, ec] = std::from_chars(first, s.data() + s.size(), v, base);
        if (ec != std::errc() || ptr != s.data() + s.size() || first == ptr) bad(s);
        return v;
    }
    int i32(const std::string& s) const {
        int v = 0;
        const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (ec != std::errc() || ptr != s.data() + s.size()) bad(s);
        return v;
    }
    double f64(const std::string& s) const {
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v)) bad(s);
        return v;
    }

    /// Fails at the line read last.
    [[noreturn]] void fail(const std::string& what) const {
        throw Error(path_ + ": line " + std::to_string(line_) + ": " + what);
    }

  private:
    [[noreturn]] void bad(const std::string& s) const { fail("malformed number \"" + s + "\""); }

    std::string path_;
    std::string_view text_;
    std::size_t pos_ = 0, line_ = 1, nextLine_ = 1;
};

} // namespace

StoreManifest parseManifest(const std::string& path, const std::string& text) {
    ManifestParser p(path, text);
    if (p.rawLine(kManifestTitle) != kManifestTitle)
        p.fail(std::string("expected \"") + kManifestTitle + "\": not a yarnvox work dir manifest");
    const std::uint64_t version = p.u64(p.line("version", 1, "version N")[0]);
    if (version != kVersion)
        p.fail("unsupported brick store version " + std::to_string(version) + ": expected " +
               std::to_string(kVersion) + " (written by another yarnvox version?)");
    StoreManifest m;
    m.yarnvoxVersion = p.line("yarnvox_version", 1, "yarnvox_version X.Y.Z")[0];
    m.samplingCode = p.u64(p.line("sampling_code", 1, "sampling_code 0xHEX")[0], 16);
    m.fingerprint = p.u64(p.line("fingerprint", 1, "fingerprint 0xHEX")[0], 16);
    const auto o = p.line("origin", 3, "origin X Y Z");
    m.grid.origin = {p.f64(o[0]), p.f64(o[1]), p.f64(o[2])};
    m.grid.voxelSize = p.f64(p.line("voxel_size", 1, "voxel_size H")[0]);
    const auto d = p.line("dims", 3, "dims NX NY NZ");
    m.grid.dims = {p.i32(d[0]), p.i32(d[1]), p.i32(d[2])};
    const std::string reduce = p.line("reduce", 1, "reduce mean|max")[0];
    if (reduce != "mean" && reduce != "max") p.fail("unknown reduce mode \"" + reduce + "\": expected mean or max");
    m.reduce = reduce == "max" ? Reduce::Max : Reduce::Mean;
    if (p.nextIs("run_metadata")) {
        const std::uint64_t n = p.u64(p.line("run_metadata", 1, "run_metadata BYTES")[0]);
        m.runMetadata = p.blob(n, "run metadata");
    }
    if (p.nextIs("complete")) m.completeRegions = p.u64(p.line("complete", 1, "complete N")[0]);
    while (m.completeRegions && p.nextIs("stage")) {
        const auto w = p.line("stage", 2, "stage NAME SECONDS");
        const double seconds = p.f64(w[1]);
        if (!isStageName(w[0]) || seconds < 0.0)
            p.fail("expected \"stage NAME SECONDS\" with a name of letters, digits, '_' and '.' and seconds not negative");
        m.stageSeconds.emplace_back(w[0], seconds);
    }
    if (!p.atEnd()) {
        p.rawLine("");
        p.fail("unexpected line after the last field");
    }
    checkGrid(m.grid, path);
    return m;
}

void checkGrid(const VoxelGrid& g, const std::string& where) {
    const bool ok = std::isfinite(g.origin.x) && std::isfinite(g.origin.y) && std::isfinite(g.origin.z) &&
                    std::isfinite(g.voxelSize) && g.voxelSize > 0 && g.dims.x >= 0 && g.dims.y >= 0 && g.dims.z >= 0 &&
                    g.dims.x % 8 == 0 && g.dims.y % 8 == 0 && g.dims.z % 8 == 0;
    if (!ok)
        throw Error(where + ": invalid grid (origin " + num(g.origin.x) + " " + num(g.origin.y) + " " +
                    num(g.origin.z) + ", voxel size " + num(g.voxelSize) + ", dims " + coordText(g.dims) +
                    "): expected finite values, a positive voxel size and dims that are multiples of 8");
}

std::string formatManifest(const StoreManifest& m) {
    std::string s = std::string(kManifestTitle) + "\n";
    s += "version " + std::to_string(kVersion) + "\n";
    s += "yarnvox_version " + m.yarnvoxVersion + "\n";
    s += "sampling_code " + hex64(m.samplingCode) + "\n";
    s += "fingerprint " + hex64(m.fingerprint) + "\n";
    s += "origin " + num(m.grid.origin.x) + " " + num(m.grid.origin.y) + " " + num(m.grid.origin.z) + "\n";
    s += "voxel_size " + num(m.grid.voxelSize) + "\n";
    s += "dims " + std::to_string(m.grid.dims.x) + " " + std::to_string(m.grid.dims.y) + " " +
         std::to_string(m.grid.dims.z) + "\n";
    s += std::string("reduce ") + toString(m.reduce) + "\n";
    // Length-prefixed, so the caller's text may hold anything, newlines included.
    if (!m.runMetadata.empty())
        s += "run_metadata " + std::to_string(m.runMetadata.size()) + "\n" + m.runMetadata + "\n";
    if (m.completeRegions) s += "complete " + std::to_string(*m.completeRegions) + "\n";
    if (m.completeRegions)
        for (const auto& [name, seconds] : m.stageSeconds) s += "stage " + name + " " + num(seconds) + "\n";
    return s;
}

bool sameGrid(const VoxelGrid& a, const VoxelGrid& b) {
    return a.origin == b.origin && a.voxelSize == b.voxelSize && a.dims == b.dims;
}

namespace {

/// The value of line "key=value" in `text`, or "".
std::string metadataLine(const std::string& text, const std::string& key) {
    const std::string prefix = key + "=";
    for (std::size_t at = 0; at < text.size();) {
        const std::size_t end = std::min(text.find('\n', at), text.size());
        if (text.compare(at, prefix.size(), prefix) == 0) return text.substr(at + prefix.size(), end - at - prefix.size());
        at = end + 1;
    }
    return "";
}

} // namespace

std::string runDifference(const StoreManifest& disk, const StoreManifest& now) {
    std::string d;
    const auto add = [&](const std::string& s) { d += (d.empty() ? "" : "; ") + s; };
    if (disk.yarnvoxVersion != now.yarnvoxVersion)
        add("made by yarnvox " + disk.yarnvoxVersion + ", this is " + now.yarnvoxVersion);
    else if (disk.samplingCode != now.samplingCode)
        add("the sampling code differs (" + hex64(disk.samplingCode) + " on disk, " + hex64(now.samplingCode) +
            " in this yarnvox): its regions may hold other values");
    else if (disk.fingerprint != now.fingerprint) {
        // The run metadata is the caller's "key=value" lines; where it names
        // the backend, a change of backend is the likely reason.
        const std::string before = metadataLine(disk.runMetadata, "backend"), after = metadataLine(now.runMetadata, "backend");
        if (!before.empty() && !after.empty() && before != after)
            add("made with --backend " + before + ", this run uses --backend " + after);
        add("fingerprint " + hex64(disk.fingerprint) + " on disk, " + hex64(now.fingerprint) + " for this run");
    }
    if (!sameGrid(disk.grid, now.grid))
        add("grid on disk has origin (" + num(disk.grid.origin.x) + ", " + num(disk.grid.origin.y) + ", " +
            num(disk.grid.origin.z) + "), voxel size " + num(disk.grid.voxelSize) + ", dims " + coordText(disk.grid.dims) +
            "; this run has origin (" + num(now.grid.origin.x) + ", " + num(now.grid.origin.y) + ", " +
            num(now.grid.origin.z) + "), voxel size " + num(now.grid.voxelSize) + ", dims " + coordText(now.grid.dims));
    if (disk.reduce != now.reduce)
        add(std::string("reduce ") + toString(disk.reduce) + " on disk, " + toString(now.reduce) + " for this run");
    return d;
}

} // namespace yv
