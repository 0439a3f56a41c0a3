#pragma once
/// @file fem_operators.h
/// Linear (P1) finite element operators on simplicial meshes: element volumes, the stiffness
/// (cotangent) matrix, the mass matrix and the per-element gradient.
///
/// A mesh is given by its vertices V and elements T:
/// - triangles: T is #T by 3, V is #V by 2 (planar) or #V by 3 (a surface in space);
/// - tetrahedra: T is #T by 4, V is #V by 3.
///
/// On each element the hat functions phi_i are the barycentric coordinates lambda_i, so their
/// gradients are constant. With J = [p1 - p0, ..., pd - p0] (dim by d, d = T.cols() - 1) the
/// gradients of lambda_1..lambda_d are the columns of J (J^T J)^-1 and
/// grad lambda_0 = -sum_{i>0} grad lambda_i. For a surface triangle (dim 3, d 2) this uses only
/// the metric J^T J of the triangle, i.e. the intrinsic formula: the stiffness entries are the
/// cotangent weights K_ij = -1/2 (cot alpha_ij + cot beta_ij) of Pinkall & Polthier 1993
/// (Eq. 5 of Meyer et al., "Discrete differential-geometry operators for triangulated
/// 2-manifolds", 2003), whichever embedding the surface has.
///
/// Every function validates the mesh first:
/// @throws Error(EmptyInput) when T has no rows (no elements);
/// @throws Error(SizeMismatch) when T does not have 3 or 4 columns, V does not have 2 or 3
///   columns, or tetrahedra are given with 2D vertices;
/// @throws Error(InvalidArgument) naming the element when an index is outside [0, #V) or when an
///   element is degenerate (volume <= 64 eps h^d, h its longest edge, d its dimension: collinear
///   or coplanar vertices, a repeated vertex);
/// @throws Error(NonFinite) naming the vertex when a coordinate is NaN or infinite.
///
/// Vertices that no element references are allowed; their rows and columns in K and M are zero
/// (so K restricted to the free vertices is singular unless such vertices are fixed).
/// Orientation does not matter: every quantity uses unsigned volumes.

#include "core/common/types.h"

#include <vector>

namespace bary
{

/// Unsigned area (triangles) or volume (tetrahedra) of every element, #T by 1:
/// |det J| / d! with J as above, and sqrt(det(J^T J)) / 2 for surface triangles.
/// @throws Error as listed in the file comment.
Eigen::VectorXd simplex_volumes(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T);

/// Stiffness matrix, #V by #V: K_ij = sum over elements of vol_t grad phi_i . grad phi_j, i.e.
/// the integral of grad phi_i . grad phi_j. Symmetric positive semidefinite, rows sum to zero
/// (the diagonal is set to minus the sum of the off-diagonal entries of its row, so constants
/// are annihilated up to the rounding of that sum). Equals minus libigl's cotmatrix; for
/// triangles K_ij = -1/2 (cot alpha_ij + cot beta_ij).
/// @throws Error as listed in the file comment.
Eigen::SparseMatrix<double> stiffness_matrix(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T);

/// Mass matrix variants.
enum class MassMatrixType
{
  /// Lumped, diagonal: vertex i gets 1/3 (triangles) or 1/4 (tetrahedra) of the volumes of its
  /// incident elements. Positive on every referenced vertex. Cheap to invert.
  Barycentric,
  /// Consistent P1 mass matrix, M_ij = integral of phi_i phi_j: on an element of volume vol
  /// and dimension d, vol (1 + delta_ij) d! / (d + 2)!, i.e. vol/12 (2 on the diagonal, 1 off)
  /// for triangles and vol/20 (2 on the diagonal, 1 off) for tetrahedra. Symmetric positive
  /// definite on the referenced vertices; f^T M f is exactly the integral of f^2 for a P1 f.
  Full,
  /// Lumped, diagonal: the Voronoi area / volume of each vertex (the lumping of Jacobson et al.
  /// 2011, §3.4), split per element and summed.
  /// - Triangles (planar or surface): the "mixed" area of Meyer et al. 2003 (Fig. 4): in a
  ///   non-obtuse triangle (right angles included) vertex i gets its circumcentric (Voronoi)
  ///   part, (|e_ij|^2 cot(angle k) + |e_ik|^2 cot(angle j)) / 8; in an obtuse triangle the
  ///   obtuse vertex gets half the area and the others a quarter each, because there the
  ///   circumcentre lies outside the triangle and the circumcentric part of a vertex would be
  ///   negative. On a Delaunay mesh of non-obtuse triangles this is exactly the area of each
  ///   vertex's Voronoi cell clipped to the domain; it is libigl's MASSMATRIX_TYPE_VORONOI.
  /// - Tetrahedra: vertex i gets the volume of the part of each tetrahedron that is nearer to
  ///   it than to the tetrahedron's other three vertices (the tetrahedron clipped by the three
  ///   bisector planes). When the tetrahedron contains its circumcentre and its faces contain
  ///   theirs (well-centred; right angles included) this is exactly its circumcentric-dual
  ///   part; otherwise (circumcentre outside, where the circumcentric part can be negative) it
  ///   is the positive closest-vertex part, the natural extension.
  /// Positive on every referenced vertex; the entries of each element sum to its volume, so M
  /// sums to the mesh's area / volume.
  Voronoi
};

/// Mass matrix, #V by #V, of the given @p type (default Barycentric). Every type sums to the
/// total area / volume of the mesh.
/// @throws Error as listed in the file comment.
Eigen::SparseMatrix<double> mass_matrix(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T,
  MassMatrixType type = MassMatrixType::Barycentric);

/// Gradient operator, (#T * dim) by #V with dim = V.cols(): for a P1 function with vertex
/// values f (#V by 1), (G f)(t * dim + k) is the k-th component of its (constant) gradient on
/// element t. For surface triangles the gradient lies in the triangle's plane. It is exact on
/// linear functions, and G^T diag(vol repeated dim times) G = stiffness_matrix(V, T) (up to
/// rounding).
/// @throws Error as listed in the file comment.
Eigen::SparseMatrix<double> gradient_operator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T);

/// Connected component of each of the @p n vertices of the elements @p T (union-find; vertices
/// in no element are components of their own): ids 0 .. #components-1 in order of each
/// component's smallest vertex. Indices in T must be in [0, n) (not checked).
Eigen::VectorXi connected_components(Index n, const Eigen::MatrixXi& T);

/// The vertices on the boundary of the simplicial mesh @p T (#T by 3 triangles or #T by 4
/// tetrahedra; #T by 2 segments also work): the vertices of the facets (edges of triangles,
/// triangles of tetrahedra) used by exactly one element, ascending, without repeats.
/// @throws Error(SizeMismatch) when T has fewer than 2 or more than 4 columns.
std::vector<int> boundary_vertices(const Eigen::MatrixXi& T);

} // namespace bary
