#include "core/stage_seconds.h"

#include "core/error.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

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

std::string formatStageSeconds(const StageSeconds& stages) {
    std::string out;
    for (const auto& [name, seconds] : stages) {
        char value[40];
        std::snprintf(value, sizeof value, "%.9g", seconds);
        out += (out.empty() ? "" : " ") + name + "=" + value;
    }
    return out;
}

StageSeconds parseStageSeconds(const std::string& text, const std::string& where) {
    StageSeconds stages;
    std::istringstream words(text);
    for (std::string word; words >> word;) {
        const std::size_t eq = word.find('=');
        const std::string name = word.substr(0, eq == std::string::npos ? word.size() : eq);
        const std::string value = eq == std::string::npos ? "" : word.substr(eq + 1);
        char* end = nullptr;
        const double seconds = std::strtod(value.c_str(), &end);
        if (!isStageName(name) || value.empty() || end != value.c_str() + value.size() || !std::isfinite(seconds) ||
            seconds < 0.0)
            throw Error(where + ": stage time \"" + word + "\": expected NAME=SECONDS, SECONDS finite and not negative");
        stages.emplace_back(name, seconds);
    }
    return stages;
}

} // namespace yv
