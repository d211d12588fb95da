#include "core/interrupt.h"

#include <atomic>
#include <csignal>

namespace yv {
namespace {

std::atomic<int> requested{0};
struct sigaction previousInt {}, previousTerm {};

extern "C" void onInterrupt(int signal) {
    if (requested.exchange(signal) != 0) {
        // Asked twice: stop now, the default way.
        std::signal(signal, SIG_DFL);
        std::raise(signal);
    }
}

std::string& recordedCommandLine() {
    static std::string line;
    return line;
}

std::string quoted(const std::string& word) {
    if (!word.empty() && word.find_first_of(" \t\n'\"\\$`*?[]{}()<>|&;#~") == std::string::npos) return word;
    std::string out = "'";
    for (char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

} // namespace

InterruptScope::InterruptScope() {
    requested = 0;
    struct sigaction action {};
    action.sa_handler = onInterrupt;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previousInt);
    sigaction(SIGTERM, &action, &previousTerm);
}

InterruptScope::~InterruptScope() {
    sigaction(SIGINT, &previousInt, nullptr);
    sigaction(SIGTERM, &previousTerm, nullptr);
}

int interruptSignal() { return requested.load(); }

std::string interruptSignalName() {
    switch (requested.load()) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    default: return "a signal";
    }
}

void recordCommandLine(int argc, char** argv) {
    std::string line;
    for (int i = 0; i < argc; ++i) line += (i ? " " : "") + quoted(argv[i]);
    recordedCommandLine() = line;
}

const std::string& commandLine() { return recordedCommandLine(); }

} // namespace yv
