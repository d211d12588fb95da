// A command that writes, run so that SIGINT or SIGTERM never leaves a
// temporary behind: the signal is recorded (core/interrupt.h), the command
// stops at its next check with one line saying what was kept and how to go
// on, and its temporaries go with the exception. A signal that comes after
// the command's last check still fails the command, once its outputs are whole.
#pragma once

#include <functional>
#include <string>

namespace yv {

/// Runs `body` under an InterruptScope. `finished` says what is kept when a
/// signal came too late to stop anything ("OUT.vdb is whole").
void runInterruptible(const std::string& finished, const std::function<void()>& body);

/// "interrupted by SIGINT " + `where` + ": " + `kept`, thrown as Interrupted
/// when `body` was stopped by a signal: the command's own word on what was kept.
void saysWhatWasKept(const std::string& where, const std::string& kept, const std::function<void()>& body);

} // namespace yv
