// Rate-limited progress line (at most 10 updates a second), cleared when the render ends.
#include "app/cli/progress.h"

#include <cstdio>
#include <unistd.h>

namespace fh {

ProgressLine::ProgressLine()
    : active_(isatty(STDERR_FILENO) != 0), start_(std::chrono::steady_clock::now()), last_print_(start_) {}

void ProgressLine::update(uint32_t done, uint32_t total) {
    if (!active_) return;
    auto now = std::chrono::steady_clock::now();
    if (done < total && now - last_print_ < std::chrono::milliseconds(100)) return;
    last_print_ = now;
    double elapsed = std::chrono::duration<double>(now - start_).count();
    double eta = done > 0 ? elapsed * double(total - done) / double(done) : 0.0;
    std::fprintf(stderr, "\r  %u/%u spp  %.1f s elapsed  ETA %.1f s   ", done, total, elapsed, eta);
    std::fflush(stderr);
}

void ProgressLine::finish() {
    if (!active_) return;
    std::fprintf(stderr, "\r%60s\r", "");
    std::fflush(stderr);
}

}  // namespace fh
