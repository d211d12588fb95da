#include "export/pending_file_buf.h"

#include "core/error.h"

namespace yv {

std::streamsize PendingFileBuf::xsputn(const char* s, std::streamsize n) {
    if (!error_.empty()) return 0;
    try {
        file_.writeAt(at_, s, std::size_t(n));
        at_ += std::uint64_t(n);
    } catch (const Error& e) {
        error_ = e.what();
        return 0;
    }
    return n;
}

PendingFileBuf::int_type PendingFileBuf::overflow(int_type c) {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
}

PendingFileBuf::pos_type PendingFileBuf::seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) {
    if (!(which & std::ios_base::out)) return pos_type(off_type(-1));
    const off_type base = dir == std::ios_base::beg ? 0 : dir == std::ios_base::cur ? off_type(at_) : off_type(file_.size());
    if (base + off < 0) return pos_type(off_type(-1));
    at_ = std::uint64_t(base + off);
    return pos_type(off_type(at_));
}

PendingFileBuf::pos_type PendingFileBuf::seekpos(pos_type pos, std::ios_base::openmode which) {
    return seekoff(off_type(pos), std::ios_base::beg, which);
}

} // namespace yv
