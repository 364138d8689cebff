// Temp-file-and-rename writing, and the early "can we write there at all" check.
#include "io/atomic_write.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <system_error>

#include "io/image.h"

namespace fh {
namespace fs = std::filesystem;

namespace {

fs::path directory_of(const fs::path& target) {
    fs::path dir = target.parent_path();
    return dir.empty() ? fs::path(".") : dir;
}

// ".NAME.PID-COUNTER-RANDOM.tmp" next to the target: unique across threads (counter), processes (pid) and
// machines sharing a directory (random); hidden so a half-written file does not look like a result.
fs::path make_temp_path(const fs::path& target) {
    static std::atomic<unsigned> counter{0};
    thread_local std::mt19937_64 random{std::random_device{}()};
    for (;;) {
        char suffix[64];
        std::snprintf(suffix, sizeof suffix, ".%ld-%u-%016llx.tmp", static_cast<long>(getpid()), counter++,
                      static_cast<unsigned long long>(random()));
        std::string name = ".";
        name += target.filename().string();
        name += suffix;
        fs::path temp = directory_of(target) / name;
        std::error_code ec;
        if (!fs::exists(temp, ec)) return temp;
    }
}

// Flushes the file's data to the disk so the rename never publishes a name whose bytes are still in cache.
void sync_file(const fs::path& file) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw IoError(file.string() + ": cannot open to flush: " + std::strerror(errno));
    const int result = ::fsync(fd);
    const int saved_errno = errno;
    ::close(fd);
    if (result != 0) throw IoError(file.string() + ": fsync failed: " + std::strerror(saved_errno));
}

}  // namespace

void write_file_atomically(const fs::path& target, const std::function<void(const fs::path& temp)>& write) {
    if (target.filename().empty()) throw IoError(target.string() + ": not a file name");
    const fs::path temp = make_temp_path(target);
    try {
        write(temp);
        std::error_code ec;
        if (!fs::is_regular_file(temp, ec))
            throw IoError(target.string() + ": the writer produced no file");
        sync_file(temp);
        fs::rename(temp, target, ec);
        if (ec) throw IoError(target.string() + ": cannot rename temporary file into place: " + ec.message());
    } catch (...) {
        std::error_code ignored;
        fs::remove(temp, ignored);
        throw;
    }
}

void check_writable(const fs::path& target) {
    const fs::path dir = directory_of(target);
    std::error_code ec;
    if (!fs::exists(dir, ec))
        throw IoError(target.string() + ": directory " + dir.string() + " does not exist");
    if (!fs::is_directory(dir, ec))
        throw IoError(target.string() + ": " + dir.string() + " is not a directory");
    if (fs::is_directory(target, ec))
        throw IoError(target.string() + ": is a directory, not a file name");
    // Creating and renaming files needs write and search permission on the directory, not on the target.
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
        throw IoError(target.string() + ": directory " + dir.string() + " is not writable: " +
                      std::strerror(errno));
}

}  // namespace fh
