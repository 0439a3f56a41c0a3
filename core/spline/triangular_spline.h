#pragma once
/// @file triangular_spline.h
/// Triangular Bézier splines of degree d >= 5 over a 2D triangulation (Rodrigues, Stolfi,
/// Gomide, "Editing C1-continuous 2D spline deformations by constrained least squares", 2014,
/// §3): the global Bézier control net (one control point per nominal position, so control
/// points on shared edges and vertices are shared and the spline is C0 by construction), the
/// classification of control points (Table 1), the quadrilateral conditions of C1 continuity
/// on every interior edge (Eqs. 4-6), evaluation, and the non-degeneracy test of §3.4.
///
/// A SplineNet holds what does not depend on the control points' values (the domain, the
/// numbering, the conditions); a TriangularSpline is a net plus values: two columns for a
/// deformation phi: Omega -> R^2, one for a scalar spline sigma: Omega -> R (the 2.5D
/// deformation's top and bottom surfaces share the xy deformation's net).

#include "core/common/types.h"
#include "core/meshing/mesh_point_locator.h"
#include "core/spline/bezier_triangle.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace bary
{

/// Smallest spline degree: below 5 C1 splines on a triangulation cannot be edited locally (§3.3).
inline constexpr int kMinSplineDegree = 5;
/// Largest spline degree BaryLab accepts (91 control points per triangle).
inline constexpr int kMaxSplineDegree = 12;
/// The default degree (the paper's).
inline constexpr int kDefaultSplineDegree = 5;

/// Types of control points (Table 1 of the paper, by the nominal position in its triangle).
enum class ControlPointType
{
  Corner,      ///< a vertex of the triangulation (i = d, j = d or k = d)
  EdgeCorner,  ///< on an edge, next to a vertex (0 and 1 among the indices)
  Edge,        ///< on an edge, the others
  InnerCorner, ///< two indices equal to 1 (next to two edges at a vertex)
  InnerEdge,   ///< one index equal to 1, not an inner corner (next to one edge)
  Interior     ///< every index >= 2
};

/// Name of a type ("corner", "edge corner", ...).
const char* to_string(ControlPointType type) noexcept;

/// One quadrilateral condition (Eq. 6) across an interior edge PQ shared by triangles u
/// (opposite vertex u0) and v (opposite vertex v0), for t = 0 .. d - 1:
/// q^v_{1,d-1-t,t} = beta0 q^u_{1,d-1-t,t} + beta1 q^u_{0,d-t,t} + beta2 q^u_{0,d-1-t,t+1},
/// with (beta0, beta1, beta2) the barycentric coordinates of v0 in (u0, P, Q), written as
/// sum_k coefficient[k] value(point[k]) = 0.
struct QuadCondition
{
  /// Global control points: q^v_1 (coefficient -1), q^u_1 (beta0), the edge point on the P side
  /// (beta1), the edge point on the Q side (beta2).
  std::array<Index, 4> point{};
  std::array<double, 4> coefficient{};
  Index edge = -1; ///< the interior edge (SplineNet::edges() row)
  int t = 0;       ///< the row's position along the edge, from P
  /// Domain vertices u0, P, Q, v0 (the exact coefficients are computed from their coordinates).
  std::array<int, 4> vertex{};
};

/// The control net of splines of one degree over one triangulation.
///
/// The triangulation is validated: finite 2D vertices, triangles with indices in range, no
/// degenerate triangle (area at most 1e-12 of the bounding box's), every vertex in a triangle,
/// an edge in at most two triangles, every vertex's triangles one fan (a manifold, no bow tie),
/// the triangles around an interior vertex turning once around it (no folded domain), and all
/// triangles counter-clockwise (when all are clockwise they are reversed: T(:, 1) and T(:, 2)
/// swapped, and the net uses the reversed triangles).
///
/// Numbering of the global control points: the #V vertices first (point v = vertex v), then the
/// d - 1 points of each edge (edges() order, from its first to its second vertex), then the
/// (d - 1)(d - 2)/2 points inside each triangle (i, j, k >= 1, in row order).
class SplineNet
{
public:
  /// @param V #V by 2 vertices (a third column is accepted when it is all zero)
  /// @param T #T by 3 triangles
  /// @param degree range [kMinSplineDegree, kMaxSplineDegree]
  /// @throws Error(EmptyInput) for no triangle, Error(SizeMismatch) for wrong column counts,
  ///   Error(NonFinite), Error(InvalidArgument) for a degree out of range or an index out of
  ///   range, Error(InvalidCage) naming the first problem of the triangulation (degenerate
  ///   triangle, non-manifold edge or vertex, unused vertex, fold, mixed orientation)
  SplineNet(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, int degree = kDefaultSplineDegree);

  int degree() const noexcept { return d_; }
  const Eigen::MatrixXd& vertices() const noexcept { return V_; }   ///< #V by 2
  const Eigen::MatrixXi& triangles() const noexcept { return T_; }  ///< #T by 3, CCW
  Index num_vertices() const noexcept { return V_.rows(); }
  Index num_triangles() const noexcept { return T_.rows(); }
  /// Whether the given triangles were clockwise and were reversed.
  bool reversed() const noexcept { return reversed_; }
  /// #E by 2 edges (first vertex < second).
  const Eigen::MatrixXi& edges() const noexcept { return E_; }
  /// #E by 2 triangles on each edge's left and right (-1 on the border for the missing one).
  const Eigen::MatrixXi& edge_triangles() const noexcept { return ET_; }
  /// Mean edge length of the triangulation ("grid size").
  double mean_edge_length() const noexcept { return h_; }

  /// Number of global control points.
  Index num_points() const noexcept { return n_; }
  /// #T by bezier_count(d): the global control point of each local one (row order).
  const Eigen::MatrixXi& local_to_global() const noexcept { return L2G_; }
  /// The global control point of (i, j, k) in triangle @p t (k = d - i - j).
  Index point(Index t, int i, int j) const { return L2G_(t, bezier_index(d_, i, j)); }
  /// The control point @p step steps (1 .. d - 1) from edge @p e's first vertex.
  Index edge_point(Index e, int step) const { return V_.rows() + e * (d_ - 1) + step - 1; }
  /// #points by 2 nominal positions.
  const Eigen::MatrixXd& nominal() const noexcept { return nominal_; }
  ControlPointType type(Index p) const { return type_[static_cast<size_t>(p)]; }
  /// For corners, edge corners, inner corners and edge points two steps from a vertex (the
  /// points whose conditions tie them to a vertex, see SplineEditor): that vertex; else -1.
  int near_vertex(Index p) const { return near_vertex_[static_cast<size_t>(p)]; }
  /// The points whose near_vertex() is @p v: the vertex, its edge corners, the edge points two
  /// steps from it and its inner corners (the points of the C1 conditions t = 0, 1 at v).
  std::vector<Index> vertex_block(int v) const;
  /// A triangle containing control point @p p (the first in triangle order).
  Index triangle_of(Index p) const { return tri_of_[static_cast<size_t>(p)]; }

  /// The C1 conditions: d per interior edge, edges() order, t ascending.
  const std::vector<QuadCondition>& conditions() const noexcept { return conditions_; }
  /// The conditions control point @p p takes part in.
  std::vector<Index> conditions_of(Index p) const;
  /// Neighbours of @p p in the global Bézier net (the edges of every local net), increasing.
  std::vector<Index> net_neighbours(Index p) const;
  /// Graph distances in the global net from @p sources, up to @p max_distance (others: -1).
  std::vector<int> net_distances(const std::vector<Index>& sources, int max_distance) const;

  /// The containing triangle of a domain point and its barycentric coordinates.
  const MeshPointLocator& locator() const { return *locator_; }

  /// Barycentric coordinates of domain point @p x in triangle @p t.
  Eigen::Vector3d barycentric(Index t, const Eigen::Vector2d& x) const;

private:
  int d_ = 0;
  bool reversed_ = false;
  Eigen::MatrixXd V_;
  Eigen::MatrixXi T_, E_, ET_, L2G_;
  Eigen::MatrixXd nominal_;
  Index n_ = 0;
  double h_ = 0;
  std::vector<ControlPointType> type_;
  std::vector<int> near_vertex_;
  std::vector<Index> tri_of_;
  std::vector<QuadCondition> conditions_;
  std::vector<Index> cond_offset_, cond_index_; ///< CSR: point -> conditions
  std::vector<Index> nb_offset_, nb_index_;     ///< CSR: point -> net neighbours
  std::vector<Index> block_offset_, block_index_; ///< CSR: vertex -> vertex_block
  std::shared_ptr<MeshPointLocator> locator_;
};

/// Result of TriangularSpline::check_jacobian (§3.4).
struct JacobianReport
{
  /// Smallest Jacobian determinant found (at a corner of a subdivided piece: a value of the
  /// map's Jacobian determinant, not a bound).
  double min_jacobian = 0;
  Eigen::Vector2d min_point = Eigen::Vector2d::Zero(); ///< where (domain coordinates)
  /// The smallest Bézier coefficient of the determinant over the whole spline (a lower bound).
  double lower_bound = 0;
  /// Triangles proven positive (every Bézier coefficient of the determinant > 0 on every
  /// piece of the subdivision).
  Index positive = 0;
  /// Triangles where the determinant is <= 0 somewhere (the map folds or degenerates there),
  /// increasing, with a point of each where it is.
  std::vector<Index> folded;
  std::vector<Eigen::Vector2d> fold_points;
  /// Triangles neither proven positive nor found folded within the subdivision depth.
  std::vector<Index> undecided;
  bool positive_everywhere() const noexcept { return folded.empty() && undecided.empty(); }
};

/// C1 continuity measured on a spline (what the tests and the editor report).
struct ContinuityReport
{
  /// Largest |sum_k coefficient_k value(point_k)| over the quadrilateral conditions (units of the
  /// values).
  double max_condition_residual = 0;
  /// Largest jump of the gradient (Frobenius norm of the difference of the two pieces'
  /// Jacobians) across an interior edge, at d + 1 points along each.
  double max_gradient_jump = 0;
  Index conditions = 0;
};

/// A spline: a net and its control points' values.
class TriangularSpline
{
public:
  /// Values: #points by m (m = 2: a deformation, m = 1: a scalar spline).
  /// @throws Error(SizeMismatch) when values has not net->num_points() rows, Error(NonFinite)
  TriangularSpline(std::shared_ptr<const SplineNet> net, Eigen::MatrixXd values);

  /// The identity deformation (every control point at its nominal position).
  static TriangularSpline identity(std::shared_ptr<const SplineNet> net);
  /// A constant scalar spline.
  static TriangularSpline constant(std::shared_ptr<const SplineNet> net, double value);

  const SplineNet& net() const noexcept { return *net_; }
  const std::shared_ptr<const SplineNet>& net_ptr() const noexcept { return net_; }
  const Eigen::MatrixXd& values() const noexcept { return values_; }
  Eigen::MatrixXd& values() noexcept { return values_; }
  int dimension() const noexcept { return static_cast<int>(values_.cols()); }

  /// bezier_count(d) by m coefficients of triangle @p t.
  Eigen::MatrixXd piece(Index t) const;

  /// Value at a point of triangle @p t with barycentric coordinates @p b.
  Eigen::RowVectorXd evaluate(Index t, const Eigen::Vector3d& b) const;
  /// Jacobian (m by 2, derivatives along the domain's x and y) in triangle @p t.
  Eigen::MatrixXd jacobian(Index t, const Eigen::Vector3d& b) const;

  /// Where points lie in the domain: located once, evaluated many times.
  struct Locations
  {
    std::vector<Index> triangle;         ///< -1 outside
    std::vector<Eigen::Vector3d> barycentric;
    std::vector<Index> outside;          ///< ids of points outside the domain, increasing
  };
  /// Locates the points (#P by 2; a third column is ignored).
  /// @throws Error(NonFinite), Error(SizeMismatch) for fewer than 2 columns,
  ///   Error(PointsOutside) naming the count and the first one under OutsidePolicy::Error
  ///   (under Nearest the nearest point of the domain is used).
  Locations locate(const Points& P, OutsidePolicy policy = OutsidePolicy::Error) const;
  /// Values at located points (#P by m; NaN rows for points outside under OutsidePolicy::NaN).
  /// Parallel over points (OpenMP); the result does not depend on the thread count.
  Eigen::MatrixXd evaluate(const Locations& where) const;

  /// The quadrilateral conditions' residuals and the gradient jumps across interior edges.
  ContinuityReport continuity() const;

  /// Non-degeneracy of a deformation (m = 2, §3.4): the Jacobian determinant of each piece as
  /// a polynomial of degree 2(d - 1) in Bézier form; a piece whose coefficients are all > 0 is
  /// positive; otherwise it is subdivided into four (midpoints) up to @p max_depth levels, and a
  /// non-positive value at a corner of a sub-piece is a fold.
  /// @throws Error(InvalidArgument) for a scalar spline or max_depth outside [0, 12]
  JacobianReport check_jacobian(int max_depth = 6) const;

  /// The same spline with degree d + 1 (degree elevation of every piece; C1 is kept). Fails
  /// above kMaxSplineDegree.
  TriangularSpline elevated() const;

private:
  std::shared_ptr<const SplineNet> net_;
  Eigen::MatrixXd values_;
};

/// Where to sample every domain edge to draw the curved grid: @p samples + 1 points per edge
/// (edges() order, from its first vertex, evenly spaced), each located in a triangle of the edge
/// with exact barycentric coordinates (0 on the third corner): block e of the result is edge e.
TriangularSpline::Locations edge_sample_locations(const SplineNet& net, int samples);

} // namespace bary
