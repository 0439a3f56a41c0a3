// Tests for core/common/progress.h: the fraction mapping, throttling, cancellation and thread safety
// of ProgressReporter.
#include "core/common/error.h"
#include "core/common/progress.h"
#include "error_matchers.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

namespace
{
using bary::ErrorCode;
using bary::ProgressReporter;
using bary::test::throws_error;

TEST(ProgressReporter, EmptyCallbackNeverCancels)
{
  ProgressReporter reporter({}, 10);
  for (int i = 0; i < 20; ++i) // more units than announced is harmless
    EXPECT_TRUE(reporter.step());
  EXPECT_TRUE(reporter.finish());
  EXPECT_FALSE(reporter.cancelled());
  EXPECT_NO_THROW(reporter.throw_if_cancelled("nothing"));
}

TEST(ProgressReporter, FractionsAreNonDecreasingInRangeAndEndAtOne)
{
  std::vector<double> seen;
  ProgressReporter reporter(
    [&](double f) {
      seen.push_back(f);
      return true;
    },
    1000);
  for (int i = 0; i < 1000; ++i)
    ASSERT_TRUE(reporter.step());
  ASSERT_TRUE(reporter.finish());
  ASSERT_GE(seen.size(), 2u);
  for (std::size_t k = 0; k < seen.size(); ++k)
  {
    EXPECT_GE(seen[k], 0.0);
    EXPECT_LE(seen[k], 1.0);
    if (k > 0)
    {
      EXPECT_LE(seen[k - 1], seen[k]) << "fraction decreased at call " << k;
    }
  }
  EXPECT_EQ(seen.back(), 1.0);
  // The first unit is reported: 1 / 1000, up to one rounding.
  EXPECT_NEAR(seen.front(), 0.001, 1e-18);
}

TEST(ProgressReporter, ThrottlesToAboutOneCallPerPercent)
{
  int calls = 0;
  ProgressReporter reporter(
    [&](double) {
      ++calls;
      return true;
    },
    100000);
  for (int i = 0; i < 100000; ++i)
    reporter.step();
  reporter.finish();
  // stride = total / 100: ~100 reports plus the final one; certainly not one per unit.
  EXPECT_GE(calls, 50);
  EXPECT_LE(calls, 102);
}

TEST(ProgressReporter, MapsThePhaseOntoItsSlice)
{
  std::vector<double> seen;
  ProgressReporter reporter(
    [&](double f) {
      seen.push_back(f);
      return true;
    },
    4, 0.5, 0.75);
  for (int i = 0; i < 4; ++i)
    reporter.step();
  reporter.finish();
  // Every unit is reported (stride 1): 0.5 + 0.25 * k / 4 for k = 1..4, then the end 0.75.
  const std::vector<double> expected = { 0.5625, 0.625, 0.6875, 0.75, 0.75 };
  ASSERT_EQ(seen.size(), expected.size());
  for (std::size_t k = 0; k < seen.size(); ++k)
    EXPECT_DOUBLE_EQ(seen[k], expected[k]) << "call " << k;
}

TEST(ProgressReporter, ZeroTotalDoesNotDivideByZero)
{
  std::vector<double> seen;
  ProgressReporter reporter(
    [&](double f) {
      seen.push_back(f);
      return true;
    },
    0);
  EXPECT_TRUE(reporter.finish());
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0], 1.0);
}

TEST(ProgressReporter, CancellationStopsAndThrows)
{
  int calls = 0;
  ProgressReporter reporter(
    [&](double f) {
      ++calls;
      return f < 0.3;
    },
    10);
  int accepted = 0;
  while (reporter.step())
    ++accepted;
  EXPECT_EQ(accepted, 2); // 0.1 and 0.2 accepted, 0.3 cancels
  EXPECT_TRUE(reporter.cancelled());
  EXPECT_FALSE(reporter.step());
  EXPECT_FALSE(reporter.finish());
  EXPECT_EQ(calls, 3) << "the callback must not be called again once it cancelled";
  EXPECT_TRUE(throws_error([&] { reporter.throw_if_cancelled("the phase under test"); },
    ErrorCode::Cancelled, { "the phase under test" }));
}

TEST(ProgressReporter, CallbackIsNeverCalledConcurrently)
{
  std::atomic<int> inside{ 0 }, overlaps{ 0 }, calls{ 0 };
  ProgressReporter reporter(
    [&](double f) {
      if (inside.fetch_add(1) != 0)
        ++overlaps;
      ++calls;
      std::this_thread::yield();
      inside.fetch_sub(1);
      return f >= 0.0 && f <= 1.0;
    },
    4 * 20000);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&] {
      for (int i = 0; i < 20000; ++i)
        reporter.step();
    });
  for (auto& th : threads)
    th.join();
  EXPECT_TRUE(reporter.finish());
  EXPECT_EQ(overlaps.load(), 0);
  EXPECT_GE(calls.load(), 2);
  EXPECT_FALSE(reporter.cancelled());
}

TEST(ProgressReporter, CancellationIsSeenByAllThreads)
{
  // Each thread steps until step() says stop; a thread that never saw the cancellation would
  // run into the (generous) cap instead.
  constexpr long long total = 4 * 10000, cap = 100 * total;
  ProgressReporter reporter([](double f) { return f < 0.25; }, total);
  std::atomic<int> stopped{ 0 };
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&] {
      for (long long i = 0; i < cap; ++i)
        if (!reporter.step())
        {
          ++stopped;
          return;
        }
    });
  for (auto& th : threads)
    th.join();
  EXPECT_TRUE(reporter.cancelled());
  EXPECT_EQ(stopped.load(), 4) << "every thread must see the cancellation";
  EXPECT_TRUE(throws_error(
    [&] { reporter.throw_if_cancelled("threads"); }, ErrorCode::Cancelled, { "threads" }));
}
} // namespace
