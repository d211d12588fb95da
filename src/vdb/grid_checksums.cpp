#include "vdb/grid_checksums.h"

#include "core/error.h"
#include "core/text.h"
#include "vdb/file_cursor.h"
#include "vdb/vdb_index.h"

#include <xxhash.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace yv {
RangeChecksum::RangeChecksum(std::uint64_t begin, std::uint64_t end) : begin_(begin), end_(std::max(begin, end)) {
    const std::uint64_t first = begin_ / kChecksumBlockBytes;
    const std::uint64_t last = end_ == begin_ ? first : (end_ - 1) / kChecksumBlockBytes + 1;
    pieces_.assign(last - first, 0);
}

void RangeChecksum::add(std::uint64_t at, std::span<const std::uint8_t> bytes) {
    YV_CHECK(at % kChecksumBlockBytes == 0);
    const std::uint64_t lo = std::max(at, begin_), hi = std::min(at + bytes.size(), end_);
    for (std::uint64_t block = lo / kChecksumBlockBytes * kChecksumBlockBytes; block < hi; block += kChecksumBlockBytes) {
        const std::uint64_t from = std::max(block, lo), to = std::min(block + kChecksumBlockBytes, hi);
        pieces_[block / kChecksumBlockBytes - begin_ / kChecksumBlockBytes] = XXH64(bytes.data() + (from - at), to - from, 0);
    }
}

void RangeChecksum::setBlock(std::uint64_t at, std::uint64_t hash) {
    YV_CHECK(at % kChecksumBlockBytes == 0 && at >= begin_ && at + kChecksumBlockBytes <= end_);
    pieces_[at / kChecksumBlockBytes - begin_ / kChecksumBlockBytes] = hash;
}

std::uint64_t blockChecksum(std::span<const std::uint8_t> block) {
    YV_CHECK(block.size() == kChecksumBlockBytes);
    return XXH64(block.data(), block.size(), 0);
}

std::uint64_t RangeChecksum::value() const {
    std::vector<std::uint8_t> bytes(pieces_.size() * 8);
    for (std::size_t i = 0; i < pieces_.size(); ++i)
        for (int b = 0; b < 8; ++b) bytes[8 * i + b] = std::uint8_t(pieces_[i] >> (8 * b));
    return XXH64(bytes.data(), bytes.size(), 0);
}

std::string checksumText(const std::vector<std::string>& gridNames, const std::vector<std::uint64_t>& sums) {
    YV_CHECK(gridNames.size() == sums.size());
    std::string text;
    for (std::size_t n = 0; n < sums.size(); ++n) {
        char hex[17];
        std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(sums[n]));
        text += (n ? " " : "") + gridNames[n] + "=" + hex;
    }
    return text;
}

namespace {

struct GridBytes {
    std::string name;
    std::uint64_t begin = 0, end = 0;
};

/// Every grid's name and bytes, from the descriptors (whatever the grids'
/// compression: blosc and zip files are outside the reader's subset).
std::vector<GridBytes> gridBytes(const VdbIndex& index) {
    std::vector<GridBytes> out;
    FileCursor in(index.file(), index.gridsPos(), 1u << 16);
    for (std::uint32_t n = 0; n < index.gridCount(); ++n) {
        GridBytes g;
        g.begin = in.position();
        g.name = in.string("grid name", 1u << 16);
        in.string("grid '" + shownName(g.name) + "' type", 1u << 10);
        in.string("grid '" + shownName(g.name) + "' instance parent", 1u << 16);
        in.skip(16); // its start and the start of its leaf buffers
        const auto end = in.pod<std::int64_t>("grid '" + shownName(g.name) + "' end");
        if (end < std::int64_t(in.position()) || std::uint64_t(end) > index.file().size())
            throw Error(index.path() + ": grid '" + shownName(g.name) + "': its descriptor places its end at byte " +
                        std::to_string(end) + ", outside the file's " + std::to_string(index.file().size()) +
                        " bytes (truncated or damaged)");
        g.end = std::uint64_t(end);
        in.seek(g.end);
        out.push_back(std::move(g));
    }
    return out;
}

/// The 16 hex digits at `text[at]`, or false.
bool parseHex(const std::string& text, std::size_t at, std::uint64_t& value) {
    value = 0;
    for (std::size_t i = at; i < at + 16; ++i) {
        const char c = i < text.size() ? text[i] : ' ';
        const int digit = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
        if (digit < 0) return false;
        value = value << 4 | std::uint64_t(digit);
    }
    return true;
}

/// The checksum of bytes [begin, end) of the file.
std::uint64_t checksumOf(const ReadOnlyFile& file, const std::string& what, std::uint64_t begin, std::uint64_t end) {
    RangeChecksum sum(begin, end);
    std::vector<std::uint8_t> buffer(1u << 20);
    for (std::uint64_t from = begin / kChecksumBlockBytes * kChecksumBlockBytes; from < end; from += buffer.size()) {
        const std::uint64_t n = std::min<std::uint64_t>(buffer.size(), end - from);
        file.read(from, std::span(buffer.data(), n), what);
        sum.add(from, std::span(buffer.data(), n));
    }
    return sum.value();
}

} // namespace

std::size_t verifyGridChecksums(const VdbIndex& index) {
    const StoredMetadata* item = nullptr;
    for (const StoredMetadata& m : index.fileMetadata())
        if (m.name == kGridChecksumsName) item = &m;
    if (!item) return 0;
    const std::string& path = index.path();
    const std::string bad = path + ": file metadata item " + kGridChecksumsName;
    // A string item's bytes are the text.
    if (item->type != "string") throw Error(bad + " is of type '" + shownName(item->type) + "', not string (damaged)");
    const std::string text(item->value.begin(), item->value.end());
    const std::vector<GridBytes> grids = gridBytes(index);
    std::vector<std::string> names;
    for (const GridBytes& g : grids) names.push_back(g.name);
    if (text.size() != checksumText(names, std::vector<std::uint64_t>(grids.size(), 0)).size())
        throw Error(bad + " does not list the file's " + std::to_string(grids.size()) + " grids (damaged)");
    std::size_t at = 0;
    for (const GridBytes& g : grids) {
        const std::string what = "grid '" + shownName(g.name) + "'";
        std::uint64_t recorded = 0;
        if (text.compare(at, g.name.size() + 1, g.name + "=") != 0 || !parseHex(text, at + g.name.size() + 1, recorded))
            throw Error(bad + " does not give " + what + " a checksum where the file has it (damaged)");
        at += g.name.size() + 18; // the name, '=', 16 digits and a space
        if (checksumOf(index.file(), what, g.begin, g.end) != recorded)
            throw Error(path + ": " + what + ": its bytes " + std::to_string(g.begin) + " to " + std::to_string(g.end) +
                        " do not match the checksum the file records: changed or damaged since yarnvox wrote it");
    }
    return grids.size();
}

} // namespace yv
