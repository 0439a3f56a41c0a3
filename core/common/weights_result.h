#pragma once
/// @file weights_result.h
/// What every weights computation returns: the weights, where each point lies, the undefined
/// rows, named statistics and whether the solver converged. The result structs of the methods
/// (MeanValueResult, GreenResult, CelestialResult, LBCResult, BBWResult) derive from
/// WeightsResult and add their own fields; each method fills the shared fields itself, so a
/// caller (filter, CLI) reports any method the same way.

#include "core/common/types.h"

#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace bary
{

/// Where a point lies relative to the cage / the control points' hull / the domain mesh.
/// The values are those of the "CageLocation" array of the filters: 0 inside, 1 outside, 2 on
/// the cage.
enum class PointLocation : unsigned char
{
  Inside = 0,   ///< strictly inside (MVC: |winding number| = 1, either cage orientation)
  Outside = 1,  ///< strictly outside (MVC: winding number 0)
  Boundary = 2, ///< on the cage / hull / mesh boundary (within the method's tolerance)
};

/// Named figures of a computation, in the order computed (iterations, residuals, seconds, ...).
using Statistics = std::vector<std::pair<std::string, double>>;

/// The weights of a mesh-based method (harmonic, BBW, LBC) at the vertices of its domain mesh,
/// from which the points' weights are interpolated (MeshPointLocator). What a run solves once
/// per cage: a distributed run (vtkBaryCoordinates with a controller of several processes)
/// solves on one process and sends this to the others, which only interpolate
/// (WeightsInput::mesh_weights), so that every process gets the serial run's weights.
struct MeshWeights
{
  Eigen::MatrixXd V;     ///< #V by dim vertices (the input's scale)
  Eigen::MatrixXi T;     ///< #T by dim + 1 simplices
  DenseWeights W;        ///< #V by #C
  Statistics statistics; ///< the solve's figures (mesh size, iterations, residuals, seconds)
};

/// What every weights computation returns.
struct WeightsResult
{
  DenseWeights W;                      ///< #P by #C (row-major)
  /// #P by #F (row-major): the coefficients of the cage's face normals (3D: the triangles of
  /// Cage::F in order; 2D: edge j from V(j) to V(j+1)), for methods whose deformation is not
  /// W alone (Green coordinates: x = W V + face_weights N, N the faces' unit normals as their
  /// vertex order orients them; see green_coordinates.h). Empty (0 columns) for every other
  /// method.
  DenseWeights face_weights;
  std::vector<PointLocation> location; ///< #P (may be empty where a method has none)
  std::vector<Index> undefined;        ///< rows of W that are NaN (undefined weights), increasing
  Statistics statistics;               ///< named figures, order computed
  bool converged = true;               ///< the method's solver reached its tolerance
  /// Control points the method added after the given ones (celestial hull points, §6 of
  /// Cerveró et al.), #A by dim: W's last #A columns are theirs, in this order (empty: none).
  Points added_controls;
  /// Mesh-based methods: the domain mesh and its vertices' weights (null for the others).
  std::shared_ptr<MeshWeights> mesh_weights;

  /// The value of the first statistic called @p name, or @p fallback when there is none.
  double statistic(
    const std::string& name, double fallback = std::numeric_limits<double>::quiet_NaN()) const;
  /// How many points lie @p where (counted in location).
  Index count(PointLocation where) const;
};

} // namespace bary
