// A seekable std::streambuf over a PendingFile (core/atomic_file.h), for
// exports written through a std::ostream: they too reach their name only
// once complete.
#pragma once

#include "core/atomic_file.h"

#include <cstdint>
#include <streambuf>
#include <string>

namespace yv {

/// For writers that take a std::ostream and seek back to fill in a header
/// (NanoVDB's io::writeGrids): bytes go straight to the file at the stream's
/// position, and a failed write surfaces as the stream's badbit with the
/// error kept here.
class PendingFileBuf : public std::streambuf {
  public:
    explicit PendingFileBuf(PendingFile& file) : file_(file) {}
    /// The first write error, empty when none.
    const std::string& error() const { return error_; }

  protected:
    std::streamsize xsputn(const char* s, std::streamsize n) override;
    int_type overflow(int_type c) override;
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override;
    pos_type seekpos(pos_type pos, std::ios_base::openmode which) override;

  private:
    PendingFile& file_;
    std::uint64_t at_ = 0;
    std::string error_;
};

} // namespace yv
