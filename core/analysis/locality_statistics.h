#pragma once
/// @file locality_statistics.h
/// How local a weight field is, and its compact (reduced) form: the statistics of Zhang et al.,
/// "Local barycentric coordinates", ACM TOG 33(6), 2014, §5 (Eq. 19-21, Fig. 14-15, Table 1),
/// for the weights of any method (#P by #C, e.g. at the vertices of a domain mesh).
///
/// - P(t) (Eq. 19-20): the fraction of the domain where |w_i| <= t, averaged over the control
///   points: large P for small t means each control point influences a small region.
/// - Q(k) (Eq. 21): the fraction of the domain where more than k-1 weights exceed the threshold
///   of negligible influence, 10^-3 / #C by default (§3.2, "Remark"): Q(k) small for small k
///   means each point depends on few control points. The mean number of significant weights is
///   sum_{k>=1} Q(k).
/// "Fraction of the domain" is the measure-weighted fraction of the points: each point (row)
/// carries a measure (e.g. its lumped area/volume, vertex_measures()); without measures every
/// point counts the same.
///
/// reduce_weights keeps only the weights above the threshold (the paper's compact
/// representation, Table 1) as a row-major sparse matrix and renormalises the rows (see
/// Renormalization), reporting what the reduction costs in partition of unity and reproduction.

#include "core/common/types.h"

#include <vector>

namespace bary
{

/// Eq. 19-21 of one weight field.
struct LocalityStatistics
{
  double threshold = 0;      ///< threshold of negligible influence used for Q and the supports
  std::vector<double> t;     ///< sample values of t (ascending)
  std::vector<double> P;     ///< P(t) (Eq. 20) at each t, in [0, 1]
  std::vector<int> k;        ///< 1 .. #C
  std::vector<double> Q;     ///< Q(k) (Eq. 21) at each k, in [0, 1], non-increasing
  double mean_support = 0;   ///< measure-weighted mean of sigma(x) = #{i : w_i(x) > threshold}
  double max_support = 0;    ///< max of sigma over the points
  /// Per control point i: the measure-weighted fraction of the domain where w_i > threshold
  /// (1 - phi_i(threshold) of Eq. 19, with > instead of <=), #C entries.
  std::vector<double> influence_fraction;
};

/// Default t samples: 0 and 10^(-6 + j/4), j = 0 .. 24 (1e-6 to 1), 26 values.
std::vector<double> default_locality_t();

/// Statistics of @p W (#P by #C).
/// @param threshold > 0, or negative for the paper's 1e-3 / #C.
/// @param measure #P non-negative per-point measures (e.g. vertex_measures(V, T)), or empty for
///   equal weights.
/// @param t the t values for P (any order, sorted in the result); empty: default_locality_t().
/// @throws Error(EmptyInput) for an empty W; Error(SizeMismatch) when measure has the wrong
///   size; Error(InvalidArgument) for a zero threshold, negative or zero-sum measures;
///   Error(NonFinite) for NaN / infinite weights or measures.
LocalityStatistics locality_statistics(const DenseWeights& W, double threshold = -1.0,
  const Eigen::VectorXd& measure = Eigen::VectorXd(), const std::vector<double>& t = {});

/// The lumped (barycentric) area/volume of each mesh vertex: 1/(d+1) of its incident elements'
/// (the diagonal of mass_matrix(V, T)), #V entries summing to the mesh's area/volume.
/// @throws the errors of fem_operators.h's mass_matrix.
Eigen::VectorXd vertex_measures(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T);

/// How reduce_weights fixes a row after dropping its small weights.
enum class Renormalization
{
  /// Keep the remaining weights as they are (partition of unity off by the dropped mass).
  None,
  /// Divide the row by the sum of its remaining weights: partition of unity exact (to
  /// rounding), weights stay >= 0 (if they were), reproduction off by at most the dropped mass
  /// times the distance to the farthest dropped control point.
  RowSum,
  /// Least-norm correction of the remaining weights so that partition of unity and
  /// reproduction hold exactly (to rounding): w + A (A^T A)^-1 (b - A^T w) with A = [c_i 1] over
  /// the row's support and b = [x 1]. Keeps linear precision; a remaining weight can become
  /// slightly negative (by about the dropped mass). Rows whose remaining control points do not
  /// span the space (fewer than dim + 1 affinely independent ones) cannot reproduce their point:
  /// they fall back to RowSum.
  Affine
};

/// Weights with the negligible ones dropped.
struct ReducedWeights
{
  SparseWeights W;               ///< #P by #C, row-major (CSR), only w > threshold kept
  double threshold = 0;          ///< the threshold used
  Renormalization renormalization = Renormalization::RowSum;
  double partition_error = 0;    ///< max_p |sum_i W(p,i) - 1| after reduction
  /// max_p |sum_i W(p,i) c_i - x_p| / (diameter of the controls' bounding box) after reduction;
  /// NaN when controls and points were not given.
  double reproduction_error = 0;
  double max_dropped = 0;        ///< max over rows of the sum of the dropped |weights|
  double min_weight = 0;         ///< smallest stored weight after renormalisation
  Index nonzeros = 0;            ///< stored entries
  /// CSR bytes (8-byte values, 4-byte column indices, #P + 1 row offsets) / dense bytes
  /// (#P #C doubles).
  double memory_fraction = 0;
};

/// Keeps the weights > @p threshold of @p W (#P by #C) and renormalises each row.
/// @param threshold > 0, or negative for 1e-3 / #C.
/// @param controls #C by dim control points and @p points #P by dim points of the rows, both
///   or neither: needed for the reproduction error (and for Renormalization::Affine).
/// @param renormalize true: Renormalization::RowSum, false: None.
/// @throws Error(EmptyInput) for an empty W; Error(SizeMismatch) for inconsistent shapes or only
///   one of controls / points; Error(NonFinite) for NaN / infinite input; Error(InvalidArgument)
///   for Affine without controls and points or a zero threshold; Error(InvalidArgument) naming
///   a row whose kept weights sum to <= 0 (RowSum).
ReducedWeights reduce_weights(const DenseWeights& W, double threshold,
  const Points* controls = nullptr, const Points* points = nullptr, bool renormalize = true);

/// The same with an explicit renormalisation mode.
ReducedWeights reduce_weights(const DenseWeights& W, double threshold, Renormalization mode,
  const Points* controls = nullptr, const Points* points = nullptr);

} // namespace bary
