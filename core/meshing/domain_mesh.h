#pragma once
/// @file domain_mesh.h
/// Meshes of the region a cage encloses: a quality triangulation of a polygon's interior (2D,
/// CGAL's constrained Delaunay mesher) or a quality tetrahedralization of a closed triangle
/// surface's interior (3D, TetGen 1.5). The volumetric methods (harmonic coordinates, bounded
/// biharmonic weights, local barycentric coordinates) compute weights at the vertices of such a
/// mesh and interpolate them elsewhere (mesh_point_locator.h).
///
/// Guarantees of both functions:
/// - Lagrange property: every cage vertex is a mesh vertex at exactly the cage's coordinates;
///   mesh vertex i is cage vertex i for i < #C (control_vertex(i) == i).
/// - The mesh fills the cage exactly: its boundary lies on the cage (vertices inserted on cage
///   edges/faces lie on them up to rounding, ~1e-16 of the cage size), its total area/volume is
///   the cage's.
/// - Triangles are counter-clockwise, tetrahedra positively oriented
///   (det[v1 - v0, v2 - v0, v3 - v0] > 0), whatever the cage's orientation.
/// - Deterministic: the same input gives the same mesh.
///
/// @sa MeshPointLocator, validate_cage

#include "core/common/cage.h"
#include "core/common/progress.h"
#include "core/common/types.h"

#include <vector>

namespace bary
{

/// A triangulation (2D) or tetrahedralization (3D) of the region enclosed by a cage.
///
/// Vertex order: the #C cage vertices first (in cage order), then (2D) the vertices of the
/// holes (hole 0's in order, then hole 1's, ...), then the accepted Steiner points in the order
/// requested (a point merged with an earlier one does not get its own vertex), then the vertices
/// the mesher added (on cage edges/faces and inside).
struct DomainMesh
{
  Eigen::MatrixXd V; ///< #V by dim mesh vertices
  /// #T by dim+1: triangles (2D, counter-clockwise) or tetrahedra (3D, positively oriented)
  Eigen::MatrixXi T;
  /// #C: the mesh vertex of each cage vertex, in cage order (the identity, see the vertex order)
  Eigen::VectorXi control_vertex;
  /// #S: the mesh vertex of each requested Steiner point, or -1 when the point was skipped:
  /// outside the domain (2D: also inside a hole), or within steiner_tolerance x the cage
  /// diameter of the domain's boundary. A point within that distance of an earlier accepted
  /// Steiner point is merged with it (same mesh vertex, the earlier point's coordinates).
  /// Accepted points are mesh vertices at exactly the requested coordinates.
  Eigen::VectorXi steiner_vertex;
  /// Mesh vertices on the cage (the outer boundary; 2D hole boundaries are not included),
  /// sorted. Includes the cage vertices.
  std::vector<int> boundary_vertices;
  /// #boundary_vertices by #C: row r writes vertex boundary_vertices[r] as an affine combination
  /// of the cage vertices: a unit row at a cage vertex; on the cage edge (i, i+1) the linear
  /// weights (1 - t, t) (2D); on a cage face the face's barycentric coordinates (3D). These are
  /// the Dirichlet values of coordinates that are linear on the cage (harmonic coordinates).
  SparseWeights boundary_weights;
  /// 2D only: mesh vertices on the holes' boundaries, sorted (empty without holes and in 3D).
  std::vector<int> hole_boundary_vertices;
  /// Wall-clock seconds spent meshing (validation included).
  double seconds = 0.0;

  int dimension() const noexcept { return static_cast<int>(V.cols()); }
  Index num_vertices() const noexcept { return V.rows(); }
  Index num_elements() const noexcept { return T.rows(); }
};

/// Upper bound on the number of cells a size bound may ask for (area / max_area in 2D,
/// volume / max_volume in 3D): larger requests throw Error(InvalidArgument) instead of running
/// out of memory.
constexpr double kMaxRequestedCells = 5e7;

/// The number of cells a domain is meshed with when the caller asks for none: 3000 triangles
/// (dim 2), 20000 tetrahedra (dim 3).
constexpr int default_target_cells(int dim)
{
  return dim == 2 ? 3000 : 20000;
}

/// The range of PolygonMeshOptions::min_angle_degrees (CGAL's refinement terminates for sure up
/// to 20.7 degrees), shared by every front end.
constexpr double kMaxMinAngleDegrees = 20.7;
/// The range of SurfaceMeshOptions::radius_edge_ratio besides 0 (no quality refinement), shared
/// by every front end: TetGen's refinement may not end below about 1.1 (1.0 did not on the
/// bundled kidney cage), and the vertices it may add are bounded (mesh_closed_surface).
constexpr double kMinRadiusEdgeRatio = 1.1;
constexpr double kMaxRadiusEdgeRatio = 10.0;

/// Options of mesh_polygon.
struct PolygonMeshOptions
{
  /// Approximate number of triangles, used when max_area <= 0: the size bound is then
  /// max_area = (area of the domain, holes excluded) / target_cells. Every triangle has an
  /// area <= that bound, so the mesh has at least target_cells triangles; with the default
  /// angle bound it has about 1.5 times as many (measured 1.51-1.56 x for targets 1000 to
  /// 100000 on the test cages, up to 2 x for a target of 100 where the boundary dominates;
  /// Steiner points, holes and sharp corners add more). Must be > 0 when max_area <= 0.
  int target_cells = default_target_cells(2);
  /// Maximum triangle area (> 0 overrides target_cells). Every triangle's area is <= it.
  double max_area = 0.0;
  /// Quality bound: CGAL refines until the smallest angle of every triangle is >= this, except
  /// near cage (and hole) corners whose interior angle is smaller, where small angles may
  /// remain. CGAL's shape criterion is the squared sine of the smallest angle, so the bound
  /// passed is B = sin^2(min_angle_degrees); termination is guaranteed up to 20.7 degrees
  /// (B = 0.125). Range [0, kMaxMinAngleDegrees = 20.7]; 0 = no shape criterion (size only).
  double min_angle_degrees = 20.0;
  /// #S by 2 points to make mesh vertices (model vertices, handle points, samples along
  /// bones); see DomainMesh::steiner_vertex for skipped and merged points.
  Eigen::MatrixXd steiner_points;
  /// Closed simple polygons (#H_k by 2, either orientation) strictly inside the cage, not
  /// touching it nor each other, not nested: the regions they enclose are not meshed. Their
  /// vertices are mesh vertices, numbered after the cage's (see DomainMesh).
  std::vector<Eigen::MatrixXd> holes;
  /// Steiner points within this distance (times the cage diameter) of the boundary (cage and
  /// holes) are skipped; within it of an earlier accepted Steiner point, merged with that one
  /// (exact duplicates always are). Range [0, 0.1].
  double steiner_tolerance = 1e-6;
};

/// Triangulates the interior of the polygon @p cage2d (minus the holes) with CGAL's
/// constrained Delaunay mesher (Delaunay refinement after Ruppert / Shewchuk; CGAL 2D Conforming
/// Triangulations and Meshes, "Delaunay_mesher_2"), with a size bound on the triangle areas and
/// the angle bound of @p options. The cage is validated first (validate_cage).
///
/// Progress: validation and set-up 0-0.1, refinement 0.1-0.95 (estimated from the expected
/// number of vertices), output 0.95-1. Cancelling throws Error(Cancelled).
///
/// @throws Error(InvalidCage | EmptyInput | NonFinite | SizeMismatch) from validate_cage, and
///   Error(InvalidCage) for a hole that is not simple, touches the cage or another hole, lies
///   outside the cage or inside another hole
/// @throws Error(InvalidArgument) for options out of range, or a size bound asking for more than
///   kMaxRequestedCells triangles
/// @throws Error(SizeMismatch | NonFinite) for Steiner points or holes that are not #S by 2 finite
/// @warning Features much smaller than the size bound (narrow gaps, short edges, Steiner points
///   near the boundary or near each other) are resolved by local refinement: more triangles.
DomainMesh mesh_polygon(const Cage& cage2d, const PolygonMeshOptions& options = {},
  const ProgressCallback& progress = {});

/// Options of mesh_closed_surface (TetGen 1.5 switches in brackets).
struct SurfaceMeshOptions
{
  /// Maximum tetrahedron volume ('a'); > 0 overrides target_cells.
  double max_volume = 0.0;
  /// Used when max_volume <= 0 and target_cells > 0: max_volume = enclosed volume /
  /// target_cells. Every tetrahedron is then at most that large, so there are at least
  /// target_cells of them; TetGen makes 2 to 3 times as many on simple cages (cube: 3.0 x at
  /// 1000, 2.1 x at 100000) and more when the quality refinement along a detailed surface
  /// dominates (a 320-face sphere: 7.4 x at 1000, 2.4 x at 100000). 0 with max_volume <= 0:
  /// no volume bound (only the quality bound refines).
  int target_cells = 0;
  /// Radius-edge ratio bound ('q'): TetGen refines until the tetrahedra's circumradius /
  /// shortest edge is <= this. Holds for every tetrahedron without a vertex on the cage; TetGen
  /// 1.5 leaves a few tetrahedra touching the cage above it where refining them would encroach
  /// the boundary (none for the cube and octahedron, 0.7% of the U box's and 0.9% of a noisy
  /// icosphere's at 1.414, ratio up to 3.5). It does not bound slivers (TetGen's mesh
  /// optimisation reduces them). <= 0 disables refinement for quality; otherwise the range is
  /// [kMinRadiusEdgeRatio, kMaxRadiusEdgeRatio] = [1.1, 10]. TetGen may add at most
  /// max_added_vertices vertices; a bound it cannot meet within them throws
  /// Error(NotConverged) instead of running for minutes into gigabytes.
  double radius_edge_ratio = 1.414;
  /// The most vertices TetGen may add ('S'); 0: automatic, 20 x the expected number of
  /// tetrahedra (each added vertex makes about 6) + 100 per cage face + the Steiner points +
  /// 10^5, which the quality refinement of every test cage stays far below.
  Index max_added_vertices = 0;
  /// #S by 3 points to make mesh vertices; see DomainMesh::steiner_vertex. They are passed to
  /// TetGen as isolated vertices of the input (not with 'i', which crashed on some cages and
  /// dropped points under 'Y' in TetGen 1.5.0).
  Eigen::MatrixXd steiner_points;
  /// Keep the cage's triangles as the mesh's boundary faces ('Y'): no vertex is added on the
  /// cage, so the boundary faces are exactly the cage's faces. Quality refinement then cannot
  /// split boundary faces, so tetrahedra touching the cage may exceed the radius-edge bound.
  bool preserve_boundary = false;
  /// As in PolygonMeshOptions; range [1e-7, 0.1] (TetGen itself merges points closer than
  /// 1e-8 of the cage's bounding-box diagonal).
  double steiner_tolerance = 1e-6;
};

/// Smallest distance between non-adjacent features of a 3D cage that mesh_closed_surface
/// accepts, relative to the cage diameter. TetGen merges points closer than 1e-8 of the
/// bounding-box diagonal and then fails (TetGen 1.5.0 crashes rather than reporting it), so
/// cages whose vertices, edges or faces come closer than this are rejected before meshing.
constexpr double kMinSurfaceFeatureSize = 1e-7;

/// Tetrahedralizes the interior of the closed triangle surface @p cage3d with TetGen 1.5
/// (Si, "TetGen, a Delaunay-based quality tetrahedral mesh generator", ACM TOMS 41(2), 2015):
/// constrained Delaunay tetrahedralization of the surface ('p'), quality refinement ('q'),
/// a volume bound ('a'), boundary preservation ('Y'); always quiet ('Q') and zero-based ('z');
/// Steiner points are isolated vertices of TetGen's input. The cage is validated first (validate_cage), then checked for
/// features closer than kMinSurfaceFeatureSize.
///
/// Progress: validation 0-0.1, TetGen 0.1-0.9 (one step: TetGen cannot report progress nor be
/// interrupted), output 0.9-1. Cancelling (between steps) throws Error(Cancelled).
///
/// Not re-entrant inside TetGen: concurrent calls are serialised by a mutex.
///
/// @throws Error(InvalidCage | EmptyInput | NonFinite | SizeMismatch) from validate_cage, and
///   Error(InvalidCage) for a cage with two non-adjacent features (vertex, edge, face) closer
///   than kMinSurfaceFeatureSize x its diameter, naming them
/// @throws Error(InvalidArgument) for options out of range or a volume bound asking for more
///   than kMaxRequestedCells tetrahedra
/// @throws Error(SizeMismatch | NonFinite) for Steiner points that are not #S by 3 finite
/// @throws Error when TetGen itself fails (its error code and meaning in the message):
///   InvalidCage for its self-intersection / small-feature / close-facets errors (3, 4, 5),
///   Internal for the others; Error(Internal) also if TetGen's output breaks a guarantee above
/// @warning Thin parts of the cage (gaps much narrower than the cage) make the quality
///   refinement add many tetrahedra there (the mesh is graded by the local feature size).
///   Classifying the Steiner points costs O(#S x #F) (generalized winding numbers, parallel).
DomainMesh mesh_closed_surface(const Cage& cage3d, const SurfaceMeshOptions& options = {},
  const ProgressCallback& progress = {});

/// A DomainMesh for a given triangulation/tetrahedralization of @p cage's interior (e.g. read
/// from files): control_vertex as given, boundary_vertices = the vertices of the mesh's boundary
/// facets (edges used by one triangle, triangles used by one tetrahedron), boundary_weights =
/// the cage's hat functions there (cage_boundary_values, harmonic_coordinates.h).
/// @param V #V by dim, @param T #T by dim+1, @param control_vertex #C: the mesh vertex at each
///   cage vertex.
/// @param tolerance relative to the cage diameter: how far a boundary vertex may lie from the
///   cage, and a control vertex from its cage vertex.
/// @throws Error(SizeMismatch) for inconsistent shapes; Error(InvalidArgument) naming a
///   boundary vertex off the cage (2D holes are not supported here), a control vertex out of
///   range or not at its cage vertex, or an index out of range.
DomainMesh domain_mesh_from_simplices(const Cage& cage, const Eigen::MatrixXd& V,
  const Eigen::MatrixXi& T, const Eigen::VectorXi& control_vertex, double tolerance = 1e-9);

/// A DomainMesh for a given triangulation/tetrahedralization (V, T) of @p cage's interior whose
/// vertices include the cage's: each cage vertex is matched to the boundary vertex of the mesh
/// (boundary_vertices, fem_operators.h) at its coordinates, within 1e-6 times the cage's
/// diameter, then domain_mesh_from_simplices(cage, V, T, matches, 1e-6). The cage is not
/// validated here (validate_cage).
/// Progress: the matching 0-0.5, then 1 at the end; cancelling throws Error(Cancelled).
/// @param V #V by dim, @param T #T by dim+1, dim = cage.dimension()
/// @throws Error(InvalidArgument) when T's elements are not simplices of the cage's dimension
///   or V's dimension is not the cage's (saying what to give), naming the first cage vertex
///   that is not a boundary vertex of the mesh (with its distance to the nearest one), and the
///   errors of domain_mesh_from_simplices.
DomainMesh domain_mesh_for_cage(const Cage& cage, const Eigen::MatrixXd& V,
  const Eigen::MatrixXi& T, const ProgressCallback& progress = {});

} // namespace bary
