// A file written in pieces under a temporary name of the process's own and
// renamed into place only once complete: exports too large to hold in memory
// stream through it, and a failed or interrupted export never leaves a file
// under the output's name (the same rule as src/core/atomic_file.h, for
// output that arrives piece by piece).
#pragma once

#include <cstddef>
#include <cstdint>
#include <streambuf>
#include <string>

namespace yv {

class StagedFile {
  public:
    /// Creates PATH.partial-PID-N beside `path`; throws yv::Error naming `path` when it cannot.
    explicit StagedFile(std::string path);
    /// Removes the temporary file unless publish() ran.
    ~StagedFile();
    StagedFile(const StagedFile&) = delete;
    StagedFile& operator=(const StagedFile&) = delete;

    /// Appends `n` bytes; every failed write (a full disk) throws yv::Error.
    void append(const void* data, std::size_t n) { writeAt(size_, data, n); }
    /// Writes `n` bytes at byte `offset` (for writers that seek back to a header).
    void writeAt(std::uint64_t offset, const void* data, std::size_t n);
    /// fsync and close: the data are on disk, still under the temporary name.
    void finish();
    /// Renames the finished file into place and syncs its directory. Call
    /// after finish(), once every file of the export is finished.
    void publish();

    const std::string& path() const { return path_; }
    std::uint64_t size() const { return size_; }

  private:
    std::string path_, tmp_;
    int fd_ = -1;
    std::uint64_t size_ = 0;
    bool published_ = false;
};

/// A seekable std::streambuf over a StagedFile, for writers that take a
/// std::ostream and seek back to fill in a header (NanoVDB's io::writeGrids):
/// bytes go straight to the file at the stream's position, and a failed
/// write surfaces as the stream's badbit with the error kept here.
class StagedFileBuf : public std::streambuf {
  public:
    explicit StagedFileBuf(StagedFile& file) : file_(file) {}
    /// The first write error, empty when none.
    const std::string& error() const { return error_; }

  protected:
    std::streamsize xsputn(const char* s, std::streamsize n) override;
    int_type overflow(int_type c) override;
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override;
    pos_type seekpos(pos_type pos, std::ios_base::openmode which) override;

  private:
    StagedFile& file_;
    std::uint64_t at_ = 0;
    std::string error_;
};

} // namespace yv
