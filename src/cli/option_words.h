// The words of the options that choose among a few settings, mapped once to
// the enums the layers below take: CLI11 turns the word into the value and
// refuses any other word, naming the ones it takes.
#pragma once

#include "core/error.h"
#include "core/sampling.h"
#include "pipeline/voxelize_job.h"
#include "vdb/lod_request.h"
#include "vdb/vdb_writer.h"

#include <CLI/CLI.hpp>

#include <initializer_list>
#include <map>
#include <string>

namespace yv {

/// Each value's word as its layer's toString spells it (the one spelling,
/// also in --stats and the .vdb's metadata), mapped back to the value.
template <class Enum>
std::map<std::string, Enum> wordsOf(std::initializer_list<Enum> values) {
    std::map<std::string, Enum> words;
    for (const Enum v : values) words.emplace(toString(v), v);
    return words;
}

inline const auto kBackendWords = wordsOf({BackendRequest::Auto, BackendRequest::Gl, BackendRequest::Cpu});
inline const auto kMethodWords = wordsOf({VoxelizeMethod::Sparse, VoxelizeMethod::Dense});
inline const auto kSampleItemsWords =
    wordsOf({SampleItemsRequest::Auto, SampleItemsRequest::Raster, SampleItemsRequest::Compute});
inline const auto kReduceWords = wordsOf({Reduce::Mean, Reduce::Max});
inline const auto kOverlapWords = wordsOf({Overlap::Clamp, Overlap::Sum});
inline const auto kCompressionWords =
    wordsOf({VdbCompression::Blosc, VdbCompression::Zip, VdbCompression::ActiveMask, VdbCompression::None});
inline const auto kPrecisionWords = wordsOf({VdbPrecision::Float, VdbPrecision::Half});

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

/// --lod's value: preview, 0 or N (vdb/lod_request.h); any other text is
/// refused with what it takes. The option's callback then parses it.
inline CLI::Validator lodWords() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            try {
                parseLodRequest(text);
                return {};
            } catch (const Error& e) {
                return e.what();
            }
        },
        "{preview, 0, N}", "level of detail");
}

} // namespace yv
