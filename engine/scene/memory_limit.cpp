// Memory sizes as users write them, the default limit, and the refusal line.
#include "scene/memory_limit.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <unistd.h>

namespace fh {

uint64_t default_memory_limit() {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0) return uint64_t(8) << 30;  // unknown: 8 GiB
    return uint64_t(pages) * uint64_t(page) / 4 * 3;
}

uint64_t resident_memory_bytes() {
    std::FILE* statm = std::fopen("/proc/self/statm", "r");
    if (!statm) return 0;
    unsigned long long total = 0, resident = 0;
    const bool read = std::fscanf(statm, "%llu %llu", &total, &resident) == 2;
    std::fclose(statm);
    const long page = sysconf(_SC_PAGESIZE);
    return read && page > 0 ? uint64_t(resident) * uint64_t(page) : 0;
}

uint64_t parse_memory_size(const std::string& word) {
    const auto refuse = [&word]() {
        return std::invalid_argument("'" + word + "' is not a size (bytes, or a number with K, M, G or T: 100M, 1.5G, 512MiB)");
    };
    size_t used = 0;
    double number = 0.0;
    try {
        if (!word.empty() && (std::isdigit(static_cast<unsigned char>(word[0])) || word[0] == '.'))
            number = std::stod(word, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || !std::isfinite(number) || number < 0.0) throw refuse();
    std::string unit = word.substr(used);
    for (char& c : unit) c = char(std::tolower(static_cast<unsigned char>(c)));
    const std::string units = "kmgt";
    double scale = 1.0;
    if (!unit.empty() && unit != "b") {
        const size_t power = units.find(unit[0]);
        const std::string rest = unit.substr(1);
        if (power == std::string::npos || !(rest.empty() || rest == "b" || rest == "ib")) throw refuse();
        scale = std::ldexp(1.0, 10 * int(power + 1));
    }
    const double bytes = std::floor(number * scale);
    if (bytes < 1.0 || bytes > 0x1p62) throw refuse();
    return uint64_t(bytes);
}

std::string format_bytes(uint64_t bytes) {
    char text[64];
    const double mib = double(bytes) / double(1u << 20);
    if (mib >= 1024.0) std::snprintf(text, sizeof text, "%.2f GiB", mib / 1024.0);
    else std::snprintf(text, sizeof text, "%.1f MiB", mib);
    return std::string(text) + " (" + std::to_string(bytes) + " bytes)";
}

std::string find_limit_problem(const std::vector<MemoryUse>& uses, uint64_t limit, const std::string& what) {
    uint64_t total = 0;
    for (const MemoryUse& use : uses) total += use.bytes;
    if (limit == 0 || total <= limit) return {};
    std::vector<MemoryUse> largest = uses;
    std::stable_sort(largest.begin(), largest.end(), [](const MemoryUse& a, const MemoryUse& b) { return a.bytes > b.bytes; });
    std::string names;
    for (size_t i = 0; i < std::min<size_t>(3, largest.size()) && largest[i].bytes > 0; ++i)
        names += (i ? ", " : "") + largest[i].name + " " + format_bytes(largest[i].bytes);
    return what + " needs " + format_bytes(total) + ", more than the memory limit of " + format_bytes(limit) +
           " (--memory-limit; largest: " + names + ")";
}

}  // namespace fh
