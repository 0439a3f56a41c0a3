#include "core/surface/surface_curves.h"

#include "core/common/error.h"

#include <limits>
#include <string>

namespace bary
{

DenseWeights bspline_weights(Index m, Index per_segment, bool closed)
{
  if (m < 4)
    throw Error(ErrorCode::InvalidArgument, "a cubic B-spline needs at least 4 control points, got " +
        std::to_string(m));
  if (per_segment < 1 || per_segment > kMaxSamplesPerSegment)
    throw Error(ErrorCode::InvalidArgument, "the samples per segment must be in [1, " +
        std::to_string(kMaxSamplesPerSegment) + "], got " + std::to_string(per_segment));
  const Index segments = closed ? m : m - 3;
  const Index rows = segments * per_segment + (closed ? 0 : 1);
  if (rows > std::numeric_limits<int>::max() || rows * m > std::numeric_limits<int>::max())
    throw Error(ErrorCode::InvalidArgument, "the curve would have too many samples");
  DenseWeights W = DenseWeights::Zero(rows, m);
  for (Index r = 0; r < rows; ++r)
  {
    Index s = r / per_segment;
    double t = static_cast<double>(r % per_segment) / static_cast<double>(per_segment);
    if (s == segments) // the end point of an open curve
    {
      s = segments - 1;
      t = 1.0;
    }
    const double u = 1.0 - t;
    const double b[4] = { u * u * u / 6.0, (3 * t * t * t - 6 * t * t + 4) / 6.0,
      (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6.0, t * t * t / 6.0 };
    for (int k = 0; k < 4; ++k)
      W(r, (s + k) % m) += b[k];
  }
  return W;
}

} // namespace bary
