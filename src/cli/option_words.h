// The words of the options that choose among a few settings, mapped once to
// the enums the layers below take: CLI11 turns the word into the value and
// refuses any other word, naming the ones it takes.
#pragma once

#include "core/sampling.h"
#include "pipeline/voxelize_job.h"
#include "vdb/vdb_writer.h"

#include <CLI/CLI.hpp>

#include <map>
#include <string>

namespace yv {

inline const std::map<std::string, BackendRequest> kBackendWords{
    {"auto", BackendRequest::Auto}, {"gl", BackendRequest::Gl}, {"cpu", BackendRequest::Cpu}};
inline const std::map<std::string, VoxelizeMethod> kMethodWords{{"sparse", VoxelizeMethod::Sparse},
                                                                {"dense", VoxelizeMethod::Dense}};
inline const std::map<std::string, Reduce> kReduceWords{{"mean", Reduce::Mean}, {"max", Reduce::Max}};
inline const std::map<std::string, Overlap> kOverlapWords{{"clamp", Overlap::Clamp}, {"sum", Overlap::Sum}};
inline const std::map<std::string, VdbCompression> kCompressionWords{{"blosc", VdbCompression::Blosc},
                                                                     {"zip", VdbCompression::Zip},
                                                                     {"mask", VdbCompression::ActiveMask},
                                                                     {"none", VdbCompression::None}};
inline const std::map<std::string, VdbPrecision> kPrecisionWords{{"float", VdbPrecision::Float},
                                                                 {"half", VdbPrecision::Half}};

/// The option's value is one of `words`, turned into its enum (as the
/// enum's number, which CLI11 then reads into the option's variable); any
/// other text is refused with the words it could have been.
template <class Enum>
CLI::Validator oneOf(const std::map<std::string, Enum>& words) {
    std::string names;
    for (const auto& [word, value] : words) names += (names.empty() ? "" : ", ") + word;
    return CLI::Validator(
        [&words, names](std::string& text) -> std::string {
            const auto it = words.find(text);
            if (it == words.end()) return "'" + text + "' is not one of " + names;
            text = std::to_string(static_cast<int>(it->second));
            return {};
        },
        "{" + names + "}", "word");
}

} // namespace yv
