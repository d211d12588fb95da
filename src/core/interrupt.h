// SIGINT and SIGTERM during a long run: the first one asks the run to stop
// at the next region boundary (so the work directory keeps every finished
// region and the run can be resumed); a second one ends the process at once.
#pragma once

#include <string>

namespace yv {

/// Installs the handlers for the scope of a region loop; restores the
/// previous ones when it ends (outside it, the signals keep their default).
class InterruptScope {
  public:
    InterruptScope();
    ~InterruptScope();
    InterruptScope(const InterruptScope&) = delete;
    InterruptScope& operator=(const InterruptScope&) = delete;
};

/// The signal that asked to stop (SIGINT or SIGTERM), kStopRequested, or 0.
int interruptSignal();
/// "SIGINT", "SIGTERM", "a stop request" or "a signal".
std::string interruptSignalName();

/// What interruptSignal() says after requestStop(): no signal's number.
inline constexpr int kStopRequested = -1;
/// Asks the run in progress to stop as a first SIGINT would (at the next
/// region boundary, keeping what is finished), from any thread: for a
/// program that runs yarnvox in its own process (the Python module's
/// progress callback). Only inside an InterruptScope, which clears it.
void requestStop();

/// The command line as the process was started, for messages that say how
/// to go on (main records it; quoted where a word needs it).
void recordCommandLine(int argc, char** argv);
const std::string& commandLine();

} // namespace yv
