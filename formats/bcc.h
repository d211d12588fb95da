// BCC (Binary Curve Collection) reader and writer. Spec: formats/bcc.md.
#pragma once

#include "garment/garment.h"

#include <cstdint>
#include <string>
#include <vector>

namespace yv {

/// Parses a BCC file held in memory. `name` is used in error messages only.
/// Throws yv::Error naming the byte offset and what was expected on a
/// truncated, inconsistent or unsupported file.
Garment parseBcc(const std::vector<std::uint8_t>& bytes, const std::string& name);

/// Reads a BCC file from disk (C0 and PL curves, 3D, open and closed).
Garment readBcc(const std::string& path);

/// Encodes a garment as BCC bytes (curve type from garment.curveType).
std::vector<std::uint8_t> encodeBcc(const Garment& garment);

/// Writes a garment to `path` atomically (temporary name, then rename).
void writeBcc(const std::string& path, const Garment& garment);

} // namespace yv
