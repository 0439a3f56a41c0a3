#pragma once
/// @file parallel_for.h
/// The one parallel loop of core's per-point and per-handle work: chunks of a range handed out
/// by OpenMP (dynamic, one chunk at a time), progress reported by whichever thread finished a
/// chunk (ProgressReporter keeps the fractions increasing; reporting from one thread only left
/// a loaded machine's cancellation unseen until the end when the other threads took every
/// chunk), cancellation seen by every thread between chunks, the first
/// exception rethrown on the calling thread. Every chunk is computed by the same sequential code
/// into its own output, so the results do not depend on the number of threads.

#include "core/common/progress.h"
#include "core/common/types.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace bary::detail
{

/// The number of threads an option `threads` asks for: itself when > 0, else OpenMP's default
/// (1 without OpenMP).
inline int thread_count(int threads)
{
#ifdef _OPENMP
  return threads > 0 ? threads : omp_get_max_threads();
#else
  (void)threads;
  return 1;
#endif
}

/// Runs body(state, begin, end) for the chunks [begin, end) = [c chunk, min(n, (c + 1) chunk))
/// of [0, n), on thread_count(threads) threads (at most one per chunk). Each thread makes its
/// own state with make_state() before its first chunk and hands it to merge(state) (one thread
/// at a time) after its last. After each chunk finished without throwing, its thread reports
/// its end - begin items to @p reporter, whose total must be n. Once the
/// reporter is cancelled or a body threw, the remaining chunks are skipped. Then: the first
/// exception is rethrown; reporter.throw_if_cancelled(what); reporter.finish();
/// reporter.throw_if_cancelled(what).
template<class MakeState, class Body, class Merge>
void parallel_for(Index n, Index chunk, int threads, ProgressReporter& reporter, const char* what,
  MakeState&& make_state, Body&& body, Merge&& merge)
{
  const Index chunks = (n + chunk - 1) / chunk;
  std::atomic<bool> stop{ false };
  std::exception_ptr failure;
  std::mutex mutex;
  const int team = static_cast<int>(std::max<Index>(1, std::min<Index>(thread_count(threads), chunks)));
#pragma omp parallel num_threads(team)
  {
    auto state = make_state();
#pragma omp for schedule(dynamic, 1)
    for (Index c = 0; c < chunks; ++c)
    {
      if (stop.load(std::memory_order_relaxed))
        continue;
      const Index begin = c * chunk, end = std::min(n, begin + chunk);
      try
      {
        body(state, begin, end);
      }
      catch (...)
      {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!failure)
          failure = std::current_exception();
        stop = true;
        continue;
      }
      if (!reporter.step(end - begin))
        stop = true;
    }
    const std::lock_guard<std::mutex> lock(mutex);
    merge(state);
  }
  if (failure)
    std::rethrow_exception(failure);
  reporter.throw_if_cancelled(what);
  reporter.finish();
  reporter.throw_if_cancelled(what);
}

/// parallel_for without per-thread state: body(begin, end).
template<class Body>
void parallel_for(
  Index n, Index chunk, int threads, ProgressReporter& reporter, const char* what, Body&& body)
{
  struct None
  {
  };
  parallel_for(
    n, chunk, threads, reporter, what, [] { return None{}; },
    [&body](None&, Index begin, Index end) { body(begin, end); }, [](None&) {});
}

} // namespace bary::detail
