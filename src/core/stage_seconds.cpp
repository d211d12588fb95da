#include "core/stage_seconds.h"

#include "core/error.h"
#include "core/json_fields.h"

#include <cctype>
#include <cmath>

namespace yv {

double wholeStageSum(const StageSeconds& stages) {
    double sum = 0.0;
    for (const auto& [name, seconds] : stages)
        if (isWholeStage(name)) sum += seconds;
    return sum;
}

bool isStageName(const std::string& name) {
    if (name.empty()) return false;
    for (const char c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.')) return false;
    return true;
}

Json stageSecondsJson(const StageSeconds& stages) {
    Json out = Json::object();
    for (const auto& [name, seconds] : stages) out[name] = seconds;
    return out;
}

JsonObject stageSecondsObject(const StageSeconds& stages) {
    JsonObject out;
    for (const auto& [name, seconds] : stages) out.set(name, seconds);
    return out;
}

StageSeconds stageSecondsFromJson(const Json& json, const std::string& where) {
    const JsonFields in(json, where + ": stage times");
    StageSeconds stages;
    for (const auto& [name, value] : json.items()) {
        if (!isStageName(name)) in.fail(name, "expected a stage name of letters, digits, '_' and '.'");
        const double seconds = in.number(name.c_str());
        if (seconds < 0.0) in.fail(name, "expected seconds not negative, found " + jsonText(value, -1));
        stages.emplace_back(name, seconds);
    }
    return stages;
}

std::string formatStageSeconds(const StageSeconds& stages) { return jsonText(stageSecondsJson(stages), -1); }

StageSeconds parseStageSeconds(const std::string& text, const std::string& where) {
    return stageSecondsFromJson(parseJson(text, where + ": stage times"), where);
}

} // namespace yv
