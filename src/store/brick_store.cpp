// The brick store's work directory: which files are ours, atomic writes,
// locking, and the BrickStore operations on top of manifest.h and region_file.h.
#include "store/brick_store.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/text.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <optional>
#include <span>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace yv {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr const char* kManifestName = "manifest";

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string joinPath(const std::string& dir, const std::string& name) { return (fs::path(dir) / name).string(); }

// ---------------------------------------------------------------------------
// Names in the work directory: only these are ours to create or delete.

std::string regionName(std::uint64_t id) { return "region-" + std::to_string(id) + ".yvb"; }

bool parseRegionName(const std::string& name, std::uint64_t& id) {
    constexpr std::string_view prefix = "region-", suffix = ".yvb";
    if (name.size() <= prefix.size() + suffix.size() || !name.starts_with(prefix) || !name.ends_with(suffix))
        return false;
    const char* first = name.data() + prefix.size();
    const char* last = name.data() + name.size() - suffix.size();
    const auto [ptr, ec] = std::from_chars(first, last, id);
    // Canonical spelling only: "region-007.yvb" was not written by us.
    return ec == std::errc() && ptr == last && name == regionName(id);
}

/// What a write cut short leaves: NAME.partial-PID-N (core/atomic_file.h),
/// or NAME.tmp-PID-N from yarnvox versions before it.
bool isTemporaryName(const std::string& name) {
    std::size_t at = name.find(".partial-");
    if (at == std::string::npos) at = name.find(".tmp-");
    if (at == std::string::npos) return false;
    const std::string base = name.substr(0, at);
    std::uint64_t id;
    return base == kManifestName || parseRegionName(base, id);
}

struct DirListing {
    bool manifest = false;
    std::vector<std::string> regions, temporaries, unknown;
};

DirListing listDir(const std::string& dir) {
    DirListing out;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        std::uint64_t id;
        std::error_code typeEc;
        const bool regular = it->is_regular_file(typeEc);
        if (regular && name == kManifestName)
            out.manifest = true;
        else if (regular && parseRegionName(name, id))
            out.regions.push_back(name);
        else if (regular && isTemporaryName(name))
            out.temporaries.push_back(name);
        else
            out.unknown.push_back(name);
    }
    if (ec) throw Error("cannot list work dir " + dir + ": " + ec.message());
    std::sort(out.regions.begin(), out.regions.end());
    std::sort(out.unknown.begin(), out.unknown.end());
    return out;
}

void removeOwnFile(const std::string& dir, const std::string& name) {
    const std::string path = joinPath(dir, name);
    if (::unlink(path.c_str()) != 0 && errno != ENOENT)
        throw Error("cannot delete " + path + ": " + errnoText(errno));
}

void writeManifest(const std::string& dir, int dirFd, const StoreManifest& m) {
    const std::string text = formatManifest(m);
    const std::span<const std::uint8_t> part(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
    writeFileAtomically(joinPath(dir, kManifestName), std::span(&part, 1), dirFd);
}

RegionHeader readHeaderOnly(const std::string& path, std::uint64_t& bytesOnDisk) {
    Fd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (fd.get() < 0) throw Error("cannot open " + path + ": " + errnoText(errno));
    struct stat st {};
    if (::fstat(fd.get(), &st) != 0) throw Error("cannot stat " + path + ": " + errnoText(errno));
    std::array<std::uint8_t, kRegionHeaderSize> b{};
    const std::size_t want = std::min<std::uint64_t>(kRegionHeaderSize, static_cast<std::uint64_t>(st.st_size));
    std::size_t got = 0;
    while (got < want) {
        const ssize_t n = ::pread(fd.get(), b.data() + got, want - got, static_cast<off_t>(got));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw Error("cannot read " + path + ": " + errnoText(errno));
        if (n == 0) break;
        got += static_cast<std::size_t>(n);
    }
    // A file that shrank under us reads as the short file it now is.
    bytesOnDisk = got < want ? got : static_cast<std::uint64_t>(st.st_size);
    return parseRegionHeader(b.data(), bytesOnDisk, path);
}

RegionInfo infoOf(const RegionHeader& h, std::uint64_t bytesOnDisk) {
    return {h.id, h.min, h.max, h.brickCount, h.activeVoxels, bytesOnDisk};
}

int openDirectory(const std::string& dir) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) throw Error("cannot open work dir " + dir + ": " + errnoText(errno));
    return fd;
}

/// Keeps two runs from sharing a work dir: one clearing it under the other
/// would lose work silently. Where locks are unsupported we go on unlocked.
void lockDirectory(int fd, bool exclusive, const std::string& dir) {
    if (::flock(fd, (exclusive ? LOCK_EX : LOCK_SH) | LOCK_NB) != 0 && errno == EWOULDBLOCK)
        throw Error(dir + ": another yarnvox process (or store) is using this work dir: wait for it to finish, "
                          "or give another --work-dir");
}

} // namespace

StoreManifest readManifest(const std::string& dir) {
    const std::string path = joinPath(dir, kManifestName);
    const auto bytes = readWholeFile(path);
    if (!bytes)
        throw Error(dir + ": no manifest: not a yarnvox work dir, or its run never started");
    return parseManifest(path, std::string(bytes->begin(), bytes->end()));
}

BrickStore::BrickStore(std::string dir, const StoreManifest& manifest, bool resume)
    : dir_(std::move(dir)), manifest_(manifest) {
    checkGrid(manifest.grid, dir_);
    manifest_.completeRegions.reset();
    manifest_.stageSeconds.clear();
    std::error_code ec;
    fs::create_directories(dir_, ec);
    if (ec) throw Error("cannot create work dir " + dir_ + ": " + ec.message());
    dirFd_ = openDirectory(dir_);
    try {
        lockDirectory(dirFd_, true, dir_);
        const DirListing listing = listDir(dir_);
        // Temporaries are what a crash left mid-write: never complete, always ours.
        const auto removeTemporaries = [&] {
            for (const std::string& name : listing.temporaries) removeOwnFile(dir_, name);
        };
        if (resume && listing.manifest) {
            const StoreManifest disk = readManifest(dir_);
            if (const std::string diff = runDifference(disk, manifest_); !diff.empty())
                throw Error(dir_ + ": this work dir belongs to a different run (" + diff +
                            "): use a fresh --work-dir, or drop --resume to start over in it");
            manifest_.completeRegions = disk.completeRegions;
            manifest_.stageSeconds = disk.stageSeconds;
            // The latest run describes the output: `yarnvox merge` uses its metadata.
            if (metadataFields(disk.run) != metadataFields(manifest_.run)) writeManifest(dir_, dirFd_, manifest_);
            removeTemporaries();
        } else {
            // Without a manifest nothing on disk is known to belong to this run: start over.
            if (!listing.unknown.empty())
                throw Error(dir_ + ": refusing to use this directory as a work dir: it holds " +
                            std::to_string(listing.unknown.size()) + " entr" +
                            (listing.unknown.size() == 1 ? "y" : "ies") + " yarnvox did not write (e.g. \"" +
                            listing.unknown.front() + "\"); give an empty or new --work-dir");
            // Manifest first: a crash halfway through leaves regions without a
            // manifest, which the next run clears in turn.
            if (listing.manifest) removeOwnFile(dir_, kManifestName);
            for (const std::string& name : listing.regions) removeOwnFile(dir_, name);
            removeTemporaries();
            writeManifest(dir_, dirFd_, manifest_);
        }
        fsyncDir(dirFd_, dir_);
    } catch (...) {
        ::close(dirFd_);
        throw;
    }
}

BrickStore::BrickStore(std::string dir, const StoreManifest& manifest, JoinStore) : dir_(std::move(dir)), manifest_(manifest) {
    checkGrid(manifest.grid, dir_);
    dirFd_ = openDirectory(dir_);
    try {
        const StoreManifest disk = readManifest(dir_);
        if (const std::string diff = runDifference(disk, manifest_); !diff.empty())
            throw Error(dir_ + ": the work dir rank 0 opened is of a different run than this rank's (" + diff +
                        "): every rank must see the same input and options");
        manifest_.completeRegions = disk.completeRegions;
    } catch (...) {
        ::close(dirFd_);
        throw;
    }
}

BrickStore::BrickStore(std::string dir) : dir_(std::move(dir)), readOnly_(true) {
    dirFd_ = openDirectory(dir_);
    try {
        lockDirectory(dirFd_, false, dir_);
        manifest_ = readManifest(dir_);
    } catch (...) {
        ::close(dirFd_);
        throw;
    }
}

BrickStore::~BrickStore() {
    if (dirFd_ >= 0) ::close(dirFd_);
}

void BrickStore::requireWritable(const char* what) const {
    if (readOnly_) throw Error(dir_ + ": cannot " + std::string(what) + ": the work dir was opened read-only");
}

std::string BrickStore::regionPath(std::uint64_t id) const { return joinPath(dir_, regionName(id)); }

BrickStore::RegionState BrickStore::verifyRegion(std::uint64_t id, glm::ivec3 min, glm::ivec3 max, std::string* whyNot) {
    requireWritable("check regions");
    const std::string path = regionPath(id);
    const auto bytes = readWholeFile(path);
    if (!bytes) {
        if (whyNot) *whyNot = path + ": not on disk";
        return RegionState::Missing;
    }
    try {
        const RegionHeader h = parseRegionHeader(bytes->data(), bytes->size(), path);
        checkRegionIdentity(h, manifest_, id, &min, &max, path);
        decodeRegionBody(bytes->data(), h, path, nullptr);
        return RegionState::Verified;
    } catch (const Error& e) {
        if (whyNot) *whyNot = e.what();
    }
    removeOwnFile(dir_, regionName(id));
    fsyncDir(dirFd_, dir_);
    return RegionState::Damaged;
}

RegionInfo BrickStore::writeRegion(std::uint64_t id, glm::ivec3 min, glm::ivec3 max, std::vector<VoxelBrick> bricks,
                                   RegionWriteTimings* timings) {
    requireWritable("write regions");
    if (min.x > max.x || min.y > max.y || min.z > max.z)
        throw Error("cannot write " + regionPath(id) + ": region bounds " + coordText(min) + "-" + coordText(max) +
                    " are inverted");
    auto t = Clock::now();
    EncodedRegion e = encodeRegion(manifest_, id, min, max, bricks, regionPath(id));
    bricks = {}; // the encoded copy is all we need from here on
    const double encodeSeconds = secondsSince(t);

    t = Clock::now();
    std::vector<std::span<const std::uint8_t>> parts{e.header, e.table};
    for (const auto& c : e.chunks) parts.emplace_back(c);
    writeFileAtomically(regionPath(id), parts, dirFd_);
    if (timings) {
        timings->encodeSeconds += encodeSeconds;
        timings->writeSeconds += secondsSince(t);
    }
    return infoOf(e.info, e.info.fileSize());
}

std::vector<RegionInfo> BrickStore::listRegions() const {
    std::vector<RegionInfo> out;
    for (const std::string& name : listDir(dir_).regions) {
        std::uint64_t id = 0, size = 0;
        parseRegionName(name, id);
        const std::string path = joinPath(dir_, name);
        const RegionHeader h = readHeaderOnly(path, size);
        checkRegionIdentity(h, manifest_, id, nullptr, nullptr, path);
        out.push_back(infoOf(h, size));
    }
    std::sort(out.begin(), out.end(), [](const RegionInfo& a, const RegionInfo& b) { return a.id < b.id; });
    return out;
}

std::vector<std::uint64_t> BrickStore::regionIds() const {
    std::vector<std::uint64_t> ids;
    for (const std::string& name : listDir(dir_).regions) {
        std::uint64_t id = 0;
        parseRegionName(name, id);
        ids.push_back(id);
    }
    std::sort(ids.begin(), ids.end());
    return ids;
}

RegionInfo BrickStore::regionInfo(std::uint64_t id) const {
    const std::string path = regionPath(id);
    std::uint64_t size = 0;
    const RegionHeader h = readHeaderOnly(path, size);
    checkRegionIdentity(h, manifest_, id, nullptr, nullptr, path);
    return infoOf(h, size);
}

std::vector<VoxelBrick> BrickStore::readRegion(std::uint64_t id) const {
    const std::string path = regionPath(id);
    const auto bytes = readWholeFile(path);
    if (!bytes) throw Error(path + ": region file missing");
    const RegionHeader h = parseRegionHeader(bytes->data(), bytes->size(), path);
    checkRegionIdentity(h, manifest_, id, nullptr, nullptr, path);
    std::vector<VoxelBrick> bricks;
    decodeRegionBody(bytes->data(), h, path, &bricks);
    return bricks;
}

BrickStore::ChunkReader::ChunkReader(const BrickStore& store, std::uint64_t id) : file_(store.regionPath(id)) {
    const std::string& path = file_.path();
    std::array<std::uint8_t, kRegionHeaderSize> head{};
    file_.read(0, std::span(head.data(), std::size_t(std::min<std::uint64_t>(head.size(), file_.size()))), "the header");
    header_ = parseRegionHeader(head.data(), file_.size(), path);
    checkRegionIdentity(header_, store.manifest(), id, nullptr, nullptr, path);
    std::vector<std::uint8_t> tableBytes(header_.dataOffset() - header_.indexOffset());
    file_.read(header_.indexOffset(), tableBytes, "the key index and chunk table");
    table_ = parseRegionTable(tableBytes.data(), header_, path);
}

RawBricks BrickStore::ChunkReader::read(std::size_t c, std::vector<std::uint8_t>& stored,
                                        std::vector<std::uint8_t>& raw) const {
    stored.resize(table_.chunks[c].stored);
    file_.read(table_.chunks[c].offset, stored, "chunk " + std::to_string(c));
    return decodeRegionChunk(stored.data(), table_, std::uint32_t(c), header_, file_.path(), raw);
}

void BrickStore::ChunkReader::checkActiveVoxels(std::uint64_t counted) const {
    checkActiveCount(header_, counted, file_.path());
}

void BrickStore::forEachChunk(std::uint64_t id, const std::function<void(const RawBricks&)>& visit) const {
    const ChunkReader reader(*this, id);
    struct Buffers {
        std::vector<std::uint8_t> stored, raw;
    };
    // Per thread, not per chunk: a chunk's 16 MiB are allocated once a thread.
    tbb::enumerable_thread_specific<Buffers> buffers;
    std::vector<std::string> errors(reader.chunkCount());
    std::vector<std::uint64_t> active(reader.chunkCount());
    tbb::parallel_for(std::size_t(0), reader.chunkCount(), [&](std::size_t c) {
        Buffers& b = buffers.local();
        try {
            const RawBricks bricks = reader.read(c, b.stored, b.raw);
            active[c] = countActive(bricks);
            visit(bricks);
        } catch (const Error& e) {
            errors[c] = e.what();
        }
    });
    // The first by position, so the message does not depend on thread timing.
    for (const std::string& e : errors)
        if (!e.empty()) throw Error(e);
    reader.checkActiveVoxels(std::accumulate(active.begin(), active.end(), std::uint64_t(0)));
}

void BrickStore::markComplete(std::uint64_t regionCount, const StageSeconds& stages) {
    requireWritable("mark the run complete");
    const std::size_t onDisk = listDir(dir_).regions.size();
    if (onDisk != regionCount)
        throw Error(dir_ + ": cannot mark the run complete: " + std::to_string(onDisk) +
                    " region files on disk, the run has " + std::to_string(regionCount) + " regions");
    manifest_.completeRegions = regionCount;
    manifest_.stageSeconds = stages;
    writeManifest(dir_, dirFd_, manifest_);
}

std::uint64_t BrickStore::bytesOnDisk() const {
    std::uint64_t sum = 0;
    for (const std::string& name : listDir(dir_).regions) {
        std::error_code ec;
        const auto size = fs::file_size(joinPath(dir_, name), ec);
        if (!ec) sum += size;
    }
    return sum;
}

} // namespace yv
