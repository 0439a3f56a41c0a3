#pragma once
/// @file remeshing.h
/// Semiregular remeshing on a surface by weighted averages (Panozzo et al., "Weighted averages
/// on surfaces", ACM TOG 32(4), 2013, §4.1, Fig. 7): a coarse quad mesh whose vertices lie on
/// the surface is split, each level, into four quads per quad (a new vertex at each edge's
/// midpoint, the weighted average of its two ends with weights 1/2, and one at each quad's
/// centre, the average of its four corners with weights 1/4), every new vertex found on the
/// surface by a forward problem; then steps of Laplacian smoothing on the surface move every
/// interior vertex to the (uniform) average of its neighbours, again by forward problems, each
/// starting where the vertex was. Vertices on the quad mesh's boundary stay put (BaryLab's
/// choice: the paper does not treat a boundary).
///
/// A vertex whose forward problem fails is marked invalid (never placed), and so is every vertex
/// a later level computes from it; smoothing leaves invalid vertices, and their neighbours, where
/// they are (as it does a vertex whose smoothing step fails).

#include "core/surface/weighted_averages.h"

#include <vector>

namespace bary
{

/// Largest number of subdivision levels (each multiplies the quads by 4).
inline constexpr int kMaxRemeshLevels = 8;

/// Options of semiregular_remesh.
struct RemeshOptions
{
  /// Subdivision levels (each multiplies the quads by 4), range [0, kMaxRemeshLevels]. Default 2.
  int levels = 2;
  /// Laplacian smoothing steps on the surface after the last level, range [0, 1000]. Default 5
  /// (the paper's Fig. 7).
  int smoothing_steps = 5;
  /// OpenMP threads (0 = OpenMP's default). Results do not depend on it. Default 0.
  int threads = 0;
};

/// The remeshed quad mesh.
struct QuadRemesh
{
  std::vector<SurfacePoint> points; ///< every vertex on the surface (face -1: invalid)
  Eigen::MatrixXi quads;            ///< #quads by 4, counter-clockwise as the coarse quads
  std::vector<char> valid;          ///< per vertex
  Index failures = 0;               ///< invalid vertices
};

/// Checks the options' ranges (as semiregular_remesh does first).
/// @throws Error(InvalidArgument) naming the option, its value and its range.
void validate_remesh_options(const RemeshOptions& options);

/// Remeshes the coarse quad mesh (@p coarse: its vertices on @p wa's surface; @p quads: #Q by 4
/// indices into them, every edge in at most two quads).
/// @throws Error(EmptyInput) for no quad; Error(SizeMismatch) when quads do not have 4 columns;
///   Error(InvalidArgument) naming an index out of range, a degenerate quad (a repeated index),
///   an edge in more than two quads, a coarse point that is not a point of the surface, or an
///   option out of range; Error(Cancelled).
QuadRemesh semiregular_remesh(const WeightedAverages& wa, const std::vector<SurfacePoint>& coarse,
  const Eigen::MatrixXi& quads, const RemeshOptions& options = {},
  const ProgressCallback& progress = {});

} // namespace bary
