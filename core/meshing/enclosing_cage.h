#pragma once
/// @file enclosing_cage.h
/// Automatic cage generation: a coarse cage that strictly encloses a model (a triangle surface
/// in 3D; a triangle mesh or polygon in the plane in 2D), with about a requested number of
/// vertices, closed, manifold, free of self-intersections and accepted by validate_cage and by
/// the domain meshers (docs/cage-generation.md).
///
/// Method: an outer offset surface, then constrained decimation (after the enclosure
/// constraints of Sacht et al., "Nested Cages", SIGGRAPH Asia 2015, without their flow):
/// 1. Offset: the unsigned distance d to the model on a grid of cell side h = margin /
///    resolution (exact point-triangle distances within margin + h of the model); the grid
///    nodes with d >= margin reachable from the grid's border are "outside", every other node
///    "solid" (cavities and inner offset components are filled). The surface is the
///    boundary between the two, extracted by marching tetrahedra (3D: six tetrahedra per cube,
///    Freudenthal's subdivision; 2D: two triangles per square), its vertices on grid edges
///    (interpolated in d - margin, kept within 5-95% of the edge). It is a closed manifold
///    (the level set of a piecewise-linear function on a triangulation), and every point of it
///    lies in a cell with an outside node, within h sqrt(3) (2D: h sqrt(2)) of a node at
///    distance >= margin, so at distance >= margin - h sqrt(3) > 0 from the model: the
///    enclosure is strict by construction (resolution >= 2). A model point's cell has only solid
///    nodes, so it is inside.
/// 2. Decimation: greedy edge collapses in the order of the quadric error (Garland-Heckbert;
///    candidate positions: the quadric's optimum, the midpoint, either end), each accepted
///    only if the link condition holds (3D) or the polygon keeps >= 3 vertices (2D), no face
///    flips (normal turned by more than ~78 degrees) or becomes a sliver, and, exactly (CGAL's
///    predicates): no model triangle (or segment) meets the closed region swept by the collapse
///    (the cone from the new position over the old faces around the edge: it contains the region
///    between the old and the new surface and the new faces), and the new faces meet no other
///    cage face except along shared edges and vertices (a uniform grid of the cage faces, updated
///    per collapse). Since the old cage enclosed the model strictly, so does the new one.
///    Stops at the target number of vertices or when no collapse is valid (reported).
/// 3. Tightening: a few rounds moving each vertex toward its closest model point, to a
///    clearance (a fraction of the margin) from it, each move checked as a collapse is (the cone
///    from the new position over the vertex's faces meets no model element, no fold, no
///    self-intersection).
/// Deterministic (sequential, ties broken by vertex ids).

#include "core/common/cage.h"
#include "core/common/progress.h"
#include "core/common/types.h"

#include <string>

namespace bary
{

/// Options of enclosing_cage.
struct EnclosingCageOptions
{
  /// Target number of cage vertices: at least 4 (3D) or 3 (2D). Required (0 is refused).
  Index target_vertices = 0;
  /// Offset distance of the initial surface from the model, in model units; 0 (default) =
  /// margin_fraction x the model's bounding-box diagonal. Negative or NaN is refused.
  double margin = 0.0;
  /// The automatic margin as a fraction of the bounding-box diagonal, in (0, 1]. Default 0.05.
  double margin_fraction = 0.05;
  /// Grid cells per margin (cell side h = margin / resolution), in [2, 64]: finer grids follow
  /// the model more closely before decimation and cost more. Default 2.
  double resolution = 2.0;
  /// Tightening after decimation: rounds of moves of each cage vertex toward its closest model
  /// point, to clearance x margin from it (the step halved up to 4 times when a move fails a
  /// check; a move is checked as a collapse is). 0 = none; [0, 1000]. Default 4.
  int tighten_rounds = 4;
  /// The distance, in margins, that tightening leaves between a vertex and its closest model
  /// point, in [0, 1]. Default 0.25.
  double clearance = 0.25;
  /// Largest grid allowed (nodes); a larger one is refused with advice. Default 2^24.
  Index max_grid_nodes = Index(1) << 24;
};

/// What enclosing_cage returns.
struct EnclosingCageResult
{
  /// The cage: 3D, a closed triangle surface with outward normals; 2D, a counter-clockwise
  /// polygon (Cage conventions).
  Cage cage;
  double margin = 0.0;        ///< the offset distance used
  double cell_size = 0.0;     ///< grid cell side h
  Index grid_nodes = 0;       ///< nodes of the distance grid
  Index offset_vertices = 0;  ///< vertices of the offset surface before decimation
  Index offset_faces = 0;     ///< its triangles (3D) or edges (2D)
  Index collapses = 0;        ///< edge collapses done
  Index rejected = 0;         ///< collapse candidates refused by a check
  Index tighten_moves = 0;    ///< vertex moves made by the tightening rounds
  /// True when the cage has target_vertices vertices (or fewer, when the offset surface already
  /// had fewer: then no collapse is made); false when no valid collapse was left before.
  bool reached_target = false;
  std::string stop_reason; ///< "target reached", "no valid collapse left", ...
  /// Model volume (3D: closed, consistently oriented models; NaN otherwise) or area (2D:
  /// triangles' area, or the area a closed polygon bounds).
  double model_measure = 0.0;
  double cage_measure = 0.0;  ///< enclosed volume (3D) or area (2D) of the cage
  double measure_ratio = 0.0; ///< cage_measure / model_measure (NaN when the latter is)
  double max_distance = 0.0;  ///< largest distance from a cage vertex to the model
  double mean_distance = 0.0; ///< mean distance from the cage vertices to the model
  double diagonal = 0.0;      ///< the model's bounding-box diagonal
  double offset_seconds = 0.0;   ///< wall-clock seconds of step 1 (grid and surface)
  double seconds = 0.0;          ///< total wall-clock seconds
};

/// A cage strictly enclosing the model (V, F).
/// @param V #V by 3 (3D) or #V by 2 (2D) model vertex positions
/// @param F #F by 3 triangles (3D: a surface, closed or not: every triangle is enclosed; 2D: a
///   triangle mesh in the plane), or #F by 2 segments (2D only: a polygon or polylines)
/// @throws Error EmptyInput (no vertices or faces), NonFinite (a NaN or infinite coordinate,
///   named), SizeMismatch (wrong columns, an index out of range), InvalidArgument (target below
///   4 / 3, bad margin or resolution, a model with no extent, a grid over max_grid_nodes, an
///   offset surface of several components: parts farther apart than twice the margin),
///   Cancelled.
EnclosingCageResult enclosing_cage(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
  const EnclosingCageOptions& options, const ProgressCallback& progress = {});

} // namespace bary
