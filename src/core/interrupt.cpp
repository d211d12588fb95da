#include "core/interrupt.h"

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <cstring>

namespace yv {
namespace {

std::atomic<int> requested{0};
std::atomic<int> depth{0};
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
    if (depth++ > 0) return;
    requested = 0;
    struct sigaction action {};
    action.sa_handler = onInterrupt;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previousInt);
    sigaction(SIGTERM, &action, &previousTerm);
}

InterruptScope::~InterruptScope() {
    if (--depth > 0) return;
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

void throwIfInterrupted(const std::string& where) {
    if (interruptSignal()) throw Interrupted("interrupted by " + interruptSignalName() + " " + where);
}

void signalAtTestPoint(const char* point) {
    static const char* const wanted = std::getenv("YARNVOX_TEST_SIGNAL_AT");
    static std::atomic<bool> raised{false};
    if (!wanted) return;
    const std::size_t n = std::strlen(point);
    if (std::strncmp(wanted, point, n) != 0 || (wanted[n] != '\0' && wanted[n] != ':')) return;
    if (raised.exchange(true)) return;
    const char* name = wanted[n] == ':' ? wanted + n + 1 : "INT";
    const int signal = std::strcmp(name, "TERM") == 0 ? SIGTERM : std::strcmp(name, "KILL") == 0 ? SIGKILL : SIGINT;
    std::raise(signal);
}

void recordCommandLine(int argc, char** argv) {
    std::string line;
    for (int i = 0; i < argc; ++i) line += (i ? " " : "") + quoted(argv[i]);
    recordedCommandLine() = line;
}

const std::string& commandLine() { return recordedCommandLine(); }

} // namespace yv
