#include "view/view_voxelizer.h"

#include "core/error.h"
#include "core/interrupt.h"
#include "pipeline/sliced_garment.h"
#include "pipeline/voxelize_run.h"

#include <nlohmann/json.hpp>

#include <charconv>
#include <chrono>
#include <cstdio>
#include <system_error>

namespace yv {
namespace {

namespace fs = std::filesystem;

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// The shortest text that reads back to `v`.
std::string exactText(double v) {
    char text[64];
    const auto end = std::to_chars(text, text + sizeof text, v).ptr;
    return std::string(text, end);
}

std::string commandText(const std::vector<std::string>& words) {
    std::string text = "yarnvox";
    for (const std::string& w : words) text += " " + w;
    return text;
}

/// Where run `id` of `input` is saved: GARMENT-view-ID in `dir`.
fs::path savedName(const fs::path& dir, const std::string& input, std::uint64_t id) {
    return dir / (fs::path(input).stem().string() + "-view-" + std::to_string(id));
}

/// The pages' message for a task that ended without its result: "failed" or "dropped".
std::string endedText(std::uint64_t id, const char* state, const char* what) {
    return nlohmann::json{{"type", "voxelize"}, {"state", state}, {"id", id}, {"text", what}}.dump();
}

/// Box after box of one garment: read once, and its slices planned once per slice spacing.
VoxelizeJob withSliceCache(VoxelizeJob job) {
    if (!job.sliceCache) job.sliceCache = std::make_shared<SlicePlanCache>();
    return job;
}

} // namespace

std::vector<std::string> voxelizeArguments(const VoxelizeJob& job) {
    const VoxelizeJob defaults;
    std::vector<std::string> words = {"voxelize", job.input};
    const auto add = [&](const char* option, std::string value) {
        words.emplace_back(option);
        words.push_back(std::move(value));
    };
    if (job.resolution > 0) add("--resolution", std::to_string(job.resolution));
    if (job.voxelSize > 0.0) add("--voxel-size", exactText(job.voxelSize));
    if (job.box) add(job.box->world ? "--bbox-world" : "--bbox", job.box->text);
    if (job.yarnRadius != defaults.yarnRadius) add("--yarn-radius", exactText(job.yarnRadius));
    if (job.slicesPerSegment != defaults.slicesPerSegment) add("--slices-per-segment", std::to_string(job.slicesPerSegment));
    if (job.spacing != defaults.spacing) add("--slice-spacing", exactText(job.spacing));
    if (job.twist != defaults.twist) add("--twist", exactText(job.twist));
    if (job.crossSection != defaults.crossSection) add("--cross-section", job.crossSection);
    if (job.backend != defaults.backend) add("--backend", toString(job.backend));
    if (job.supersample != defaults.supersample) add("--supersample", std::to_string(job.supersample));
    return words;
}

ViewVoxelizer::ViewVoxelizer(VoxelizeJob base, fs::path saveDir, Listener listener)
    : base_(withSliceCache(std::move(base))), saveDir_(std::move(saveDir)),
      listener_(std::move(listener)), worker_([this] { work(); }) {}

ViewVoxelizer::~ViewVoxelizer() {
    {
        const std::lock_guard lock(mutex_);
        stopping_ = true;
        waiting_.clear();
    }
    wake_.notify_all();
    worker_.join();
    if (firstPass_.joinable()) firstPass_.join();
}

VoxelizeJob ViewVoxelizer::jobFor(const ViewVoxelization& plan) const {
    VoxelizeJob job = base_;
    job.resolution = 0;
    job.voxelSize = plan.voxelSize;
    job.box = parseBoxRequest(true, plan.boxText);
    if (plan.twist) job.twist = *plan.twist;
    job.quiet = true;
    job.verbose = false;
    job.statsPath.clear();
    job.workDir.clear();
    job.keepWorkDir = job.resume = false;
    return job;
}

bool ViewVoxelizer::request(const ViewVoxelization& plan, const std::optional<ViewVoxelization>& first) {
    {
        const std::lock_guard lock(mutex_);
        if (running_ == plan || last_ == plan) return false;
        for (const Task& t : waiting_)
            if (t.kind == Task::Kind::Voxelize && t.plan == plan) return false;
        // The newest view wins over every pass of one not yet started, and
        // over the passes under way (they stop at their next region).
        std::erase_if(waiting_, [](const Task& t) { return t.kind == Task::Kind::Voxelize; });
        for (const auto& cancel : {runningCancel_, firstPassCancel_})
            if (cancel) cancel->store(true);
        const double asked = now();
        for (const ViewVoxelization* pass : {first ? &*first : nullptr, &plan}) {
            if (!pass) continue;
            Task task;
            task.plan = *pass;
            task.id = nextId_++;
            task.askedAt = asked;
            task.cancel = std::make_shared<std::atomic<bool>>(false);
            waiting_.push_back(std::move(task));
        }
    }
    wake_.notify_all();
    return true;
}

std::optional<DetailRun> ViewVoxelizer::takeFinished() {
    const std::lock_guard lock(mutex_);
    return std::exchange(finished_, std::nullopt);
}

void ViewVoxelizer::save(const DetailRun& run, bool workDir) {
    {
        const std::lock_guard lock(mutex_);
        Task task;
        task.kind = workDir ? Task::Kind::SaveWorkDir : Task::Kind::SaveVdb;
        task.run = run;
        task.id = run.id;
        task.askedAt = now();
        waiting_.push_back(std::move(task));
    }
    wake_.notify_all();
}

bool ViewVoxelizer::busy() const {
    const std::lock_guard lock(mutex_);
    return running_.has_value() || !waiting_.empty();
}

void ViewVoxelizer::work() {
    makePassContexts();
    for (;;) {
        Task task;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stopping_ || !waiting_.empty(); });
            if (stopping_) return;
            task = std::move(waiting_.front());
            waiting_.erase(waiting_.begin());
            if (task.kind == Task::Kind::Voxelize) {
                (task.plan.firstPass ? firstPassCancel_ : runningCancel_) = task.cancel;
                if (!task.plan.firstPass) running_ = task.plan;
            }
        }
        if (task.kind == Task::Kind::Voxelize && task.plan.firstPass) {
            // The coarse pass runs beside the final one (a GL context of its
            // own; the GPU and cores have room for both), so it costs the
            // final pass nothing; the one before it is done or nearly.
            if (firstPass_.joinable()) firstPass_.join();
            firstPass_ = std::thread([this, task] { voxelizeOrDrop(task); });
            continue;
        }
        if (task.kind == Task::Kind::Voxelize) {
            voxelizeOrDrop(task);
        } else {
            try {
                saveRun(task);
            } catch (const Error& e) {
                listener_.tell(endedText(task.id, "failed", e.what()));
            }
        }
        const std::lock_guard lock(mutex_);
        running_.reset();
        runningCancel_.reset();
        if (interruptSignal() != 0) return; // Ctrl-C: the view is stopping
    }
}

void ViewVoxelizer::voxelizeOrDrop(const Task& task) {
    try {
        voxelize(task);
    } catch (const RunCancelled& e) {
        listener_.tell(endedText(task.id, "dropped", e.what()));
    } catch (const Error& e) {
        listener_.tell(endedText(task.id, "failed", e.what()));
    }
}

void ViewVoxelizer::voxelize(const Task& task) {
    listener_.tell(nlohmann::json{{"type", "voxelize"},
                                  {"state", "running"},
                                  {"id", task.id},
                                  {"voxelSize", task.plan.voxelSizeText},
                                  {"bboxWorld", task.plan.boxText},
                                  {"pass", task.plan.firstPass ? "first" : "final"}}
                       .dump());
    VoxelizeJob job = jobFor(task.plan);
    job.output.clear(); // the bricks are kept, no file written: a save voxelizes again
    job.keepBricks = std::make_shared<KeptBricks>();
    job.cancel = task.cancel;
    job.glContext = task.plan.firstPass ? coarseContext_ : finalContext_;
    // The context is left to the next pass, which may run on another thread.
    const auto release = [&] {
        if (job.glContext) job.glContext->releaseCurrent();
    };
    VoxelizeReport report;
    try {
        report = runVoxelize(job, [](const std::string&) {});
    } catch (...) {
        release();
        throw;
    }
    release();
    DetailRun run;
    run.id = task.id;
    run.plan = task.plan;
    run.bricks = std::move(job.keepBricks);
    run.grid.origin = report.origin;
    run.grid.voxelSize = report.voxelSize;
    run.grid.dims = report.dims;
    run.activeVoxels = report.activeVoxels;
    run.seconds = now() - task.askedAt;
    run.command = voxelizeArguments(job);
    {
        const std::lock_guard lock(mutex_);
        // A coarse pass done after the final one of its view (or a later view's): not shown.
        if (task.id < publishedId_) return;
        publishedId_ = task.id;
        finished_ = std::move(run);
        last_ = task.plan;
    }
    listener_.finished();
}

void ViewVoxelizer::makePassContexts() {
    if (base_.backend == BackendRequest::Cpu) return;
    for (std::shared_ptr<GlContext>* kept : {&coarseContext_, &finalContext_}) {
        try {
            *kept = std::make_shared<GlContext>(GlContextOptions{base_.device, false});
            (*kept)->releaseCurrent(); // taken by the thread of each pass
        } catch (const Error&) {
            // None kept: each run makes its own attempt, and says why or takes the CPU.
        }
    }
}

void ViewVoxelizer::saveRun(const Task& task) {
    const fs::path name = savedName(saveDir_, base_.input, task.id);
    // The run shown, voxelized again (it kept its bricks alone): the same
    // passes give the same voxels, and the .vdb is written as `voxelize`
    // writes one (in place only once complete).
    VoxelizeJob job = jobFor(task.run.plan);
    job.output = name.string() + ".vdb";
    if (task.kind == Task::Kind::SaveWorkDir) job.workDir = name.string() + ".work";
    runVoxelize(job, [](const std::string&) {});
    std::vector<std::string> command = voxelizeArguments(job);
    if (!job.workDir.empty()) command.insert(command.end(), {"--work-dir", job.workDir});
    command.insert(command.end(), {"-o", job.output});
    nlohmann::json said = {{"type", "voxelize"}, {"state", "saved"}, {"id", task.id}, {"vdb", job.output}};
    if (!job.workDir.empty()) said["workDir"] = job.workDir;
    said["command"] = command;
    said["commandText"] = commandText(command);
    said["seconds"] = now() - task.askedAt;
    listener_.tell(said.dump());
}

} // namespace yv
