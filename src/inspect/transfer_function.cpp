#include "inspect/transfer_function.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace yv {
namespace {

struct ControlPoint {
    double density;
    glm::vec4 rgba;
};

TransferFunction interpolate(const std::vector<ControlPoint>& points) {
    TransferFunction tf;
    for (int i = 0; i < 256; ++i) {
        const double d = i / 255.0;
        std::size_t k = 1;
        while (k + 1 < points.size() && points[k].density < d) ++k;
        const ControlPoint& a = points[k - 1];
        const ControlPoint& b = points[k];
        const double span = b.density - a.density;
        const float t = span > 0.0 ? float(std::clamp((d - a.density) / span, 0.0, 1.0)) : (d < a.density ? 0.0f : 1.0f);
        tf[std::size_t(i)] = a.rgba + t * (b.rgba - a.rgba);
    }
    return tf;
}

// Opacity per voxel length rises with density: a yarn's inner voxels (near 1)
// hide what lies behind within a few voxels, thin edges stay see-through.
const std::vector<std::pair<std::string, std::vector<ControlPoint>>>& presets() {
    static const std::vector<std::pair<std::string, std::vector<ControlPoint>>> p = {
        {"fibre", {{0.0, {0.55f, 0.35f, 0.20f, 0.0f}}, {0.05, {0.65f, 0.42f, 0.25f, 0.08f}},
                   {0.5, {0.90f, 0.70f, 0.45f, 0.35f}}, {1.0, {1.0f, 0.95f, 0.85f, 0.6f}}}},
        {"grey", {{0.0, {0.0f, 0.0f, 0.0f, 0.0f}}, {1.0, {1.0f, 1.0f, 1.0f, 0.5f}}}},
        {"heat", {{0.0, {0.1f, 0.0f, 0.0f, 0.0f}}, {0.33, {0.9f, 0.1f, 0.0f, 0.2f}},
                  {0.66, {1.0f, 0.8f, 0.0f, 0.4f}}, {1.0, {1.0f, 1.0f, 1.0f, 0.6f}}}},
    };
    return p;
}

} // namespace

const std::vector<std::string>& transferFunctionPresets() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const auto& [name, _] : presets()) n.push_back(name);
        return n;
    }();
    return names;
}

TransferFunction defaultTransferFunction() { return interpolate(presets().front().second); }

TransferFunction parseColourMap(const std::string& text, const std::string& name) {
    std::vector<ControlPoint> points;
    std::istringstream in(text);
    int lineNo = 0;
    for (std::string line; std::getline(in, line);) {
        ++lineNo;
        if (const std::size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        std::istringstream fields(line);
        std::string first;
        if (!(fields >> first)) continue; // blank or comment
        fields.clear();
        fields.str(line);
        double v[5];
        std::string extra;
        const auto where = name + " line " + std::to_string(lineNo) + ": ";
        for (double& x : v)
            if (!(fields >> x) || !std::isfinite(x)) throw Error(where + "expected five numbers: density r g b opacity");
        if (fields >> extra) throw Error(where + "expected five numbers: density r g b opacity, found more");
        for (double x : v)
            if (x < 0.0 || x > 1.0) throw Error(where + "every number must lie in [0, 1]");
        if (!points.empty() && v[0] <= points.back().density)
            throw Error(where + "densities must rise from line to line");
        points.push_back({v[0], glm::vec4(float(v[1]), float(v[2]), float(v[3]), float(v[4]))});
    }
    if (points.size() < 2) throw Error(name + ": a colour map needs at least two lines (density r g b opacity)");
    return interpolate(points);
}

TransferFunction loadTransferFunction(const std::string& nameOrPath) {
    for (const auto& [name, points] : presets())
        if (name == nameOrPath) return interpolate(points);
    const auto bytes = readWholeFile(nameOrPath);
    if (!bytes)
        throw Error("--tf '" + nameOrPath + "': neither a preset (fibre, grey, heat) nor an existing colour map file");
    return parseColourMap(std::string(bytes->begin(), bytes->end()), nameOrPath);
}

TransferFunction withOpacityScale(const TransferFunction& tf, double factor) {
    if (factor == 1.0) return tf;
    TransferFunction out = tf;
    for (glm::vec4& entry : out) {
        const double a = std::clamp(double(entry.a), 0.0, 1.0);
        entry.a = float(a >= 1.0 ? 1.0 : 1.0 - std::pow(1.0 - a, factor));
    }
    return out;
}

} // namespace yv
