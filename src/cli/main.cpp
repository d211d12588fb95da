// yarnvox: yarn-level cloth to sparse volumes of fibre density and orientation.
#include "cli/commands.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/trace.h"
#include "pipeline/cluster.h"

#include <CLI/CLI.hpp>
#include <openvdb/Exceptions.h>

#include <cstdio>

namespace {

/// "rank R: " in a run of several MPI processes, so an error names the process it comes from.
std::string rankPrefix() {
    const yv::Cluster* c = yv::cluster();
    return c && c->size() > 1 ? "rank " + std::to_string(c->rank()) + ": " : "";
}

int runCommand(int argc, char** argv);

} // namespace

int main(int argc, char** argv) {
    yv::recordCommandLine(argc, argv);
    yv::traceEnabled(); // YV_TRACE's timeline starts here
    try {
        const yv::ClusterScope mpi(argc, argv);
        int code = 0;
        {
            const yv::TraceSpan span("run the command"); // its end: after the command's data is freed
            code = runCommand(argc, argv);
        }
        yv::writeTrace();
        // The other ranks may wait for this one in a collective: end them all.
        if (code != 0 && yv::cluster() && yv::cluster()->size() > 1) yv::cluster()->abort(code);
        return code;
    } catch (const yv::Error& e) {
        std::fprintf(stderr, "yarnvox: error: %s\n", e.what());
        return 1;
    }
}

namespace {

int runCommand(int argc, char** argv) {
    CLI::App app{"yarnvox: turns yarn-level cloth into sparse volumes of fibre density and orientation"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "yarnvox " YV_VERSION);
    // A bad option is one line like every other error: what, where, and where to look.
    app.failure_message([](const CLI::App*, const CLI::Error& e) {
        return std::string("yarnvox: error: ") + e.what() + " (see --help)\n";
    });
    yv::addGenCommand(app);
    yv::addVoxelizeCommand(app);
    yv::addMergeCommand(app);
    yv::addInspectCommand(app);
    yv::addExportCommand(app);
    yv::addViewCommand(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const yv::Error& e) {
        std::fprintf(stderr, "yarnvox: error: %s%s\n", rankPrefix().c_str(), e.what());
        return 1;
    } catch (const openvdb::Exception& e) {
        std::fprintf(stderr, "yarnvox: OpenVDB error: %s%s\n", rankPrefix().c_str(), e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "yarnvox: error: %sout of host memory\n", rankPrefix().c_str());
        return 1;
    } catch (const std::exception& e) {
        // Whatever else a library throws (a filesystem or system error, a
        // number that does not parse) is still one line and exit 1, not an abort.
        std::fprintf(stderr, "yarnvox: error: %s%s\n", rankPrefix().c_str(), e.what());
        return 1;
    }
    return 0;
}

} // namespace
