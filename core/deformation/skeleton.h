#pragma once
/// @file skeleton.h
/// Skeletons as handles of bounded biharmonic weights (Jacobson et al. 2011, §3.1) and of
/// linear blend skinning: joints C, point handles P (joints on no bone) and bones BE (pairs of
/// joints). Handle order is libigl's: the point handles first (in P's order), then the bones (in
/// BE's order). Also what a skeleton needs at pose time: the parent of every bone, forward
/// kinematics of per-bone rotations (libigl's .dmat poses), and transforms from moved joints.
///
/// @sa bbw.h (handles_from_skeleton, BBWHandles), linear_blend_skinning.h

#include "core/deformation/linear_blend_skinning.h"
#include "core/common/types.h"

#include <Eigen/Geometry>

#include <vector>

namespace bary
{

/// Joints, point handles and bones, and (mixed handles, paper §2 and Figs. 1, 10, 11, 14) cage
/// faces and regions over the same joints. Handles are numbered (the weights' columns): the
/// point handles (in P's order), the bones (in BE's order), the cage vertices (the joints used
/// by CF, in ascending joint order: cage_joints()), then the regions (in their order). With
/// CF and regions empty this is libigl's order.
struct Skeleton
{
  Eigen::MatrixXd C; ///< #C by dim (2 or 3) joint positions
  Eigen::VectorXi P; ///< #P indices into C: the point handles
  Eigen::MatrixXi BE; ///< #B by 2 indices into C: the bones, (tail, head)
  /// #F by 2 (segments, 2D or 3D) or #F by 3 (triangles, 3D) indices into C: the faces of a
  /// cage, closed or open ("a collection of simplices", §2). Every joint they use is a cage
  /// vertex handle, and the weights are linear on every face (Eq. 4). Empty: no cage.
  Eigen::MatrixXi CF;
  /// Region handles: each a closed polygon (2D: #E by 2 edges, indices into C) or a closed
  /// triangle surface (3D: #F by 3); every domain point inside or on it moves with the region
  /// (weight 1 for it, 0 for the others: Eq. 3 on a region H_j).
  std::vector<Eigen::MatrixXi> regions;

  int dimension() const noexcept { return static_cast<int>(C.cols()); }
  /// The joints of the cage vertex handles: those used by CF, ascending.
  Eigen::VectorXi cage_joints() const;
  /// #P + #B + #cage_joints() + #regions: the number of handles (weights columns).
  Index handle_count() const;
};

/// Checks a skeleton: 2D or 3D finite joints, indices inside C, no zero-length bone, at least one
/// handle, no joint listed twice in P; cage faces and regions of the right shape (segments or,
/// in 3D, triangles; regions: edges in 2D, triangles in 3D), not degenerate, and disjoint from
/// the other handles (a cage vertex that is a point handle or a bone's joint, or a region
/// corner that is any other handle's joint, overlaps).
/// @throws Error(EmptyInput) for no handle or an empty region; Error(SizeMismatch) for C not 2
///   or 3 columns, BE not #B by 2, CF or a region with the wrong number of columns;
///   Error(NonFinite) naming a joint with NaN / infinity; Error(InvalidArgument) naming a
///   point handle, bone, cage face or region with an index outside [0, #C), a bone from a joint
///   to itself or of zero length, a point handle listed twice, a degenerate cage face or region
///   face, a joint shared by two kinds of handle.
void validate_skeleton(const Skeleton& skeleton);

/// Points along the skeleton to insert into a domain mesh (Steiner points) so that the mesh
/// holds the handles as vertices (BBW fixes the mesh vertices on a handle, §3.1; "we sample
/// vertices on all provided skeleton bones and cage faces", §3.4): every joint used by a
/// handle (once), then for each bone the interior samples splitting it into pieces no longer
/// than @p spacing (the bone's end points are the joints), then the same along every cage
/// face and region face (segments: as bones; triangles: a barycentric grid with that many
/// pieces per edge, its interior and edge points, each edge once per face).
/// @param spacing > 0, in the units of C
/// @throws the errors of validate_skeleton; Error(InvalidArgument) for spacing <= 0 or a
///   spacing that asks for more than 1e7 samples.
Eigen::MatrixXd skeleton_samples(const Skeleton& skeleton, double spacing);

/// The spacing of bone samples about one mesh cell apart, so that a mesh whose cells measure
/// @p cell_measure (area in 2D, volume in 3D) resolves the bones: the edge length of an
/// equilateral triangle of that area, sqrt(4 c / sqrt 3) (dim 2), or of a regular tetrahedron
/// of that volume, cbrt(6 sqrt 2 c) (dim 3).
/// A cell_measure that is not finite and > 0 gives a spacing (NaN, 0 or infinite) that
/// skeleton_samples rejects.
/// @throws Error(InvalidArgument) when dim is not 2 or 3.
double bone_sample_spacing(int dim, double cell_measure);

/// The parent of every bone (libigl's directed_edge_parents): bone b's parent is a bone whose
/// head BE(p, 1) is b's tail BE(b, 0), the first such in BE's order; -1 for a root.
/// @throws Error(SizeMismatch) for BE not #B by 2; Error(InvalidArgument) when the parents form a
///   cycle (naming a bone on it).
Eigen::VectorXi bone_parents(const Eigen::MatrixXi& BE);

/// Forward kinematics of relative bone rotations (libigl's forward_kinematics, as its BBW
/// tutorial poses the hand): a root bone b rotates by @p rotations[b] about its tail; a child
/// rotates by its parent's absolute rotation times its own, about its own tail carried along by
/// the parent, so joints shared by a parent and child stay together. Returns one transform per
/// bone (3 by 4, [R | t]); point handles get none (this is for bones only).
/// @param skeleton 3D joints and bones (point handles are ignored)
/// @param rotations #B unit quaternions (normalized here), relative to the parent
/// @throws the errors of validate_skeleton and bone_parents; Error(SizeMismatch) when the
///   skeleton is not 3D or rotations has not #B entries; Error(NonFinite) / (InvalidArgument) for
///   a NaN or zero quaternion (named).
AffineTransforms forward_kinematics(
  const Skeleton& skeleton, const std::vector<Eigen::Quaterniond>& rotations);

/// Transforms of every handle (Skeleton's handle order) from moved joints: a bone gets the
/// smallest rotation taking its rest direction to its posed direction, and the translation
/// that maps its rest tail to its posed tail (its length change is ignored: skinning is rigid
/// per bone); point handles get their rotations from @p pseudo_edges between point handles
/// (indices into P, transforms_from_pseudo_edges) and translations moving them to their posed
/// joints; a cage vertex gets the translation by its displacement (A = I: the cage deformation
/// x' = x + sum_j w_j (c'_j - c_j)); a region gets the rigid motion that best maps its rest
/// joints to their posed positions in the least-squares sense (Kabsch: rotation about the
/// joints' centroid, translation of the centroid).
/// @param posed_C #C by dim posed joint positions
/// @throws the errors of validate_skeleton and transforms_from_pseudo_edges; Error(SizeMismatch)
///   when posed_C's shape differs from C's; Error(InvalidArgument) naming a bone of zero length
///   when posed.
AffineTransforms transforms_from_joints(const Skeleton& skeleton, const Eigen::MatrixXd& posed_C,
  const Eigen::MatrixXi& pseudo_edges = Eigen::MatrixXi());

} // namespace bary
