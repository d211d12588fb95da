// Runs the yarnvox binary (or any shell line) from a test, with its exit
// code and everything it printed.
#pragma once

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace yv::test {

struct RunResult {
    int exitCode;
    std::string output; // stdout and stderr
};

/// Runs a shell command line, stdout and stderr together.
inline RunResult runShell(const std::string& line) {
    FILE* pipe = popen(("(" + line + ") 2>&1").c_str(), "r");
    REQUIRE(pipe);
    std::string out;
    std::array<char, 4096> buf;
    while (std::size_t n = std::fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

/// Runs `yarnvox ARGS` from the build directory.
inline RunResult runYarnvox(const std::string& args) { return runShell(std::string(YV_BINARY_DIR) + "/yarnvox " + args); }

} // namespace yv::test
