#pragma once
/// @file phong_projection.h
/// Phong projection onto a triangle mesh embedded in R^D (Panozzo et al., "Weighted averages on
/// surfaces", ACM TOG 32(4), 2013, §3.2): a smooth stand-in for the Euclidean closest point,
/// which jumps at the mesh's medial axis.
///
/// - Tangent planes at the vertices (tangent_frames): the Loop limit tangent stencils applied
///   to the embedded one-ring, t1 = sum_i cos(2 pi i / k) p_i, t2 = sum_i sin(2 pi i / k) p_i,
///   made orthonormal. At a boundary vertex (fan p_0 .. p_{k-1}, p_0 and p_{k-1} on the
///   boundary) BaryLab uses t1 = p_{k-1} - p_0 (along the boundary) and
///   t2 = sum_{i=1}^{k-2} sin(i pi / (k - 1)) (p_i - v) (across it; p_0 + p_1 - 2 v when k = 2):
///   the paper does not say which boundary stencil it used. Every stencil is a combination of
///   one-ring edge vectors, so on a flat patch the tangent plane is the patch's plane.
/// - Per triangle (v1, v2, v3) with orthonormal frames T1, T2, T3 (2 by D): R_ij = Ort(T_j T_i^T)
///   (the closest orthogonal 2 by 2 matrix, by SVD = polar decomposition, Eq. 10), then the
///   in-plane rotations E12, E23, E31 of Eq. (12) by alternating Procrustes (each E in turn is
///   Ort of the sum it is compared with; the energy never increases; stopped when it changes by
///   less than 1e-15 relative or after 100 rounds), the edge interpolants
///   Psi_12 = xi1 E12 R12 T1 + xi2 E12 T2 + xi3 (E23 + E31 R31) T3 / 2 (and cyclically), and the
///   1/xi blend of Eq. (11). Multiplied out, Eq. (11) is
///   Psi = (xi1 xi2 Psi_12 + xi2 xi3 Psi_23 + xi3 xi1 Psi_31) / (xi1 xi2 + xi2 xi3 + xi3 xi1),
///   a cubic in xi over a quadratic with seven 2 by D coefficient matrices A1..A6, B. Each is a
///   2 by 2 matrix times a vertex frame (A1 = E12 R12 T1, A2 = E12 T2, ..., A6 = E31 T1) and
///   B = (A1 + ... + A6) / 2, so a triangle stores six 2 by 2 matrices and the frames are stored
///   once per vertex (detail/phong_kernel.h).
/// - Projection onto a triangle: Newton's method on Eqs. (7)-(8) from (1/3, 1/3, 1/3) (the
///   forward problem starts at the Euclidean projection onto the triangle's plane) in the two
///   free barycentric coordinates, on Psi r / s, which has the same roots in the triangle as
///   Eq. (7) and stays well scaled near its corners. Converged when the step is below 1e-13,
///   when the next step predicted from the last two (|step_k|^2 / |step_{k-1}|, Newton's
///   contraction) is below 1e-8, or when |Psi r / s| is below 1e-14 times the triangle's longest
///   edge. The prediction bounds the error left where convergence is only linear (near a
///   corner); where it is quadratic, as elsewhere, the error left is of the order of the
///   prediction's square: on the benchmark meshes forward(inverse(x)) returns within 3e-10 mean
///   edge lengths. Two or three iterations from the Euclidean start. Rejected when it does not
///   converge in 30 steps, when it converges to a point outside the triangle (the step halved
///   and the iterate outside by more than twice the step) or when Eq. (9) fails (a coordinate
///   below -1e-9; coordinates in [-1e-9, 0) are set to 0).
///   Per query and triangle the R^D work is eight dot products (the three corners' frames and
///   the triangle's two edges with the target minus a corner); Newton's steps are then 2 by 2
///   arithmetic on twelve residual rows.
/// - The kernels run in an AVX2 + FMA instantiation where the CPU has both and in a portable one
///   otherwise (detail/simd.h); they agree to rounding (1e-12).

#include "core/common/types.h"
#include "core/detail/simd.h"
#include "core/surface/surface_mesh.h"

#include <vector>

namespace bary
{

/// Orthonormal tangent frames of the embedded mesh: #V by 2D, row v holds the two basis vectors
/// of vertex v's tangent plane (first D entries, then the other D). See the file comment.
/// @param mesh the surface's topology (its one-rings in fan order)
/// @param E #V by D embedded vertices (D >= 2)
/// @throws Error(SizeMismatch) when E does not have #V rows or has fewer than 2 columns;
///   Error(InvalidArgument) naming a vertex whose embedded one-ring spans less than a plane.
Eigen::MatrixXd tangent_frames(const SurfaceMesh& mesh, const Eigen::MatrixXd& E);

/// Phong projection onto the embedded mesh, precomputed per triangle. Copies are independent;
/// const methods are thread-safe.
class PhongProjection
{
public:
  /// @param mesh the surface (topology, its F)
  /// @param E #V by D embedded vertices
  /// @throws the errors of tangent_frames; Error(NonFinite) for a non-finite embedding entry.
  PhongProjection(const SurfaceMesh& mesh, const Eigen::MatrixXd& E);

  /// Phong projection of @p y (D numbers) onto triangle @p f: true and its barycentric
  /// coordinates @p xi (>= 0, summing to 1) when Newton converges to a point of the triangle;
  /// false otherwise (xi then holds the last iterate). Never throws, no allocation.
  bool project(Index f, const double* y, Eigen::Vector3d& xi) const
  {
    return project(f, y, xi, Eigen::Vector3d::Constant(1.0 / 3));
  }
  /// The same with Newton started at @p start (barycentric coordinates of a point of the
  /// triangle, e.g. from euclidean_barycentric: fewer iterations than the centroid).
  bool project(Index f, const double* y, Eigen::Vector3d& xi, const Eigen::Vector3d& start) const;

  /// Barycentric coordinates (unclamped) of the Euclidean projection of @p y onto the affine
  /// plane of triangle @p f in R^D: the cheap guess (2 dot products) that orders and starts the
  /// search. No allocation.
  Eigen::Vector3d euclidean_barycentric(Index f, const double* y) const;

  /// The interpolated tangent basis Psi(xi) of triangle @p f (2 by D; its rows span the tangent
  /// plane, not orthonormal). At a corner (xi = e_k) the limit is a basis of that vertex's plane.
  Eigen::MatrixXd psi(Index f, const Eigen::Vector3d& xi) const;
  /// The same into @p out (2 D numbers, row-major: the two rows one after the other). No
  /// allocation.
  void psi(Index f, const Eigen::Vector3d& xi, double* out) const;

  /// Embedded position of a point of triangle f: sum_k xi_k E.row(F(f, k)).
  void position(Index f, const Eigen::Vector3d& xi, double* out) const;

  int dimension() const noexcept { return D_; }
  const Eigen::MatrixXd& frames() const noexcept { return frames_; }
  /// The triangles (#F by 3).
  const Eigen::MatrixXi& faces() const noexcept { return F_; }
  /// Row-major embedded vertices (#V by D).
  const double* vertex(Index v) const noexcept { return E_.data() + v * D_; }

private:
  friend class WeightedAverages; // its search inlines the projection kernel (detail/phong_kernel.h)
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const double* data(Index f) const noexcept { return data_.data() + f * kData; }
  /// Row-major frame of vertex v: t1 (D numbers), then t2.
  const double* frame(Index v) const noexcept { return frame_rows_.data() + v * 2 * D_; }
  static constexpr int kData = 56; ///< detail::kPhongData
  int D_ = 0;
  Eigen::MatrixXi F_;
  RowMatrix E_;              ///< #V by D
  Eigen::MatrixXd frames_;   ///< #V by 2D
  std::vector<double, detail::AlignedAllocator<double>> frame_rows_; ///< frames_, row-major
  /// Per triangle kData numbers (detail::PhongData): the rows C_r of A1..A6 (r = 2 m + i, the
  /// coefficient matrices of Psi other than B = (A1 + ... + A6) / 2) dotted with e1 = v1 - v3 and
  /// e2 = v2 - v3; the 2 by 2 matrices M_m with A_m = M_m T_k (by column); G^-1 of e1, e2 (the
  /// Euclidean projection onto the triangle's plane); the longest embedded edge.
  std::vector<double, detail::AlignedAllocator<double>> data_; ///< #F kData
};

} // namespace bary
