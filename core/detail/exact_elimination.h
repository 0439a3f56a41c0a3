#pragma once
/// @file exact_elimination.h
/// Gaussian elimination of the C1 conditions with exact rational arithmetic (GMP), for the
/// spline editor's redundancy elimination (Rodrigues et al. 2014, §4.3.2). The conditions'
/// coefficients are barycentric coordinates of domain vertices; computed from the vertices'
/// double coordinates (each an exact dyadic rational) they are exact rationals, so ranks and
/// dependencies are decided without tolerances. The only file that includes GMP.

#include <array>
#include <vector>

namespace bary::detail
{

/// One quadrilateral condition -q^v + beta0 q^u + beta1 e_P + beta2 e_Q = 0 as elimination
/// input: the class of each of its four points' columns, and the domain vertices u0, P, Q, v0
/// from which the betas are computed exactly.
struct ExactCondition
{
  /// Per point: 0 .. unknowns - 1 (a derived point), unknowns .. unknowns + anchors - 1 (an
  /// anchor), or -1 (a fixed point: a constant, ignored by the elimination).
  std::array<int, 4> column{ -1, -1, -1, -1 };
  std::array<std::array<double, 2>, 4> vertex{};
};

struct ExactElimination
{
  /// The input rows that are linearly independent in the unknowns' columns (a maximal such
  /// set, in input order: a row is kept when it is independent of the rows kept before it).
  std::vector<int> independent;
  /// First row that, reduced by the kept rows, has no unknown left but an anchor: the anchors'
  /// new positions cannot be met by the unknowns in general (-1: none).
  int conflict = -1;
};

/// Eliminates the rows over the rationals.
ExactElimination eliminate_exact(
  const std::vector<ExactCondition>& rows, int unknowns, int anchors);

/// The barycentric coordinates of v0 in (u0, P, Q), computed exactly and rounded to double.
std::array<double, 3> exact_barycentric(const std::array<std::array<double, 2>, 4>& vertex);

} // namespace bary::detail
