// printf-style formatting into std::string for the one-line reports of the image checks (GCC 12 lacks std::format).
#pragma once

#include <cstdio>
#include <string>

namespace fh {

template <typename... Args>
std::string format_text(const char* format, Args... args) {
    const int size = std::snprintf(nullptr, 0, format, args...);
    std::string text(size > 0 ? std::size_t(size) : 0, '\0');
    if (size > 0) std::snprintf(text.data(), text.size() + 1, format, args...);
    return text;
}

}  // namespace fh
