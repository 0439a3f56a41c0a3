#pragma once
/// @file landmark_decimation.h
/// Landmark vertices of a triangle surface by greedy halfedge-collapse decimation, as used to
/// pick the subset S of the Euclidean-embedding metric of Panozzo, Baran, Diamanti & Sorkine-
/// Hornung, "Weighted averages on surfaces", ACM TOG 32(4), 2013, §3.5: "decimating the mesh ...
/// [by] iteratively collaps[ing] the halfedge that changes the face normals least ... When a
/// user-specified number of points (we use 1000) is left, the decimation stops and these vertices
/// are used as S." Written for BaryLab (no OpenMesh); the rules below are this unit's.
///
/// **Collapse.** A halfedge collapse u -> v removes vertex u; v keeps its original position, so
/// every surviving vertex is an original vertex at its original place. The faces holding the
/// edge uv (two, or one on the boundary) disappear; the other faces around u get u replaced by v
/// (the "changed" faces).
///
/// **Normal cones.** Every face carries a circular cone of unit directions (axis, half-angle),
/// initially its own unit normal with half-angle 0; a degenerate face (twice its area at most
/// 1e-12 times its longest edge squared) has no normal and an empty cone. When u -> v is done,
/// each changed face f takes into its cone the cones of the removed faces that share an edge
/// with it (a removed face (u, v, w) shares uw with the changed face that, after the collapse,
/// covers the region the removed face covered) and its own new normal; merging two cones gives
/// the smallest circular cone that holds both. So a face's cone holds the normals of the
/// original faces it has absorbed and every normal the face has had. A removed face that shares
/// no edge with a changed face (its edge uw is on the boundary) leaves the surface and its cone
/// is dropped; the boundary term below measures that change.
///
/// **Cost** of u -> v, in radians: the largest of
/// - for each changed face f: the largest angle between f's new normal and a direction in f's
///   cone or in the cone of a removed face that shares an edge with f (the angle to the cone's
///   axis plus its half-angle, at most pi). Since f's cone holds f's current normal, this is at
///   least the turn of f's normal;
/// - for a collapse along the boundary (not in the paper, which does not treat boundaries): the
///   same angle between the direction of the new boundary edge and the direction cones of the
///   two boundary edges it replaces. Every boundary edge carries a cone of directions (initially
///   its own), merged in the same way, so that the boundary keeps its shape where it turns:
///   removing the corner of a flat grid costs pi/2, a vertex of a straight boundary 0.
///
/// The costs are computed from cosines and sines (no inverse trigonometry) and ordered by
/// sin(theta) up to pi/2, 2 - sin(theta) above; cost differences below about 1e-8 radians near
/// pi/2 do not order collapses (ties are then broken by ids, below).
///
/// The cheapest legal collapse is always done next: a priority queue holds the best collapse of
/// every vertex (by cost, then the shorter edge, then the kept vertex's id), with lazy
/// invalidation by per-vertex version counters, ordered by cost, then the collapsed edge's
/// length (shorter first), then the removed vertex's id, so the order does not depend on the
/// standard library. The length tie-break is BaryLab's (the paper names only the normal
/// criterion): on a flat region every collapse costs 0, and without it the region would lose
/// its vertices in id order, leaving one end bare of landmarks (measured on a flat 41 x 41
/// grid, 300 landmarks: the embedding's largest distance error was 0.79 that way). A collapse u -> v changes the cost of the collapses of v and of u's
/// neighbours only (the faces around any other vertex keep their vertices and cones); they are
/// evaluated again at once. A queued collapse of another vertex may become illegal (the link
/// condition): every collapse is evaluated again when it leaves the queue and done only if it is
/// still legal at the same cost.
///
/// **Legality.** u -> v is refused when
/// - the link condition fails: the vertices adjacent to both u and v must be exactly the
///   opposite vertices of the faces holding uv;
/// - u is on the boundary and uv is not a boundary edge (a boundary vertex moves only along its
///   boundary, into the next or previous boundary vertex); an interior u may collapse into any
///   neighbour, a boundary one included;
/// - a changed face would have zero area (twice its area at most 1e-12 times its longest edge
///   squared) or its normal would turn by 90 degrees or more (a fold);
/// - u's connected component has 4 vertices or fewer (a tetrahedron, or what is left of an
///   open component, is never reduced further; smaller components are kept as they are).
///
/// With these rules the mesh stays an edge- and vertex-manifold triangle mesh with the same
/// connected components, genus and boundary loops as the input (each boundary loop keeps its
/// vertices' order, some of them removed).
///
/// **Orientation.** Normals need a consistent orientation: the faces of each connected
/// component are oriented like its lowest-numbered face before decimating (an input that is
/// not orientable, e.g. one holding a Moebius strip, is refused). The output faces are turned
/// back: each has the orientation of the input face it descends from. A consistently oriented
/// input gives the same landmarks as any other orientation of its faces.
///
/// **Stopping.** Decimation stops when target_vertices vertices remain, or earlier when no
/// legal collapse is left (every component at 4 vertices or fewer, or every remaining collapse
/// would fold or flatten a face): then more than target_vertices landmarks are returned; compare
/// landmarks.size() with the target.
///
/// **Cost of the computation**: O(#V log #V) for meshes of bounded valence; one thread. Measured
/// at -O2 on a 2-core virtual machine: 3596 -> 1000 vertices (3holes) in 0.03-0.05 s, a
/// 100002-vertex icosphere -> 1000 in 1.2-1.5 s (up to 2 s while the machine was shared).
/// The result depends only on the input (the same on every run and thread count); across
/// platforms only through the last bits of std::cos, std::sin and std::atan2, which enter the
/// merged cones.

#include "core/common/progress.h"
#include "core/common/types.h"

#include <Eigen/Core>

#include <vector>

namespace bary
{

/// Options of decimation_landmarks().
struct LandmarkDecimationOptions
{
  /// Stop when this many vertices remain; range [4, #V]. Default 1000 (Panozzo et al. §3.5).
  Index target_vertices = 1000;
};

/// What decimation_landmarks() returns.
struct LandmarkDecimation
{
  /// The surviving original vertex ids, ascending: target_vertices of them, or more when the
  /// decimation ran out of legal collapses (see the file comment).
  std::vector<int> landmarks;
  /// The decimated mesh's triangles, in original vertex ids (so every id is a landmark), each
  /// oriented as the input face it descends from, in the order of those input faces.
  Eigen::MatrixXi faces;
  /// Halfedge collapses performed (#V - landmarks.size()).
  Index collapses = 0;
  /// The largest cost (radians, see the file comment) of a collapse that was done; 0 when none.
  double max_normal_deviation = 0;
};

/// Decimates the triangle surface (V, F) by greedy halfedge collapses of least normal change
/// until options.target_vertices vertices remain, and returns the surviving vertices.
///
/// The input must be an orientable, edge- and vertex-manifold triangle mesh in which every
/// vertex belongs to a face; its faces need not be consistently oriented (see the file comment)
/// and degenerate (zero-area) faces are accepted.
///
/// @param V #V by 3 vertex positions
/// @param F #F by 3 triangles (indices into V)
/// @param progress called about once per percent with the fraction done (0 to 0.1 while every
///   vertex's best collapse is computed, 0.1 to 1 over the collapses); return false to stop
/// @throws Error(EmptyInput) when V or F has no rows; Error(SizeMismatch) when V or F does not
///   have 3 columns; Error(InvalidArgument) for target_vertices outside [4, #V], a vertex index
///   outside [0, #V), a face that repeats a vertex, a vertex in no face, an edge in three or more
///   faces, a part that cannot be oriented (a Moebius strip) or a vertex whose faces form more
///   than one fan (each named, an edge for the orientation); Error(NonFinite) for a
///   non-finite coordinate (the vertex named); Error(Cancelled) when @p progress returns false.
LandmarkDecimation decimation_landmarks(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
  const LandmarkDecimationOptions& options = {}, const ProgressCallback& progress = {});

} // namespace bary
