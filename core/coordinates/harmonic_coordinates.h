#pragma once
/// @file harmonic_coordinates.h
/// Harmonic coordinates (Joshi, Meyer, DeRose, Green & Sanocki, "Harmonic coordinates for
/// character articulation", ACM TOG 26(3), 2007): w_i is the solution of Laplace's equation
/// inside the cage with w_i = the piecewise-linear "hat" of cage vertex i on the cage (linear on
/// 2D edges, barycentric on 3D faces). Discretised with linear finite elements on a
/// triangulation (2D) or tetrahedralization (3D) of the cage's interior: one sparse Cholesky
/// factorisation of the stiffness matrix restricted to interior vertices, all #C right-hand sides
/// solved together.
///
/// Properties (discrete): partition of unity and linear reproduction to solver precision, Lagrange
/// property at the cage vertices, linear on cage edges / faces, non-negative in 2D on a Delaunay
/// mesh (discrete maximum principle; may dip slightly below 0 in 3D), not defined outside the cage.
/// They are the baseline of every comparison (the LBC paper's "HBC").

#include "core/common/cage.h"
#include "core/meshing/domain_mesh.h"
#include "core/meshing/mesh_point_locator.h"
#include "core/common/progress.h"
#include "core/solvers/sparse_cholesky.h"
#include "core/common/types.h"

#include <memory>
#include <vector>

namespace bary
{

/// Options for harmonic coordinates.
struct HarmonicOptions
{
  /// Triangulation of a 2D cage (quality, target cell count, Steiner points, holes).
  PolygonMeshOptions polygon_mesh;
  /// Tetrahedralization of a 3D cage (quality, max volume, Steiner points).
  SurfaceMeshOptions surface_mesh;
  /// Linear solver backend (CHOLMOD when available).
  SparseCholesky::Backend backend = SparseCholesky::Backend::Automatic;
  /// Validate the cage first (validate_cage).
  bool validate = true;
  /// Relative tolerance (times the cage diameter) within which a mesh boundary vertex must lie
  /// on the cage; its value is the cage's linear interpolant there.
  double boundary_tolerance = 1e-9;
};

/// What a computation did, for reports.
struct HarmonicReport
{
  Index mesh_vertices = 0, mesh_cells = 0, boundary_vertices = 0;
  double mesh_seconds = 0, factor_seconds = 0, solve_seconds = 0;
  double max_residual = 0; ///< max |K_II w_I + K_IB w_B| over interior rows, all columns
  SparseCholesky::Backend backend = SparseCholesky::Backend::Automatic;
};

/// Harmonic coordinates of a cage: meshes the cage's interior (or takes a given mesh of it),
/// solves on the mesh once, then evaluates at any points inside.
class HarmonicCoordinates
{
public:
  /// Meshes the cage's interior with options.polygon_mesh / options.surface_mesh and solves.
  /// @throws Error(InvalidCage ...) for a bad cage, Error(Cancelled) on cancellation, and the
  /// meshing and solver errors.
  explicit HarmonicCoordinates(
    Cage cage, const HarmonicOptions& options = {}, const ProgressCallback& progress = {});

  /// Uses @p mesh, a triangulation/tetrahedralization of the cage's interior whose boundary lies
  /// on the cage (e.g. from mesh_polygon / mesh_closed_surface, or read from a file).
  /// @throws Error(InvalidArgument) if a boundary vertex of the mesh is not on the cage, naming
  /// it, or if a cage vertex is not a mesh vertex.
  HarmonicCoordinates(Cage cage, DomainMesh mesh, const HarmonicOptions& options = {},
    const ProgressCallback& progress = {});

  ~HarmonicCoordinates();
  HarmonicCoordinates(HarmonicCoordinates&&) noexcept;
  HarmonicCoordinates& operator=(HarmonicCoordinates&&) noexcept;

  const Cage& cage() const noexcept { return cage_; }
  const DomainMesh& mesh() const noexcept { return mesh_; }
  /// #V by #C weights at the mesh vertices.
  const DenseWeights& mesh_weights() const noexcept { return mesh_weights_; }
  const HarmonicReport& report() const noexcept { return report_; }

  /// Weights at the rows of @p P (#P by dim): barycentric interpolation in the containing mesh
  /// cell. Points outside the cage are handled by @p policy; their ids go to @p outside.
  DenseWeights evaluate(const Points& P, OutsidePolicy policy = OutsidePolicy::Error,
    std::vector<Index>* outside = nullptr, const ProgressCallback& progress = {}) const;

private:
  void solve(const HarmonicOptions& options, const ProgressCallback& progress, double begin);

  Cage cage_;
  DomainMesh mesh_;
  DenseWeights mesh_weights_;
  HarmonicReport report_;
  std::unique_ptr<MeshPointLocator> locator_;
};

/// Dirichlet values of the cage's hat functions at mesh boundary vertices: row k holds the
/// linear (2D edge) / barycentric (3D face) interpolant of the cage vertices at
/// V.row(boundary[k]), clamped to [0, 1] and scaled to sum to 1 (rounding off an edge or face
/// would otherwise leave entries like -2e-16). Shared by every method with cage boundary conditions (harmonic, BBW with
/// cage handles, LBC). @throws Error(InvalidArgument) naming a vertex that is not on the cage.
DenseWeights cage_boundary_values(const Cage& cage, const Eigen::MatrixXd& V,
  const std::vector<int>& boundary, double tolerance = 1e-9);

} // namespace bary
