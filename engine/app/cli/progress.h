// Progress on a terminal for long renders: samples done/total, elapsed time and ETA, on one updated line.
#pragma once
#include <chrono>
#include <cstdint>

namespace fh {

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
