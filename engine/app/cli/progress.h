// Progress on a terminal for long renders: samples done/total, elapsed time and ETA, on one updated line.
#pragma once
#include <chrono>
#include <cstdint>

namespace fh {

// Wall-clock seconds since `start` (steady clock), for the timings the commands print.
inline double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

class ProgressLine {
public:
    ProgressLine();  // active only when stderr is a terminal
    void update(uint32_t done, uint32_t total);
    // A render to a target error: the error so far and the time left, assuming the error falls as 1 / sqrt(samples).
    void update_target(uint32_t done, double error, double target);
    void finish();

private:
    bool due(bool last);
    bool active_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point last_print_;
};

}  // namespace fh
