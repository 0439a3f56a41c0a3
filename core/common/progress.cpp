#include "core/common/progress.h"

#include "core/common/error.h"

#include <algorithm>
#include <string>

namespace bary
{

ProgressReporter::ProgressReporter(
  const ProgressCallback& callback, long long total, double begin, double end)
  : callback_(callback)
  , total_(std::max(1LL, total))
  , begin_(begin)
  , end_(end)
  , stride_(std::max(1LL, total_ / 100))
{
  next_report_ = 0;
}

bool ProgressReporter::report(double fraction)
{
  if (!callback_)
    return true;
  // One reporter at a time, from any thread; the others skip (they will report later).
  bool expected = false;
  if (!busy_.compare_exchange_strong(expected, true))
    return !cancelled();
  // Threads may report out of order (one read done_ earlier but won busy_ later): the callback
  // only ever sees increasing fractions.
  fraction = std::clamp(fraction, 0.0, 1.0);
  if (fraction >= last_fraction_)
  {
    last_fraction_ = fraction;
    if (!callback_(fraction))
      cancelled_ = true;
  }
  busy_ = false;
  return !cancelled();
}

bool ProgressReporter::step(long long units)
{
  if (cancelled())
    return false;
  const long long done = done_.fetch_add(units, std::memory_order_relaxed) + units;
  long long next = next_report_.load(std::memory_order_relaxed);
  if (done >= next && next_report_.compare_exchange_strong(next, done + stride_))
    return report(begin_ + (end_ - begin_) * static_cast<double>(done) / total_);
  return true;
}

bool ProgressReporter::finish()
{
  if (cancelled())
    return false;
  return report(end_);
}

void ProgressReporter::throw_if_cancelled(const char* what) const
{
  if (cancelled())
    throw Error(ErrorCode::Cancelled, std::string(what) + " was cancelled");
}

} // namespace bary
