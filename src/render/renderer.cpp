#include "render/renderer.h"

#include "core/trace.h"
#include "gpu/gl_program.h"

#include <algorithm>
#include <optional>

namespace yv {
namespace {

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

/// prepare() and draw() of one frame into `frame.target`, each timed by its
/// timer: drawFrames and PictureInFlight draw a frame so.
void prepareAndDraw(Renderer& renderer, const Frame& frame, GpuTimer& prepareTimer, GpuTimer& drawTimer) {
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    {
        const TraceSpan span("prepare the picture (the slices' order)");
        prepareTimer.begin();
        renderer.prepare(frame.camera);
        prepareTimer.end();
    }
    frame.target.bind();
    frame.target.clear(zero);
    const TraceSpan span("draw the picture");
    drawTimer.begin();
    renderer.draw(frame);
    drawTimer.end();
    checkGlError("drawing a frame");
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
    std::vector<double> sorts, draws;
    try {
        for (int i = 0; i < std::max(1, repeat); ++i) {
            // Each to its end (glFinish at both ends): what prepare() queued
            // (the slices' order) is its time, the draw's the frame's.
            GpuTimer prepareTimer(false), drawTimer(false);
            prepareAndDraw(renderer, frame, prepareTimer, drawTimer);
            sorts.push_back(prepareTimer.seconds());
            draws.push_back(drawTimer.seconds());
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
    try {
        prepareAndDraw(renderer, frame, prepareTimer_, timer_);
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
