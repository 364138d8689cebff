// Threads that take work a thread offers and may do itself (help-first): the BVH build's subtrees.
#pragma once
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <span>
#include <thread>
#include <vector>

namespace fh {

// A thread offers a job (a subtree's build) and goes on with its own work; an idle helper takes the job. When the
// offering thread needs the result (finish), it runs the job itself if no helper took it, and otherwise runs other
// offered jobs while it waits. So every hardware thread stays busy with one thread each, and an unbalanced split
// leaves no thread idle while work is queued.
class HelperThreads {
public:
    struct Job {
        std::function<void()> run;
        bool taken = false, done = false;
        std::exception_ptr failure;
    };

    // Starts up to `helpers` threads (fewer where the system refuses more); with none, finish runs every job on the
    // offering thread.
    explicit HelperThreads(uint32_t helpers);
    ~HelperThreads();
    HelperThreads(const HelperThreads&) = delete;
    HelperThreads& operator=(const HelperThreads&) = delete;

    void offer(Job& job);
    // Returns when the job has run (here, or on a helper); rethrows what it threw.
    void finish(Job& job);

    // Runs tasks[0] here while the others are offered, and returns when all are done (rethrowing the first failure in
    // task order).
    void run_all(std::span<const std::function<void()>> tasks);
    void run_both(std::function<void()> first, std::function<void()> second) {
        const std::function<void()> tasks[] = {std::move(first), std::move(second)};
        run_all(tasks);
    }

private:
    void serve();
    static void execute(Job& job);
    // Runs one queued job, unlocking while it runs; false when the queue was empty.
    bool run_one(std::unique_lock<std::mutex>& lock);

    std::mutex mutex_;
    std::condition_variable queued_, finished_;
    std::deque<Job*> queue_;  // oldest (largest, nearest the root) first
    bool stopping_ = false;
    std::vector<std::thread> threads_;
};

}  // namespace fh
