// SIGINT and SIGTERM while a command writes: the first one asks the command
// to stop at its next safe point (a region boundary, a chunk of the .vdb, a
// region of a merge, a picture), where it throws Interrupted, its
// temporaries go with the exception, and the command says in one line what
// was kept and how to go on; a second one ends the process at once (what it
// leaves, the next run writing beside it removes: core/output_path.h).
#pragma once

#include "core/error.h"

#include <string>

namespace yv {

/// Installs the handlers for its scope; restores the previous ones when the
/// outermost scope ends (outside every scope, the signals keep their
/// default). Scopes nest: only the outermost one forgets an earlier signal,
/// so a signal during a command's set-up is still seen by its region loop.
class InterruptScope {
  public:
    InterruptScope();
    ~InterruptScope();
    InterruptScope(const InterruptScope&) = delete;
    InterruptScope& operator=(const InterruptScope&) = delete;
};

/// The signal that asked to stop (SIGINT or SIGTERM), or 0.
int interruptSignal();
/// "SIGINT", "SIGTERM" or "a signal".
std::string interruptSignalName();

/// Where a command stopped for a signal. The message starts "interrupted by
/// SIGINT"; the layer that knows what was kept adds it.
class Interrupted : public Error {
  public:
    explicit Interrupted(const std::string& what) : Error(what) {}
};

/// Throws Interrupted("interrupted by SIG... `where`") when a signal came.
void throwIfInterrupted(const std::string& where);

/// Under mpirun the launcher ends every rank soon after one ends or is
/// interrupted (SIGTERM, then SIGKILL about a second later), too soon for a
/// rank blocked in a collective to reach its next check. From this call on,
/// SIGINT and SIGTERM are answered at once: one line, "yarnvox: error:
/// `prefix`stopped by SIG...; " and the stop note, then exit 1. What the
/// rank was writing stays as a temporary, which the next run removes.
void answerSignalsAtOnce(const std::string& prefix);

/// What an abrupt stop keeps and how to go on ("the regions written so far
/// are kept in DIR; go on with: ..."), said by stopAtOnce and by a signal
/// answered at once. Until set: nothing is kept.
void setStopNote(const std::string& note);

/// Says "yarnvox: error: PREFIX`why`; NOTE" in one line and ends the process
/// with exit code 1 at once, from any thread (a rank whose peer died).
[[noreturn]] void stopAtOnce(const std::string& why);

/// Fault injection for tests: where the environment variable
/// YARNVOX_TEST_SIGNAL_AT is `point` or `point:SIG` (SIG one of INT, TERM,
/// KILL; INT when left out), raises that signal here, once per process.
void signalAtTestPoint(const char* point);

/// The command line as the process was started, for messages that say how
/// to go on (main records it; quoted where a word needs it).
void recordCommandLine(int argc, char** argv);
const std::string& commandLine();

} // namespace yv
