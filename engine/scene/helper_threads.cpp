#include "scene/helper_threads.h"

#include <algorithm>
#include <system_error>

namespace fh {

HelperThreads::HelperThreads(uint32_t helpers) {
    try {
        for (uint32_t i = 0; i < helpers; ++i) threads_.emplace_back([this] { serve(); });
    } catch (const std::system_error&) {
        // No more threads to be had (a process or container limit): the ones started do the work, or, with none,
        // the offering threads themselves.
    }
}

HelperThreads::~HelperThreads() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    queued_.notify_all();
    for (std::thread& t : threads_) t.join();
}

void HelperThreads::offer(Job& job) {
    if (threads_.empty()) return;  // finish runs it
    {
        std::lock_guard lock(mutex_);
        queue_.push_back(&job);
    }
    queued_.notify_one();
    finished_.notify_all();  // a thread waiting in finish may take it too
}

void HelperThreads::execute(Job& job) {
    try {
        job.run();
    } catch (...) {
        job.failure = std::current_exception();
    }
}

bool HelperThreads::run_one(std::unique_lock<std::mutex>& lock) {
    if (queue_.empty()) return false;
    Job* job = queue_.front();
    queue_.pop_front();
    job->taken = true;
    lock.unlock();
    execute(*job);
    lock.lock();
    job->done = true;
    finished_.notify_all();
    return true;
}

void HelperThreads::finish(Job& job) {
    std::unique_lock lock(mutex_);
    if (!job.taken) {
        job.taken = true;
        const auto queued = std::find(queue_.begin(), queue_.end(), &job);
        if (queued != queue_.end()) queue_.erase(queued);
        lock.unlock();
        execute(job);
        lock.lock();
        job.done = true;
    }
    while (!job.done)
        if (!run_one(lock)) finished_.wait(lock, [&] { return job.done || !queue_.empty(); });
    if (job.failure) std::rethrow_exception(job.failure);
}

void HelperThreads::run_all(std::span<const std::function<void()>> tasks) {
    std::vector<Job> jobs(tasks.size());  // sized once: offered jobs never move
    for (size_t i = 1; i < tasks.size(); ++i) {
        jobs[i].run = tasks[i];
        offer(jobs[i]);
    }
    std::exception_ptr failure;
    for (size_t i = 0; i < tasks.size(); ++i) try {
            if (i == 0) tasks[0]();
            else finish(jobs[i]);  // every offered job is over before `jobs` is
        } catch (...) {
            if (!failure) failure = std::current_exception();
        }
    if (failure) std::rethrow_exception(failure);
}

void HelperThreads::serve() {
    std::unique_lock lock(mutex_);
    while (true) {
        queued_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
        if (!run_one(lock)) return;  // stopping, nothing queued
    }
}

}  // namespace fh
