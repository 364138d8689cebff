// Progress on a terminal for long renders: samples done/total, elapsed time and ETA, on one updated line.
#pragma once
#include <chrono>
#include <cstdint>

namespace fh {

class ProgressLine {
public:
    ProgressLine();  // active only when stderr is a terminal
    void update(uint32_t done, uint32_t total);
    void finish();

private:
    bool active_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point last_print_;
};

}  // namespace fh
