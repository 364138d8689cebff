// Writing files so that a reader never sees a half-written one: write a temporary file, then rename it.
#pragma once

#include <filesystem>
#include <functional>

namespace fh {

// Calls `write(temp)` with a fresh, uniquely named path in the same directory as `target`, flushes that file
// to disk and renames it over `target` (atomic on POSIX file systems, so `target` is either the old file or
// the complete new one). If `write` throws, or leaves no file behind, the temporary file is removed, `target`
// is left untouched and the exception propagates (IoError for a missing file or a failed rename).
void write_file_atomically(const std::filesystem::path& target,
                           const std::function<void(const std::filesystem::path& temp)>& write);

// Throws IoError unless the directory that would hold `target` exists and this process may create files in
// it, and `target` itself is not a directory. Call it before a long render so a typo fails in milliseconds.
void check_writable(const std::filesystem::path& target);

}  // namespace fh
