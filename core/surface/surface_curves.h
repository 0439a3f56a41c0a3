#pragma once
/// @file surface_curves.h
/// Curves on surfaces as weighted averages (Panozzo et al., "Weighted averages on surfaces",
/// ACM TOG 32(4), 2013, §4.1, Fig. 2): a point of a B-spline is the weighted average of its
/// control points with the basis functions as weights, so a spline whose control points lie on
/// a surface is a sequence of forward problems (WeightedAverages::forward with warm starts: each
/// sample starts from the previous one, as the paper does when a control point is dragged).
///
/// Uniform cubic B-splines: with control points c_0 .. c_{m-1}, segment s is
/// sum_{k=0..3} B_k(t) c_{s+k} for t in [0, 1), B_0 = (1-t)^3/6, B_1 = (3t^3 - 6t^2 + 4)/6,
/// B_2 = (-3t^3 + 3t^2 + 3t + 1)/6, B_3 = t^3/6 (partition of unity, non-negative, C2). An open
/// curve has m - 3 segments (it starts near c_1 and ends near c_{m-2}, inside the control
/// polygon, as uniform B-splines do); a closed curve has m segments, indices taken modulo m.

#include "core/common/types.h"

namespace bary
{

/// Largest number of samples per segment of bspline_weights.
inline constexpr Index kMaxSamplesPerSegment = 100000;

/// The weights of the samples of a uniform cubic B-spline: #samples by m (one row per sample,
/// the basis functions of the 4 control points of its segment; each row sums to 1). Samples
/// are @p per_segment evenly spaced parameters per segment, plus the end point of an open
/// curve: (m - 3) per_segment + 1 rows (open) or m per_segment rows (closed).
/// @throws Error(InvalidArgument) when m < 4, per_segment is outside [1, kMaxSamplesPerSegment], or the
///   number of rows would exceed 2^31.
DenseWeights bspline_weights(Index control_points, Index per_segment, bool closed);

} // namespace bary
