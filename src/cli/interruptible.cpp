#include "cli/interruptible.h"

#include "core/interrupt.h"

namespace yv {

void runInterruptible(const std::string& finished, const std::function<void()>& body) {
    const InterruptScope interruptible;
    body();
    signalAtTestPoint("command-end");
    // Too late to stop: the outputs are published, and the signal is still
    // answered with a failure, as it would have been a moment earlier.
    throwIfInterrupted("after the command had finished: " + finished + "; nothing to go on with");
}

void saysWhatWasKept(const std::string& where, const std::string& kept, const std::function<void()>& body) {
    try {
        body();
    } catch (const Interrupted&) {
        throw Interrupted("interrupted by " + interruptSignalName() + " " + where + ": " + kept);
    }
}

} // namespace yv
