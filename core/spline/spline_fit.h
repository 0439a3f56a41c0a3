#pragma once
/// @file spline_fit.h
/// A C1 spline fitted to a given map (Rodrigues et al. 2014 start from the identity; BaryLab
/// also starts from what a user has: a cage deformation, a registration, any map sampled at
/// points): the least-squares spline through the samples among the C1 splines on the net,
/// min sum_s |phi(x_s) - y_s|^2 + epsilon E(c - c0) subject to every quadrilateral condition,
/// the redundant conditions removed by exact elimination (as the editor does), the rest solved
/// as one sparse KKT system. E is the membrane energy of the displacement from c0 over the edges
/// of the Bézier net (sum over net edges pq of |u_p - u_q|^2, plus 1e-6 |u|^2): where samples are
/// too few to decide the spline, the displacement decays smoothly away from them. epsilon is
/// relative to the largest diagonal entry of the samples' normal matrix; c0 is the identity for
/// a deformation, 0 for a scalar spline.

#include "core/spline/triangular_spline.h"

#include <memory>
#include <optional>
#include <vector>

namespace bary
{

/// Result of fit_spline.
struct SplineFit
{
  std::optional<TriangularSpline> spline;
  double rms_error = 0; ///< root mean square of |phi(x_s) - y_s| over the samples
  double max_error = 0; ///< largest |phi(x_s) - y_s|
  Index independent_conditions = 0;
  Index conditions = 0;
};

/// Fits a spline on @p net to samples (@p X: #S by 2 domain points, @p Y: #S by m values).
/// Samples at the nominal positions of every control point (net->nominal(): 21 per triangle at
/// d = 5) determine each piece; more samples are a least-squares fit.
/// @throws Error(SizeMismatch) for X, Y of different row counts or X without 2 columns,
///   Error(EmptyInput) for no sample, Error(NonFinite), Error(PointsOutside) naming a sample
///   outside the domain, Error(InvalidArgument) for a regularization outside [0, 1]
/// @param pinned control points held at c0 (e.g. the border, kept where it is)
SplineFit fit_spline(std::shared_ptr<const SplineNet> net, const Points& X,
  const Eigen::MatrixXd& Y, double regularization = 1e-6, const std::vector<Index>& pinned = {});

} // namespace bary
