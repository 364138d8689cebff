// HelperThreads: every offered job runs once, wherever it runs; nested offers finish; a job's exception reaches finish;
// run_all runs every task and rethrows the first failure in task order.
#include <atomic>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "scene/helper_threads.h"

namespace {

// Sums f(i) over [begin, end) by halving the range and offering the second half, as the BVH build offers subtrees.
uint64_t sum_offering(fh::HelperThreads& helpers, uint64_t begin, uint64_t end, std::vector<std::atomic<int>>& runs) {
    if (end - begin <= 64) {
        uint64_t sum = 0;
        for (uint64_t i = begin; i < end; ++i) {
            runs[i].fetch_add(1);
            sum += i * i;
        }
        return sum;
    }
    const uint64_t mid = begin + (end - begin) / 2;
    uint64_t second = 0;
    fh::HelperThreads::Job job;
    job.run = [&] { second = sum_offering(helpers, mid, end, runs); };
    helpers.offer(job);
    const uint64_t first = sum_offering(helpers, begin, mid, runs);
    helpers.finish(job);
    return first + second;
}

TEST(HelperThreads, EveryJobRunsOnceWithAnyNumberOfHelpers) {
    constexpr uint64_t n = 100000;
    uint64_t expected = 0;
    for (uint64_t i = 0; i < n; ++i) expected += i * i;
    for (uint32_t helpers : {0u, 1u, 3u, 7u}) {
        std::vector<std::atomic<int>> runs(n);
        fh::HelperThreads threads(helpers);
        EXPECT_EQ(sum_offering(threads, 0, n, runs), expected) << helpers << " helpers";
        for (uint64_t i = 0; i < n; ++i) ASSERT_EQ(runs[i].load(), 1) << "element " << i << ", " << helpers << " helpers";
    }
}

TEST(HelperThreads, FinishRethrowsWhatTheJobThrew) {
    for (uint32_t helpers : {0u, 1u}) {
        fh::HelperThreads threads(helpers);
        fh::HelperThreads::Job job;
        job.run = [] { throw std::runtime_error("job failed"); };
        threads.offer(job);
        EXPECT_THROW(threads.finish(job), std::runtime_error) << helpers << " helpers";
    }
}

TEST(HelperThreads, RunAllRunsEveryTaskAndRethrowsTheFirstFailureInTaskOrder) {
    for (uint32_t helpers : {0u, 1u, 3u}) {
        fh::HelperThreads threads(helpers);
        std::vector<std::atomic<int>> runs(4);
        const std::function<void()> tasks[] = {
            [&] { runs[0].fetch_add(1); },
            [&] {
                runs[1].fetch_add(1);
                throw std::runtime_error("second");
            },
            [&] {
                runs[2].fetch_add(1);
                throw std::logic_error("third");
            },
            [&] { runs[3].fetch_add(1); }};
        try {
            threads.run_all(tasks);
            ADD_FAILURE() << "run_all did not throw, " << helpers << " helpers";
        } catch (const std::runtime_error& e) {
            EXPECT_STREQ(e.what(), "second") << helpers << " helpers";
        }
        for (int i = 0; i < 4; ++i) EXPECT_EQ(runs[i].load(), 1) << "task " << i << ", " << helpers << " helpers";
    }
}

}  // namespace
