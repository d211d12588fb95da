// The 1D transfer function of the ray cast: density in [0, 1] to colour and
// opacity, as 256 entries the shader reads with linear filtering. Presets by
// name, or a colour map file (formats/transfer-function.md).
#pragma once

#include <glm/vec4.hpp>

#include <array>
#include <string>
#include <vector>

namespace yv {

/// rgb in [0, 1]; a is the opacity of one voxel's length of that density.
using TransferFunction = std::array<glm::vec4, 256>;

/// Names of the presets, the default first.
const std::vector<std::string>& transferFunctionPresets();

/// The default preset (the first, "fibre").
TransferFunction defaultTransferFunction();

/// A preset by name, or, when `nameOrPath` is no preset, the colour map file
/// at that path. Throws yv::Error naming the file and line on a bad file.
TransferFunction loadTransferFunction(const std::string& nameOrPath);

/// Parses colour map text (`name` is used in errors).
TransferFunction parseColourMap(const std::string& text, const std::string& name);

} // namespace yv
