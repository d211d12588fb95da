#include "render/renderer.h"

#include "core/trace.h"
#include "gpu/gl_program.h"

#include <algorithm>
#include <chrono>
#include <optional>

namespace yv {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The median and the fastest of `seconds`.
std::pair<double, double> medianAndBest(std::vector<double> seconds) {
    std::sort(seconds.begin(), seconds.end());
    return {seconds[seconds.size() / 2], seconds.front()};
}

/// The state the renders change, back to GL's defaults, so that the next
/// picture on the same context starts from where a fresh context would.
void resetDrawState() {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDisable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ZERO);
    glDisable(GL_PROGRAM_POINT_SIZE);
    glBindVertexArray(0);
    glUseProgram(0);
}

} // namespace

PendingRgbImage Renderer::startPicture(const Frame& frame) {
    return PendingRgbImage::start(frame.target.texture(0), frame.target.width(), frame.target.height());
}

void drawFrames(Renderer& renderer, const Camera& camera, int repeat, RenderReport& report) {
    const TraceSpan span("draw a picture");
    std::optional<TraceSpan> making(std::in_place, "make the picture's target");
    const RenderTarget target(camera.width, camera.height, renderer.targetFormats());
    making.reset();
    const Frame frame{camera, target};
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    std::vector<double> sorts, draws;
    try {
        for (int i = 0; i < std::max(1, repeat); ++i) {
            auto start = std::chrono::steady_clock::now();
            renderer.prepare(camera);
            glFinish(); // what prepare() queued (the slices' order) is its time
            sorts.push_back(secondsSince(start));
            if (traceEnabled()) traceSpanSince("prepare the picture (the slices' order)", start);
            target.bind();
            target.clear(zero);
            glFinish();
            start = std::chrono::steady_clock::now();
            renderer.draw(frame);
            glFinish();
            draws.push_back(secondsSince(start));
            if (traceEnabled()) traceSpanSince("draw the picture, to its end", start);
            checkGlError("drawing a frame");
        }
        const TraceSpan reading("read the picture back");
        report.image = renderer.picture(frame);
    } catch (...) {
        resetDrawState();
        throw;
    }
    resetDrawState();
    std::tie(report.frameSeconds, report.bestFrameSeconds) = medianAndBest(draws);
    std::tie(report.sortSeconds, report.bestSortSeconds) = medianAndBest(sorts);
    renderer.describe(report);
}

PictureInFlight::PictureInFlight(Renderer& renderer, const Camera& camera, bool timerQueries)
    : renderer_(renderer), target_(camera.width, camera.height, renderer.targetFormats()), prepareTimer_(timerQueries),
      timer_(timerQueries) {
    const TraceSpan span("queue a picture");
    const Frame frame{camera, target_};
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    try {
        prepareTimer_.begin();
        renderer.prepare(camera);
        prepareTimer_.end();
        target_.bind();
        target_.clear(zero);
        timer_.begin();
        renderer.draw(frame);
        timer_.end();
        checkGlError("drawing a frame");
        picture_ = renderer.startPicture(frame);
    } catch (...) {
        resetDrawState();
        throw;
    }
    resetDrawState();
}

RenderReport PictureInFlight::finish() {
    const TraceSpan span("finish a picture");
    RenderReport report;
    report.image = picture_.finish();
    report.frameSeconds = report.bestFrameSeconds = timer_.seconds();
    report.sortSeconds = report.bestSortSeconds = prepareTimer_.seconds();
    renderer_.describe(report);
    return report;
}

} // namespace yv
