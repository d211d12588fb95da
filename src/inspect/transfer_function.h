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

/// The limits of withOpacityScale's factor (the live view's opacity control).
constexpr double kMinOpacityScale = 1.0 / 64.0, kMaxOpacityScale = 64.0;

/// `tf` with every entry's extinction times `factor`: opacity a becomes
/// 1 - (1 - a)^factor, what a voxel `factor` times as long would block, so
/// the picture darkens and lightens as if the fibres were denser or thinner
/// (colours unchanged; a factor of 1 returns `tf` bit for bit).
TransferFunction withOpacityScale(const TransferFunction& tf, double factor);

} // namespace yv
