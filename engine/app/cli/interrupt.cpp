// Async-signal-safe interruption: a flag for the first signal, an immediate exit on the second.
#include "app/cli/interrupt.h"

#include <signal.h>
#include <unistd.h>

#include <csignal>

namespace fh {
namespace {
volatile std::sig_atomic_t g_interrupted = 0;
volatile std::sig_atomic_t g_stderr_is_terminal = 0;  // decided at install: isatty() is not async-signal-safe

// The first SIGINT/SIGTERM only sets the flag, so the render finishes its sample index and writes a resumable
// image. If that does not come (a long wave, a blocking read, a hung device), a second one ends the process at
// once: write(2) and _exit(2) are async-signal-safe, stdio and exit() are not. 130 = 128 + SIGINT, as a shell
// reports a process killed by Ctrl-C; an image being written may leave its temporary file behind.
extern "C" void on_signal(int) {
    if (g_interrupted) {
        static const char message[] = "\nfredholm: interrupted again: exiting at once\n";
        const char* text = g_stderr_is_terminal ? message : message + 1;  // own line after a progress line
        const size_t length = sizeof message - (g_stderr_is_terminal ? 1 : 2);
        [[maybe_unused]] const ssize_t written = write(STDERR_FILENO, text, length);
        _exit(130);
    }
    g_interrupted = 1;
}
}  // namespace

void install_interrupt_handlers() {
    g_stderr_is_terminal = isatty(STDERR_FILENO) ? 1 : 0;
    struct sigaction action = {};
    action.sa_handler = on_signal;
    action.sa_flags = SA_RESTART;
    sigemptyset(&action.sa_mask);  // each signal blocks the other while handled: two at once still count as two
    sigaddset(&action.sa_mask, SIGINT);
    sigaddset(&action.sa_mask, SIGTERM);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

bool interrupt_requested() { return g_interrupted != 0; }

}  // namespace fh
