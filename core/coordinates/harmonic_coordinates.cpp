#include "core/coordinates/harmonic_coordinates.h"

#include "core/common/error.h"
#include "core/solvers/fem_operators.h"
#include "core/coordinates/mean_value_coordinates.h"
#include "core/solvers/min_quad_with_fixed.h"
#include "core/detail/timing.h"

#include <algorithm>
#include <chrono>
#include <string>

namespace bary
{
namespace
{
void check_cancel(const ProgressCallback& progress, double fraction)
{
  if (progress && !progress(fraction))
    throw Error(ErrorCode::Cancelled, "harmonic coordinates were cancelled");
}

/// Maps a sub-phase's progress into [begin, end] of the caller's.
ProgressCallback slice(const ProgressCallback& progress, double begin, double end)
{
  if (!progress)
    return {};
  return [&progress, begin, end](double f) { return progress(begin + (end - begin) * f); };
}
} // namespace

DenseWeights cage_boundary_values(const Cage& cage, const Eigen::MatrixXd& V,
  const std::vector<int>& boundary, double tolerance)
{
  if (V.cols() != cage.dimension())
    throw Error(ErrorCode::SizeMismatch,
      "mesh vertices have " + std::to_string(V.cols()) + " coordinates but the cage is " +
        std::to_string(cage.dimension()) + "D");
  // On the cage, mean value coordinates are exactly the linear (2D edge) / barycentric (3D
  // face) interpolant of the cage vertices: the hat functions' boundary values.
  MeanValueOptions options;
  options.validate = false;
  options.boundary_tolerance = std::clamp(tolerance, 0.0, 1e-3);
  const MeanValueCoordinates mvc(cage, options);
  DenseWeights values(static_cast<Index>(boundary.size()), cage.num_controls());
  for (std::size_t k = 0; k < boundary.size(); ++k)
  {
    const int v = boundary[k];
    if (v < 0 || v >= V.rows())
      throw Error(ErrorCode::InvalidArgument,
        "boundary vertex index " + std::to_string(v) + " is out of range");
    const Eigen::RowVectorXd x = V.row(v);
    if (mvc.evaluate(x.data(), values.row(static_cast<Index>(k)).data()) != PointLocation::Boundary)
      throw Error(ErrorCode::InvalidArgument,
        "mesh boundary vertex " + std::to_string(v) + " does not lie on the cage (farther than " +
          std::to_string(tolerance) + " x the cage diameter); the mesh must fill the cage exactly");
    // Hat functions lie in [0, 1] and sum to 1; rounding (a vertex a hair off its edge or face)
    // gives entries like -2e-16, which bounded methods (BBW's Eq. 6) would refuse as data.
    auto row = values.row(static_cast<Index>(k));
    row = row.cwiseMax(0.0).cwiseMin(1.0);
    row /= row.sum();
  }
  return values;
}

HarmonicCoordinates::HarmonicCoordinates(
  Cage cage, const HarmonicOptions& options, const ProgressCallback& progress)
  : cage_(std::move(cage))
{
  if (options.validate)
    validate_cage(cage_);
  check_cancel(progress, 0.0);
  const auto t0 = std::chrono::steady_clock::now();
  if (cage_.dimension() == 2)
    mesh_ = mesh_polygon(cage_, options.polygon_mesh, slice(progress, 0.0, 0.4));
  else
    mesh_ = mesh_closed_surface(cage_, options.surface_mesh, slice(progress, 0.0, 0.4));
  report_.mesh_seconds = seconds_since(t0);
  solve(options, progress, 0.4);
}

HarmonicCoordinates::HarmonicCoordinates(
  Cage cage, DomainMesh mesh, const HarmonicOptions& options, const ProgressCallback& progress)
  : cage_(std::move(cage))
  , mesh_(std::move(mesh))
{
  if (options.validate)
    validate_cage(cage_);
  if (mesh_.control_vertex.size() != cage_.num_controls())
    throw Error(ErrorCode::InvalidArgument,
      "the mesh maps " + std::to_string(mesh_.control_vertex.size()) +
        " cage vertices but the cage has " + std::to_string(cage_.num_controls()));
  solve(options, progress, 0.0);
}

HarmonicCoordinates::~HarmonicCoordinates() = default;
HarmonicCoordinates::HarmonicCoordinates(HarmonicCoordinates&&) noexcept = default;
HarmonicCoordinates& HarmonicCoordinates::operator=(HarmonicCoordinates&&) noexcept = default;

void HarmonicCoordinates::solve(
  const HarmonicOptions& options, const ProgressCallback& progress, double begin)
{
  const Eigen::MatrixXd& V = mesh_.V;
  const Eigen::MatrixXi& T = mesh_.T;
  if (V.rows() == 0 || T.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the domain mesh is empty");
  if (T.cols() != cage_.dimension() + 1)
    throw Error(ErrorCode::SizeMismatch,
      "a " + std::to_string(cage_.dimension()) + "D cage needs a mesh of " +
        (cage_.dimension() == 2 ? std::string("triangles") : std::string("tetrahedra")));
  report_.mesh_vertices = V.rows();
  report_.mesh_cells = T.rows();
  report_.boundary_vertices = static_cast<Index>(mesh_.boundary_vertices.size());

  // Every cage vertex must be a boundary vertex of the mesh (Lagrange property).
  std::vector<char> on_boundary(static_cast<std::size_t>(V.rows()), 0);
  for (int b : mesh_.boundary_vertices)
    if (b >= 0 && b < V.rows())
      on_boundary[static_cast<std::size_t>(b)] = 1;
  for (Index i = 0; i < cage_.num_controls(); ++i)
  {
    const int v = mesh_.control_vertex(i);
    if (v < 0 || v >= V.rows() || !on_boundary[static_cast<std::size_t>(v)] ||
      (V.row(v) - cage_.V.row(i)).norm() > options.boundary_tolerance * cage_.diameter())
      throw Error(ErrorCode::InvalidArgument,
        "cage vertex " + std::to_string(i) + " is not a boundary vertex of the domain mesh");
  }

  const DenseWeights boundary_values =
    cage_boundary_values(cage_, V, mesh_.boundary_vertices, options.boundary_tolerance);
  check_cancel(progress, begin + 0.1 * (1.0 - begin));

  // min 1/2 w^T K w subject to w = hat values on the boundary: K_II w_I = -K_IB w_B.
  auto t0 = std::chrono::steady_clock::now();
  const Eigen::SparseMatrix<double> K = stiffness_matrix(V, T);
  Eigen::VectorXi known(static_cast<Index>(mesh_.boundary_vertices.size()));
  for (std::size_t k = 0; k < mesh_.boundary_vertices.size(); ++k)
    known(static_cast<Index>(k)) = mesh_.boundary_vertices[k];
  MinQuadWithFixed problem;
  problem.precompute(K, known, options.backend);
  report_.factor_seconds = seconds_since(t0);
  report_.backend = problem.solver().backend();
  check_cancel(progress, begin + 0.7 * (1.0 - begin));

  t0 = std::chrono::steady_clock::now();
  const Eigen::MatrixXd W = problem.solve(Eigen::MatrixXd(), Eigen::MatrixXd(boundary_values));
  report_.solve_seconds = seconds_since(t0);
  if (!W.allFinite())
    throw Error(ErrorCode::NotConverged, "the harmonic solve produced non-finite weights");

  // residual of the discrete Laplace equation at interior vertices
  const Eigen::MatrixXd R = K * W;
  double residual = 0.0;
  for (Index r = 0; r < problem.unknown().size(); ++r)
    residual = std::max(residual, R.row(problem.unknown()(r)).cwiseAbs().maxCoeff());
  report_.max_residual = residual;

  mesh_weights_ = W;
  locator_ = std::make_unique<MeshPointLocator>(V, T);
  check_cancel(progress, 1.0);
}

DenseWeights HarmonicCoordinates::evaluate(const Points& P, OutsidePolicy policy,
  std::vector<Index>* outside, const ProgressCallback& progress) const
{
  if (P.cols() != cage_.dimension())
    throw Error(ErrorCode::SizeMismatch,
      "the points have " + std::to_string(P.cols()) + " coordinates but the cage is " +
        std::to_string(cage_.dimension()) + "D");
  MeshPointLocator::Result result = locator_->interpolate(mesh_weights_, P, policy, progress);
  if (outside)
    *outside = std::move(result.outside);
  return std::move(result.W);
}

} // namespace bary
