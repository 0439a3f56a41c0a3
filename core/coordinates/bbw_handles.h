#pragma once
/// @file bbw_handles.h
/// Mixed handles of bounded biharmonic weights (Jacobson et al. 2011, §2: "a handle can be a
/// single point, a region, a skeleton bone or a vertex of a cage"; Figs. 1, 10, 11, 14) turned
/// into one BBWHandles for one solve, and the shape-preservation brush (§3.3) given per vertex.
///
/// A Skeleton (skeleton.h) carries point handles, bones, cage faces (closed or open) and
/// regions over one set of joints; mesh vertex sets can be added as further regions. The
/// weights' columns are, in this order: the point handles (P's order), the bones (BE's order),
/// the cage vertices (Skeleton::cage_joints(), ascending joint index), the skeleton's regions
/// (their order), then the vertex regions (their order).
///
/// Boundary conditions (Eq. 3-4) at the mesh vertices, with an absolute tolerance tol (default
/// 1e-6 x the mesh's bounding-box diagonal):
/// - point handles and bones: handles_from_skeleton (libigl's rule; joints shared by bones get
///   1/k each);
/// - cage faces: every mesh vertex within tol of a cage face (a segment, or a triangle in 3D)
///   gets the face's linear hat functions at its closest point on the face (Eq. 4), so a cage
///   vertex's own mesh vertex gets 1, and faces or parts of faces outside the domain fix
///   nothing (an open or partial cage, Fig. 14);
/// - a region (a closed polygon in 2D, a closed triangle surface in 3D): every mesh vertex
///   inside (generalized winding number >= 1/2 in magnitude) or within tol of its boundary gets
///   1 for the region and 0 for every other handle; a vertex region: its listed vertices.
/// Handles must be disjoint (§2): a mesh vertex fixed by two different kinds of handle, or by
/// two regions, is an error (validate_skeleton checks the joints; this checks the mesh
/// vertices).
///
/// @sa bbw.h (BBWHandles, bbw_boundary_conditions, BoundedBiharmonicWeights)

#include "core/coordinates/bbw.h"
#include "core/deformation/skeleton.h"

#include <vector>

namespace bary
{

/// The handles of @p skeleton (any mix of point handles, bones, cage faces and regions) plus
/// the mesh vertex sets @p vertex_regions as boundary conditions on the mesh vertices @p V
/// (see the file comment for the column order and the rules).
/// @param V #V by dim mesh vertices (dim = the skeleton's dimension)
/// @param skeleton the handles; may hold no handle (then C may be empty) when vertex_regions is
///   not empty
/// @param vertex_regions lists of mesh vertex indices, each a region handle
/// @param tolerance absolute distance; <= 0 selects 1e-6 times V's bounding-box diagonal
/// @throws Error(EmptyInput) for no handle at all, an empty vertex region, or a mesh with no
///   vertex; the errors of validate_skeleton and handles_from_skeleton; Error(SizeMismatch)
///   when the skeleton and V differ in dimension; Error(InvalidArgument) naming a cage vertex
///   none of whose faces touches a mesh vertex, a region that holds no mesh vertex, a vertex
///   region index outside [0, #V), or a mesh vertex claimed by two handles of different kinds
///   or by two regions (naming both).
BBWHandles mixed_bbw_handles(const Eigen::MatrixXd& V, const Skeleton& skeleton,
  const std::vector<std::vector<int>>& vertex_regions = {}, double tolerance = -1.0);

/// The per-element brush BBWOptions::shape_preservation from a brush painted per vertex: the
/// mean of the element's vertex values, so that Eq. 9's per-element term rho_t vol_t is the
/// exact integral of the piecewise-linear brush over the element (the gradient of w is constant
/// there).
/// @param T #T by 3 or 4 elements; @param rho #V values, finite and >= 0
/// @param vertex_count #V
/// @throws Error(SizeMismatch) when rho does not have #V entries; Error(NonFinite) naming a
///   NaN / infinite entry; Error(InvalidArgument) naming a negative entry or an element index
///   outside [0, #V).
Eigen::VectorXd shape_preservation_per_element(
  const Eigen::MatrixXi& T, const Eigen::VectorXd& rho, Index vertex_count);

} // namespace bary
