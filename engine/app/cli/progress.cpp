// Rate-limited progress line (at most 10 updates a second), cleared when the render ends.
#include "app/cli/progress.h"

#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace fh {

ProgressLine::ProgressLine()
    : active_(isatty(STDERR_FILENO) != 0), start_(std::chrono::steady_clock::now()), last_print_(start_) {}

bool ProgressLine::due(bool last) {
    if (!active_) return false;
    const auto now = std::chrono::steady_clock::now();
    if (!last && now - last_print_ < std::chrono::milliseconds(100)) return false;
    last_print_ = now;
    return true;
}

void ProgressLine::update_target(uint32_t done, double error, double target) {
    if (!due(false)) return;
    const double elapsed = std::chrono::duration<double>(last_print_ - start_).count();
    if (!std::isfinite(error) || done == 0) {
        std::fprintf(stderr, "\r  %u spp  %.1f s elapsed  error: estimating   ", done, elapsed);
    } else {
        const double needed = double(done) * (error / target) * (error / target);
        const double eta = needed > done ? elapsed * (needed - done) / done : 0.0;
        std::fprintf(stderr, "\r  %u spp  %.1f s elapsed  error %.3g%% (target %.3g%%)  ETA %.1f s   ", done, elapsed,
                     100 * error, 100 * target, eta);
    }
    std::fflush(stderr);
}

void ProgressLine::update(uint32_t done, uint32_t total) {
    if (!due(done >= total)) return;
    double elapsed = std::chrono::duration<double>(last_print_ - start_).count();
    double eta = done > 0 ? elapsed * double(total - done) / double(done) : 0.0;
    std::fprintf(stderr, "\r  %u/%u spp  %.1f s elapsed  ETA %.1f s   ", done, total, elapsed, eta);
    std::fflush(stderr);
}

void ProgressLine::finish() {
    if (!active_) return;
    std::fprintf(stderr, "\r%80s\r", "");
    std::fflush(stderr);
}

}  // namespace fh
