#include "gpu/program_cache.h"

#include <xxhash.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <system_error>

#include <unistd.h>

namespace yv {
namespace {

// File: the magic, the binary's format (u32), zero (u32), its length (u64),
// XXH64 of its bytes (u64, seed 0), then the bytes; little-endian as the
// machine writes them (a cache is never shared between machines).
constexpr char kMagic[8] = {'Y', 'V', 'P', 'R', 'O', 'G', '0', '1'};
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 8 + 8;

std::atomic<std::uint64_t> gLoaded{0}, gStored{0}, gRefused{0};

std::string glString(GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? reinterpret_cast<const char*>(s) : "";
}

} // namespace

std::optional<std::filesystem::path> programCacheDir() {
    if (const char* dir = std::getenv("YV_PROGRAM_CACHE"); dir && *dir) {
        if (std::strcmp(dir, "off") == 0) return std::nullopt;
        return std::filesystem::path(dir);
    }
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
        return std::filesystem::path(xdg) / "yarnvox" / "programs";
    if (const char* home = std::getenv("HOME"); home && *home)
        return std::filesystem::path(home) / ".cache" / "yarnvox" / "programs";
    return std::nullopt;
}

std::string driverIdentity() {
    return glString(GL_VENDOR) + "\n" + glString(GL_RENDERER) + "\n" + glString(GL_VERSION) + "\n" +
           glString(GL_SHADING_LANGUAGE_VERSION);
}

std::string programKey(const std::string& driver, const std::vector<std::pair<GLenum, std::string>>& stages) {
    XXH3_state_t* state = XXH3_createState();
    XXH3_128bits_reset(state);
    // Each part with its length first, so no two lists of parts hash the same bytes.
    const auto add = [&](const void* data, std::uint64_t n) {
        XXH3_128bits_update(state, &n, sizeof n);
        XXH3_128bits_update(state, data, n);
    };
    add(driver.data(), driver.size());
    for (const auto& [type, text] : stages) {
        const std::uint32_t t = type;
        add(&t, sizeof t);
        add(text.data(), text.size());
    }
    const XXH128_hash_t h = XXH3_128bits_digest(state);
    XXH3_freeState(state);
    char hex[33];
    std::snprintf(hex, sizeof hex, "%016llx%016llx", static_cast<unsigned long long>(h.high64),
                  static_cast<unsigned long long>(h.low64));
    return hex;
}

std::optional<ProgramBinary> loadCachedProgram(const std::filesystem::path& dir, const std::string& key) {
    std::ifstream in(dir / (key + ".bin"), std::ios::binary);
    if (!in) return std::nullopt;
    char header[kHeaderBytes];
    if (!in.read(header, sizeof header) || std::memcmp(header, kMagic, sizeof kMagic) != 0) return std::nullopt;
    std::uint32_t format = 0;
    std::uint64_t length = 0, checksum = 0;
    std::memcpy(&format, header + 8, 4);
    std::memcpy(&length, header + 16, 8);
    std::memcpy(&checksum, header + 24, 8);
    if (length == 0 || length > (std::uint64_t(1) << 30)) return std::nullopt;
    ProgramBinary binary{format, std::vector<std::uint8_t>(length)};
    if (!in.read(reinterpret_cast<char*>(binary.bytes.data()), std::streamsize(length)) || in.peek() != EOF)
        return std::nullopt;
    if (XXH64(binary.bytes.data(), binary.bytes.size(), 0) != checksum) return std::nullopt;
    return binary;
}

bool storeCachedProgram(const std::filesystem::path& dir, const std::string& key, const ProgramBinary& binary) {
    static std::atomic<unsigned> serial{0};
    std::error_code error;
    std::filesystem::create_directories(dir, error);
    if (error) return false;
    // No fsync: a file cut short by a crash fails its checksum and is compiled again.
    const std::filesystem::path path = dir / (key + ".bin");
    const std::filesystem::path partial =
        dir / (key + ".partial-" + std::to_string(::getpid()) + "-" + std::to_string(serial++));
    {
        std::ofstream out(partial, std::ios::binary | std::ios::trunc);
        char header[kHeaderBytes] = {};
        const std::uint32_t format = binary.format;
        const std::uint64_t length = binary.bytes.size(), checksum = XXH64(binary.bytes.data(), length, 0);
        std::memcpy(header, kMagic, sizeof kMagic);
        std::memcpy(header + 8, &format, 4);
        std::memcpy(header + 16, &length, 8);
        std::memcpy(header + 24, &checksum, 8);
        out.write(header, sizeof header);
        out.write(reinterpret_cast<const char*>(binary.bytes.data()), std::streamsize(length));
        if (!out.flush()) {
            out.close();
            std::filesystem::remove(partial, error);
            return false;
        }
    }
    std::filesystem::rename(partial, path, error);
    if (!error) return true;
    std::filesystem::remove(partial, error);
    return false;
}

ProgramCacheCounts programCacheCounts() { return {gLoaded.load(), gStored.load(), gRefused.load()}; }

void countProgramCache(std::uint64_t loaded, std::uint64_t stored, std::uint64_t refused) {
    gLoaded += loaded;
    gStored += stored;
    gRefused += refused;
}

} // namespace yv
