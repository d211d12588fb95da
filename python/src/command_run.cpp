#include "command_run.h"

#include "cli/embedded_command.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "pipeline/voxelize_run.h"

#include <CLI/CLI.hpp>
#include <openvdb/Exceptions.h>

#include <csignal>
#include <cstdio>
#include <memory>
#include <mutex>

namespace py = pybind11;

namespace yv::python {
namespace {

// Held for the life of the process: the interpreter may finalize before a static's destructor would run.
py::handle errorType, optionErrorType, cancelledType;

/// The Python progress callback behind the process-wide observer, for one
/// run: it remembers a stop asked for (False or an exception) and asks
/// every later stage to stop too, so a stop asked before the region loop
/// (whose InterruptScope starts clear) still holds.
class CallbackBridge {
  public:
    explicit CallbackBridge(py::object callback) : callback_(std::move(callback)) {
        if (callback_.is_none()) return;
        previous_ = setProgressObserver([this](const std::string& stage, const std::string& unit, std::uint64_t done,
                                               std::uint64_t total) { tell(stage, unit, done, total); });
        installed_ = true;
    }
    ~CallbackBridge() {
        if (installed_) setProgressObserver(previous_);
    }
    CallbackBridge(const CallbackBridge&) = delete;
    CallbackBridge& operator=(const CallbackBridge&) = delete;

    bool stopAsked() const { return stopAsked_; }
    /// The callback's exception, when it raised one.
    std::unique_ptr<py::error_already_set>& raised() { return raised_; }

  private:
    void tell(const std::string& stage, const std::string& unit, std::uint64_t done, std::uint64_t total) {
        std::lock_guard<std::mutex> lock(mutex_); // stages on several threads: one call at a time
        if (!stopAsked_) {
            py::gil_scoped_acquire gil;
            try {
                const py::object answer = callback_(stage, unit, done, total);
                stopAsked_ = !answer.is_none() && !answer.cast<bool>();
            } catch (py::error_already_set& e) {
                raised_ = std::make_unique<py::error_already_set>(std::move(e));
                stopAsked_ = true;
            }
        }
        if (stopAsked_) requestStop();
    }

    py::object callback_;
    ProgressObserver previous_;
    bool installed_ = false;
    bool stopAsked_ = false;
    std::unique_ptr<py::error_already_set> raised_;
    std::mutex mutex_;
};

py::dict reportDict(const VoxelizeJob& job, const VoxelizeReport& r, const std::vector<std::string>& notes) {
    py::dict d;
    d["input"] = job.input;
    d["output"] = job.output;
    d["backend"] = r.backend;
    d["slices"] = r.slices;
    d["active_voxels"] = r.activeVoxels;
    d["bricks"] = r.bricks;
    d["dims"] = py::make_tuple(r.dims.x, r.dims.y, r.dims.z);
    d["voxel_size"] = r.voxelSize;
    d["voxelize_seconds"] = r.voxelizeSeconds;
    d["notes"] = notes;
    return d;
}

/// The command line as `yarnvox WORDS` would have been, for messages that say how to go on (--resume).
void recordWords(const std::vector<std::string>& words) {
    std::vector<std::string> argvWords{"yarnvox"};
    argvWords.insert(argvWords.end(), words.begin(), words.end());
    std::vector<char*> argv;
    for (std::string& w : argvWords) argv.push_back(w.data());
    recordCommandLine(int(argv.size()), argv.data());
}

} // namespace

py::list runCommand(const std::vector<std::string>& words, const py::object& progress) {
    recordWords(words);
    struct Done {
        VoxelizeJob job;
        VoxelizeReport report;
        std::vector<std::string> notes;
    };
    std::vector<Done> done;
    CallbackBridge bridge(progress);
    std::string failure;
    enum class Failure { None, Option, Run } kind = Failure::None;
    {
        py::gil_scoped_release released;
        try {
            runEmbeddedCommand(words, [&](const VoxelizeJob& job) {
                std::vector<std::string> notes;
                VoxelizeReport report = runVoxelize(job, [&](const std::string& line) {
                    std::fprintf(stderr, "%s\n", line.c_str()); // as the command line shows them
                    notes.push_back(line);
                });
                done.push_back({job, std::move(report), std::move(notes)});
            });
        } catch (const CLI::ParseError& e) {
            kind = Failure::Option, failure = e.what();
        } catch (const openvdb::Exception& e) {
            kind = Failure::Run, failure = std::string("OpenVDB error: ") + e.what();
        } catch (const std::bad_alloc&) {
            kind = Failure::Run, failure = "out of host memory";
        } catch (const std::exception& e) { // yv::Error, and whatever a library throws, as the command line
            kind = Failure::Run, failure = e.what();
        }
    }
    if (kind == Failure::Option) {
        PyErr_SetString(optionErrorType.ptr(), failure.c_str());
        throw py::error_already_set();
    }
    if (bridge.raised()) throw std::move(*bridge.raised());
    if (kind == Failure::Run) {
        if (bridge.stopAsked()) PyErr_SetString(cancelledType.ptr(), failure.c_str());
        else if (interruptSignal() == SIGINT) PyErr_SetString(PyExc_KeyboardInterrupt, failure.c_str());
        else PyErr_SetString(errorType.ptr(), failure.c_str());
        throw py::error_already_set();
    }
    py::list reports;
    for (const Done& d : done) reports.append(reportDict(d.job, d.report, d.notes));
    return reports;
}

void registerExceptions(py::module_& m) {
    // yv::Error thrown by the other functions becomes this one too.
    errorType = py::register_exception<Error>(m, "Error", PyExc_RuntimeError).inc_ref();
    // A bad option is a ValueError too, as Python's own bad arguments are.
    const py::tuple optionBases = py::make_tuple(errorType, py::handle(PyExc_ValueError));
    optionErrorType = PyErr_NewException("yarnvox.OptionError", optionBases.ptr(), nullptr);
    m.attr("OptionError") = optionErrorType;
    cancelledType = PyErr_NewException("yarnvox.Cancelled", errorType.ptr(), nullptr);
    m.attr("Cancelled") = cancelledType;
}

} // namespace yv::python
