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

/// The signal that asked to stop (SIGINT or SIGTERM), or 0.
int interruptSignal();
/// "SIGINT", "SIGTERM" or "a signal".
std::string interruptSignalName();

/// The command line as the process was started, for messages that say how
/// to go on (main records it; quoted where a word needs it).
void recordCommandLine(int argc, char** argv);
const std::string& commandLine();

} // namespace yv
