// BCC reader and writer; the layout is described in formats/bcc.md.
#include "bcc.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/world_units.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <mutex>
#include <optional>
#include <utility>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace yv {
namespace {

constexpr std::size_t kHeaderSize = 64;
constexpr std::size_t kPointSize = 3 * 4;
// A curve's count plus the two points every curve must have: the least a
// curve can occupy, used to bound a header's curve count by the file size.
constexpr std::size_t kMinCurveSize = 4 + 2 * kPointSize;
constexpr std::uint8_t kByteCount = 0x44;
constexpr char kAxes[] = "xyz";

// Bytes are assembled by hand so the format stays little-endian on any host.
std::uint64_t loadLe(const std::uint8_t* p, int n) {
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= std::uint64_t{p[i]} << (8 * i);
    return v;
}

void storeLe(std::vector<std::uint8_t>& out, std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

// Header fields are shown as text when printable so a wrong file type is
// recognisable in the message, and as hex escapes otherwise.
std::string quoted(const std::uint8_t* p, std::size_t n) {
    std::string s = "\"";
    for (std::size_t i = 0; i < n; ++i) {
        if (p[i] >= 0x20 && p[i] < 0x7f && p[i] != '"' && p[i] != '\\') {
            s += static_cast<char>(p[i]);
        } else {
            char hex[5];
            std::snprintf(hex, sizeof hex, "\\x%02x", p[i]);
            s += hex;
        }
    }
    return s + "\"";
}

Error byteError(const std::string& name, std::size_t offset, const std::string& what) {
    return Error(name + ": byte " + std::to_string(offset) + ": " + what);
}

[[noreturn]] void fail(const std::string& name, std::size_t offset, const std::string& what) {
    throw byteError(name, offset, what);
}

/// Reads until `n` bytes or the end of the file; returns how many arrived.
std::size_t readUpTo(int fd, std::uint8_t* out, std::size_t n, const std::string& path) {
    std::size_t used = 0;
    while (used < n) {
        const ssize_t got = ::read(fd, out + used, n - used);
        if (got == 0) break;
        if (got < 0) {
            if (errno == EINTR) continue;
            throw Error("cannot read " + path + ": " + errnoText(errno));
        }
        used += static_cast<std::size_t>(got);
    }
    return used;
}

/// Checks the fixed header fields of `p` (`size` bytes, possibly fewer than
/// the header: the signature is judged first, so a short non-BCC file is
/// called that, not "truncated") and sets the curve type.
void checkHeader(const std::uint8_t* p, std::size_t size, const std::string& name, Garment& garment) {
    const std::size_t sigLen = std::min<std::size_t>(size, 3);
    if (std::string(p, p + sigLen) != std::string("BCC", sigLen))
        fail(name, 0, "expected signature \"BCC\", found " + quoted(p, sigLen));
    if (size < kHeaderSize)
        fail(name, size, "truncated header: expected 64-byte header, file ends");
    if (p[3] != kByteCount) {
        char found[5];
        std::snprintf(found, sizeof found, "0x%02x", p[3]);
        fail(name, 3, std::string("unsupported byteCount ") + found +
                          ": expected 0x44 (4-byte integers and 4-byte floats)");
    }
    const std::string type(p + 4, p + 6);
    if (type == "C0")
        garment.curveType = CurveType::CatmullRom;
    else if (type == "PL")
        garment.curveType = CurveType::Polyline;
    else if (type == "BS")
        garment.curveType = CurveType::BSpline;
    else if (type == "BZ")
        garment.curveType = CurveType::Bezier;
    else
        fail(name, 4, "unsupported curve type " + quoted(p + 4, 2) +
                          ": expected \"C0\" (Catmull-Rom), \"PL\" (polyline), \"BS\" (B-spline) or \"BZ\" (Bezier)");
    if (p[6] != 3) fail(name, 6, "unsupported dimensions " + std::to_string(p[6]) + ": expected 3");
}

/// The exact file size the header's counts imply (each curve: a 4-byte count
/// and 12 bytes per point); nullopt when it does not fit in 64 bits.
std::optional<std::uint64_t> impliedSize(const std::uint8_t* p) {
    const std::uint64_t curves = loadLe(p + 8, 8), points = loadLe(p + 16, 8);
    constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
    if (curves > (kMax - kHeaderSize) / 4) return std::nullopt;
    const std::uint64_t countBytes = kHeaderSize + 4 * curves;
    if (points > (kMax - countBytes) / kPointSize) return std::nullopt;
    return countBytes + kPointSize * points;
}

/// "yarn-radius=R" in the 40-byte free-text field (written by yarnvox) gives
/// the radius; text that says yarn-radius= but is no sane length is refused,
/// not ignored.
void readRadius(const std::uint8_t* p, const std::string& name, Garment& garment) {
    const std::string info(reinterpret_cast<const char*>(p + 24), strnlen(reinterpret_cast<const char*>(p + 24), 40));
    const std::size_t at = info.find("yarn-radius=");
    if (at == std::string::npos) return;
    const char* begin = info.c_str() + at + 12;
    char* end = nullptr;
    const double r = std::strtod(begin, &end);
    const std::string text(begin, std::find(begin, info.c_str() + info.size(), ' '));
    if (end == begin)
        fail(name, 24 + at, "file info says yarn-radius=" + text + ", which is not a number");
    if (const std::string problem = lengthProblem(r); !problem.empty())
        fail(name, 24 + at, "file info's yarn-radius=" + text + ": " + problem + " (--yarn-radius overrides it)");
    garment.yarnRadius = r;
}

} // namespace

Garment parseBcc(const std::vector<std::uint8_t>& bytes, const std::string& name) {
    const std::uint8_t* p = bytes.data();
    const std::size_t size = bytes.size();
    Garment garment;
    checkHeader(p, size, name, garment);

    const std::uint64_t curveCount = loadLe(p + 8, 8);
    const std::uint64_t totalPoints = loadLe(p + 16, 8);
    // Checked before reserving so a corrupt count cannot trigger a huge allocation.
    if (curveCount > (size - kHeaderSize) / kMinCurveSize)
        fail(name, 8, "curve count " + std::to_string(curveCount) + " cannot fit: each curve needs at least " +
                          std::to_string(kMinCurveSize) + " bytes and " +
                          std::to_string(size - kHeaderSize) + " bytes follow the header");
    garment.yarns.reserve(curveCount);
    readRadius(p, name, garment);

    // Each curve's count says where the next begins: the counts are read in
    // file order, the points then on every core. A broken count is said
    // after any bad point of a curve before it, as a reading in file order would.
    struct CurveBytes {
        std::size_t at; ///< its first point
        std::uint64_t points;
        bool closed;
    };
    std::vector<CurveBytes> curves;
    curves.reserve(curveCount);
    std::size_t at = kHeaderSize;
    std::uint64_t pointSum = 0;
    std::exception_ptr brokenCount;
    for (std::uint64_t i = 0; i < curveCount && !brokenCount; ++i) {
        try {
            // Built only on failure: files hold up to millions of curves.
            const auto curve = [i] { return "curve " + std::to_string(i); };
            if (size - at < 4)
                fail(name, at, "truncated " + curve() + ": expected 4-byte control-point count, file ends");
            const auto raw = static_cast<std::int32_t>(loadLe(p + at, 4));
            // Widened before negating: -INT32_MIN does not fit in 32 bits.
            const std::uint64_t n = static_cast<std::uint64_t>(std::abs(std::int64_t{raw}));
            if (n < 2)
                fail(name, at, curve() + " has " + std::to_string(n) + " control points: expected at least 2");
            at += 4;
            if ((size - at) / kPointSize < n)
                fail(name, at, "truncated " + curve() + ": expected " + std::to_string(n) + " control points (" +
                                   std::to_string(n * kPointSize) + " bytes), file ends after " +
                                   std::to_string(size - at));
            curves.push_back({at, n, raw < 0});
            at += n * kPointSize;
            pointSum += n;
        } catch (const Error&) {
            brokenCount = std::current_exception();
        }
    }

    garment.yarns.resize(curves.size());
    std::mutex firstBadMutex;
    std::size_t firstBad = curves.size();
    std::exception_ptr badPoint;
    tbb::parallel_for(std::size_t(0), curves.size(), [&](std::size_t i) {
        const CurveBytes& c = curves[i];
        Yarn& yarn = garment.yarns[i];
        yarn.closed = c.closed;
        yarn.points.resize(c.points);
        for (std::uint64_t j = 0; j < c.points; ++j)
            for (int k = 0; k < 3; ++k) {
                const std::size_t from = c.at + (j * 3 + k) * 4;
                const float v = std::bit_cast<float>(static_cast<std::uint32_t>(loadLe(p + from, 4)));
                if (const std::string problem = coordinateProblem(v); !problem.empty()) {
                    const std::lock_guard lock(firstBadMutex);
                    if (i < firstBad) {
                        firstBad = i;
                        badPoint = std::make_exception_ptr(byteError(
                            name, from, "curve " + std::to_string(i) + " point " + std::to_string(j) + ": " +
                                            kAxes[k] + " coordinate " + problem));
                    }
                    return;
                }
                yarn.points[j][k] = v;
            }
    });
    if (badPoint) std::rethrow_exception(badPoint);
    if (brokenCount) std::rethrow_exception(brokenCount);

    if (at != size)
        fail(name, at, std::to_string(size - at) + " trailing bytes after the last of " +
                           std::to_string(curveCount) + " curves: expected end of file (curve count too small?)");
    if (pointSum != totalPoints)
        fail(name, 16, "header total control-point count " + std::to_string(totalPoints) +
                           " does not match the curves' sum " + std::to_string(pointSum));
    return garment;
}

Garment readBcc(const std::string& path) {
    // The header is read and checked before anything else: /dev/zero, a pipe
    // or a huge file of another kind is refused after 64 bytes.
    const Fd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (fd.get() < 0) throw Error("cannot open " + path + ": " + errnoText(errno));
    std::vector<std::uint8_t> bytes(kHeaderSize);
    bytes.resize(readUpTo(fd.get(), bytes.data(), kHeaderSize, path));
    Garment header;
    checkHeader(bytes.data(), bytes.size(), path, header);

    // The header's counts fix the file's size exactly; only that many bytes
    // (and one more, to see trailing bytes) are ever read or allocated, and
    // storage grows with the bytes that arrive, not with what the header claims.
    const std::optional<std::uint64_t> implied = impliedSize(bytes.data());
    if (!implied)
        fail(path, 8, "curve count " + std::to_string(loadLe(bytes.data() + 8, 8)) + " and control-point count " +
                          std::to_string(loadLe(bytes.data() + 16, 8)) + " cannot describe a file");
    struct stat st {};
    if (::fstat(fd.get(), &st) != 0) throw Error("cannot stat " + path + ": " + errnoText(errno));
    if (S_ISREG(st.st_mode) && std::uint64_t(st.st_size) > *implied)
        fail(path, *implied, std::to_string(std::uint64_t(st.st_size) - *implied) + " bytes past the " +
                                 std::to_string(*implied) + " that the header's counts describe (" +
                                 std::to_string(loadLe(bytes.data() + 8, 8)) + " curves, " +
                                 std::to_string(loadLe(bytes.data() + 16, 8)) + " control points)");
    const std::uint64_t limit = S_ISREG(st.st_mode) ? std::uint64_t(st.st_size) : *implied + 1;
    if (S_ISREG(st.st_mode)) bytes.reserve(limit); // the file's own size: no growth, no copies
    constexpr std::size_t kChunk = std::size_t(1) << 22;
    while (bytes.size() < limit) {
        const std::size_t used = bytes.size();
        const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(kChunk, limit - used));
        bytes.resize(used + want);
        const std::size_t got = readUpTo(fd.get(), bytes.data() + used, want, path);
        bytes.resize(used + got);
        if (got < want) break;
    }
    return parseBcc(bytes, path);
}

std::vector<std::uint8_t> encodeBcc(const Garment& garment) {
    std::vector<std::uint8_t> out;
    out.reserve(kHeaderSize + garment.yarns.size() * 4 + garment.controlPointCount() * kPointSize);
    out.insert(out.end(), {'B', 'C', 'C', kByteCount});
    const char* type = garment.curveType == CurveType::Polyline  ? "PL"
                       : garment.curveType == CurveType::BSpline ? "BS"
                       : garment.curveType == CurveType::Bezier  ? "BZ"
                                                                 : "C0";
    out.insert(out.end(), {static_cast<std::uint8_t>(type[0]), static_cast<std::uint8_t>(type[1]), 3, 2});
    storeLe(out, garment.yarns.size(), 8);
    storeLe(out, garment.controlPointCount(), 8);
    // The radius travels in the free-text field, which other readers ignore.
    std::string info = "yarnvox";
    if (garment.yarnRadius > 0) {
        char radius[32];
        std::snprintf(radius, sizeof radius, " yarn-radius=%.9g", garment.yarnRadius);
        info += radius;
    }
    out.insert(out.end(), info.begin(), info.end());
    out.resize(kHeaderSize, 0);

    for (std::size_t i = 0; i < garment.yarns.size(); ++i) {
        const Yarn& yarn = garment.yarns[i];
        const std::string where = "cannot encode BCC: yarn " + std::to_string(i);
        const std::size_t n = yarn.points.size();
        // Refused here so we never write a file our own reader rejects.
        if (n < 2) throw Error(where + " has " + std::to_string(n) + " control points: expected at least 2");
        if (n > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
            throw Error(where + " has " + std::to_string(n) + " control points: BCC stores at most 2^31-1");
        const auto count = static_cast<std::int32_t>(n);
        storeLe(out, static_cast<std::uint32_t>(yarn.closed ? -count : count), 4);
        for (std::size_t j = 0; j < n; ++j) {
            for (int k = 0; k < 3; ++k) {
                const double v = yarn.points[j][k];
                if (const std::string problem = coordinateProblem(v); !problem.empty())
                    throw Error(where + " point " + std::to_string(j) + ": " + kAxes[k] + " coordinate " + problem);
                storeLe(out, std::bit_cast<std::uint32_t>(static_cast<float>(v)), 4);
            }
        }
    }
    return out;
}

void writeBcc(const std::string& path, const Garment& garment) {
    std::vector<std::uint8_t> bytes;
    try {
        bytes = encodeBcc(garment);
    } catch (const Error& e) {
        throw Error(path + ": " + e.what());
    }

    writeFileAtomically(path, bytes);
}

} // namespace yv
