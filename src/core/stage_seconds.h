// How long a run spent in each of its stages, as recorded for later
// inspection: in a work directory's manifest, and read from a .vdb's
// "stage_seconds" metadata where a file has one; JSON in both, an object of
// NAME: SECONDS in the run's order.
// Names without a dot are wall-clock stages one after another ("read",
// "slices", "plan", "voxelize"); "voxelize.NAME" is a part of the voxelize
// stage measured on its own threads, so parts may overlap each other.
#pragma once

#include "core/stats.h"

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <utility>
#include <vector>

namespace yv {

/// Stage name and seconds, in the order the run went through them.
using StageSeconds = std::vector<std::pair<std::string, double>>;

/// Whether `name` is a whole stage (no dot) rather than a part of one.
inline bool isWholeStage(const std::string& name) { return name.find('.') == std::string::npos; }

/// Sum of the whole stages: the run's wall-clock time up to the last of them.
double wholeStageSum(const StageSeconds& stages);

/// {"read": 0.012, "slices": 0.5, ...}, in the stages' order.
nlohmann::ordered_json stageSecondsJson(const StageSeconds& stages);
/// {"read": s, "slices": s, ...} for --stats and inspect's reports (numbers as JsonObject writes them).
JsonObject stageSecondsObject(const StageSeconds& stages);
/// The stages of a stageSecondsJson object; throws yv::Error naming `where`
/// on anything else, a bad name or a negative or non-finite time.
StageSeconds stageSecondsFromJson(const nlohmann::ordered_json& json, const std::string& where);

/// stageSecondsJson as one line of text, for a metadata string.
std::string formatStageSeconds(const StageSeconds& stages);
/// Parses formatStageSeconds's text, as stageSecondsFromJson.
StageSeconds parseStageSeconds(const std::string& text, const std::string& where);

/// Whether `name` may be a stage name: letters, digits, '_' and '.', not empty.
bool isStageName(const std::string& name);

} // namespace yv
