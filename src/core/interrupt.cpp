#include "core/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <cstring>

namespace yv {
namespace {

std::atomic<int> requested{0};
std::atomic<int> depth{0};
struct sigaction previousInt {}, previousTerm {};

// Texts an abrupt stop says, kept for good once set (a signal handler may
// read them at any moment, so none is ever freed).
std::atomic<const char*> stopPrefix{nullptr};
std::atomic<const char*> stopNote{nullptr};

const char* kept(const std::string& text) { return strdup(text.c_str()); }

/// Appends `text` to `line` (async-signal-safe: no allocation).
void appendTo(char* line, std::size_t capacity, std::size_t& used, const char* text) {
    for (; text && *text && used + 1 < capacity; ++text) line[used++] = *text;
}

[[noreturn]] void sayAndExit(const char* why) {
    char line[8192];
    std::size_t used = 0;
    appendTo(line, sizeof line, used, "yarnvox: error: ");
    appendTo(line, sizeof line, used, stopPrefix.load());
    appendTo(line, sizeof line, used, why);
    appendTo(line, sizeof line, used, "; ");
    const char* note = stopNote.load();
    appendTo(line, sizeof line, used, note ? note : "nothing was kept; run the command again");
    line[used++] = '\n';
    for (std::size_t done = 0; done < used;) {
        const ssize_t n = ::write(STDERR_FILENO, line + done, used - done);
        if (n <= 0) break;
        done += std::size_t(n);
    }
    ::_exit(1);
}

extern "C" void onInterrupt(int signal) {
    if (stopPrefix.load() != nullptr)
        sayAndExit(signal == SIGINT ? "stopped by SIGINT (mpirun ends every rank when one ends or is interrupted)"
                                    : "stopped by SIGTERM (mpirun ends every rank when one ends or is interrupted)");
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

void answerSignalsAtOnce(const std::string& prefix) { stopPrefix = kept(prefix); }

void setStopNote(const std::string& note) { stopNote = kept(note); }

void stopAtOnce(const std::string& why) { sayAndExit(why.c_str()); }

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
