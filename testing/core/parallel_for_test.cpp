// Tests for core/detail/parallel_for.h: the chunked OpenMP loop with progress and cancellation.
#include "core/detail/parallel_for.h"
#include "core/common/error.h"
#include "error_matchers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace
{
using namespace bary;
using bary::test::throws_error;

/// Squares of 0..n-1 and the chunk each index was computed in, on @p threads threads.
std::vector<double> squares(Index n, Index chunk, int threads, std::vector<int>* visits = nullptr)
{
  std::vector<double> out(static_cast<std::size_t>(n), 0.0);
  std::vector<int> seen(static_cast<std::size_t>(n), 0);
  ProgressReporter reporter({}, n);
  detail::parallel_for(n, chunk, threads, reporter, "squares", [&](Index begin, Index end) {
    for (Index i = begin; i < end; ++i)
    {
      out[static_cast<std::size_t>(i)] = std::sqrt(static_cast<double>(i)) * 1.1;
      ++seen[static_cast<std::size_t>(i)];
    }
  });
  if (visits)
    *visits = seen;
  return out;
}

TEST(ParallelFor, EveryIndexOnceWhateverTheThreads)
{
  for (const Index n : { Index(0), Index(1), Index(7), Index(1000) })
    for (const int threads : { 1, 2, 3, 0 })
    {
      std::vector<int> visits;
      const std::vector<double> a = squares(n, 8, threads, &visits);
      for (const int v : visits)
        EXPECT_EQ(v, 1) << "n " << n << ", threads " << threads;
      EXPECT_EQ(a, squares(n, 8, 1)) << "n " << n << ", threads " << threads;
    }
}

TEST(ParallelFor, PerThreadStateIsMergedOnce)
{
  const Index n = 1003;
  for (const int threads : { 1, 2, 4 })
  {
    long long total = 0;
    int states = 0, merges = 0;
    ProgressReporter reporter({}, n);
    const auto make_state = [&] {
#pragma omp atomic
      ++states;
      return 0LL;
    };
    detail::parallel_for(
      n, 10, threads, reporter, "sum", make_state,
      [](long long& sum, Index begin, Index end) {
        for (Index i = begin; i < end; ++i)
          sum += i;
      },
      [&](long long& sum) {
        total += sum; // merge runs one thread at a time
        ++merges;
      });
    EXPECT_EQ(total, n * (n - 1) / 2) << threads << " threads";
    EXPECT_EQ(states, merges);
    EXPECT_GE(states, 1);
    EXPECT_LE(states, threads);
  }
}

TEST(ParallelFor, ProgressIsMonotoneAndEndsAtTheSliceEnd)
{
  std::vector<double> seen;
  ProgressReporter reporter(
    [&](double f) {
      seen.push_back(f);
      return true;
    },
    5000, 0.2, 0.6);
  detail::parallel_for(5000, 16, 2, reporter, "work", [](Index, Index) {});
  ASSERT_FALSE(seen.empty());
  for (std::size_t k = 1; k < seen.size(); ++k)
    EXPECT_GE(seen[k], seen[k - 1]);
  EXPECT_GE(seen.front(), 0.2);
  EXPECT_EQ(seen.back(), 0.6);
}

TEST(ParallelFor, CancelStopsAndThrowsNamingTheWork)
{
  // One thread: the third report cancels, the remaining chunks are skipped.
  {
    int calls = 0;
    Index computed = 0;
    ProgressReporter reporter([&](double) { return ++calls < 3; }, 100000);
    EXPECT_TRUE(throws_error(
      [&] {
        detail::parallel_for(100000, 8, 1, reporter, "the test loop",
          [&](Index begin, Index end) { computed += end - begin; });
      },
      ErrorCode::Cancelled, { "the test loop was cancelled" }));
    EXPECT_LT(computed, 100000);
  }
  // Two threads: whichever thread finishes a chunk reports, so the cancel is seen during the
  // loop even when one thread takes every chunk (on a loaded machine it did, and only OpenMP's
  // thread 0 reported before); how many chunks run first depends on the schedule.
  {
    int calls = 0;
    Index computed = 0;
    ProgressReporter reporter([&](double) { return ++calls < 3; }, 100000);
    const auto count = [&](Index begin, Index end) {
#pragma omp atomic
      computed += end - begin;
    };
    EXPECT_TRUE(throws_error(
      [&] { detail::parallel_for(100000, 8, 2, reporter, "the test loop", count); },
      ErrorCode::Cancelled, { "the test loop was cancelled" }));
    EXPECT_LT(computed, 100000);
  }
}

TEST(ParallelFor, TheFirstExceptionIsRethrown)
{
  ProgressReporter reporter({}, 100);
  EXPECT_TRUE(throws_error(
    [&] {
      detail::parallel_for(100, 1, 2, reporter, "throwing", [](Index begin, Index) {
        if (begin == 42)
          throw Error(ErrorCode::InvalidArgument, "item 42 is bad");
      });
    },
    ErrorCode::InvalidArgument, { "item 42 is bad" }));
}

TEST(ParallelFor, ThreadCount)
{
  EXPECT_EQ(detail::thread_count(3), 3);
  EXPECT_GE(detail::thread_count(0), 1);
}
} // namespace
