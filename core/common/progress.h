#pragma once
/// @file progress.h
/// Progress reporting and cancellation for long computations.

#include <atomic>
#include <functional>

namespace bary
{

/// Called with the fraction of work done, in [0, 1]. Return false to ask the computation to
/// stop; it then throws Error(ErrorCode::Cancelled). Called from one thread at a time.
using ProgressCallback = std::function<bool(double fraction)>;

/// Maps the progress of one phase onto the slice [begin, end] of the caller's [0, 1] and
/// throttles calls. Thread-safe: any thread may call step(); only the thread that holds the
/// reporting turn calls the user's callback, and a cancellation is seen by all threads.
class ProgressReporter
{
public:
  /// @param callback may be empty (no reporting, never cancelled)
  /// @param total number of work units of this phase (> 0)
  ProgressReporter(const ProgressCallback& callback, long long total, double begin = 0.0,
    double end = 1.0);

  /// Record @p units finished units; may call the callback. Returns false once cancelled.
  bool step(long long units = 1);
  /// True once the callback returned false.
  bool cancelled() const noexcept { return cancelled_.load(std::memory_order_relaxed); }
  /// Report the end of the phase (fraction = end). Returns false if cancelled.
  bool finish();
  /// Throws Error(ErrorCode::Cancelled) if cancelled, naming @p what was interrupted.
  void throw_if_cancelled(const char* what) const;

private:
  bool report(double fraction);

  ProgressCallback callback_;
  long long total_;
  double begin_, end_;
  long long stride_;
  std::atomic<long long> done_{ 0 };
  std::atomic<long long> next_report_{ 0 };
  std::atomic<bool> busy_{ false };
  double last_fraction_ = -1.0; ///< the last fraction reported (guarded by busy_)
  std::atomic<bool> cancelled_{ false };
};

} // namespace bary
