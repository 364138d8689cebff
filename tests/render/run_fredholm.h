// Runs the fredholm binary for the render tests that drive its command line: the command is printed, its messages
// are appended to DIR/log.txt, and the exit code comes back (128 when it did not exit), with the log's last line for
// the tests that check a refusal's words.
#pragma once
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>

namespace fh::test {

inline int run_fredholm(const std::string& exe, const std::filesystem::path& dir, const std::string& args) {
    std::filesystem::create_directories(dir);
    const std::string line = exe + " " + args + " 2>>" + (dir / "log.txt").string();
    std::printf("%s\n", line.c_str());
    const int status = std::system(line.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

inline std::string last_log_line(const std::filesystem::path& dir) {
    std::ifstream log(dir / "log.txt");
    std::string line, last;
    while (std::getline(log, line)) last = line;
    return last;
}

}  // namespace fh::test
