#pragma once
/// @file correspondence.h
/// A map between two surfaces from corresponding anchors (Panozzo et al., "Weighted averages on
/// surfaces", ACM TOG 32(4), 2013, §4.3): a point of the target surface gets its weights with
/// respect to the target's anchors (the inverse problem), and its image is the weighted average
/// of the source's anchors with those weights (the forward problem on the source). Used to
/// transfer point data (texture coordinates, skinning weights, any array) from the source to the
/// target and to morph one into the other.
///
/// §4.4: a target point whose round trip on the target does not return is not a weighted average
/// of the target's anchors, and a forward problem on the source may fail: those points are
/// **undefined** (no image), never mapped silently.
///
/// Distortion (per target triangle whose three corners are defined): the triangle's affine map
/// onto the triangle of its corners' images has singular values G >= g (in the triangles' own
/// planes); BaryLab reports the scale-invariant symmetric stretch
/// sigma = sqrt(((G^2 + g^2) / 2) ((1/G^2 + 1/g^2) / 2)) >= 1, the product of the L2 stretches
/// of the map and of its inverse (Sander et al. 2001; Schreiner et al. 2004 symmetrise the same
/// way), 1 exactly for a similarity; and whether the image triangle is **flipped**: its normal
/// points against the source surface's normal there (the normal of the source triangle holding
/// the image of its centroid), counted against the orientation most triangles keep (a
/// mirror-image anchor set flips every triangle consistently, which the paper's Fig. 12 shows is
/// a valid map).

#include "core/surface/weighted_averages.h"

#include <vector>

namespace bary
{

/// Options of map_surface_points.
struct CorrespondenceOptions
{
  InverseOptions inverse;  ///< the inverse problems on the target
  ForwardOptions forward;  ///< the forward problems (round trip on the target, image on the source)
  /// Round-trip tolerance on the target, relative to its mean edge length (range (0, 1e6]).
  double round_trip_tolerance = kDefaultRoundTripTolerance;
};

/// The images of target points on the source.
struct SurfaceMap
{
  std::vector<SurfacePoint> image;  ///< per target point: its point on the source (face -1: undefined)
  std::vector<char> defined;        ///< per target point: 1 when it has an image
  std::vector<double> round_trip_error; ///< per target point: the round trip's error on the target (NaN: failed)
  Index undefined = 0;              ///< target points without an image
  Index not_returned = 0;           ///< of those, the ones whose round trip did not return
  Index source_failures = 0;        ///< of those, the ones whose forward problem on the source failed
  DenseWeights weights;             ///< #points by #anchors: the target points' weights
};

/// Maps @p target_points to the source. The anchor lists correspond (anchor i of the target is
/// anchor i of the source).
/// @throws Error(SizeMismatch) when the anchor lists differ in length; the errors of inverse()
///   and forward() (anchors or points not on their surfaces, options out of range).
SurfaceMap map_surface_points(const WeightedAverages& target,
  const std::vector<SurfacePoint>& target_anchors, const std::vector<SurfacePoint>& target_points,
  const WeightedAverages& source, const std::vector<SurfacePoint>& source_anchors,
  const CorrespondenceOptions& options = {}, const ProgressCallback& progress = {});

/// Distortion of a map of the target's vertices.
struct MapDistortion
{
  Eigen::VectorXd stretch;    ///< per target triangle: sigma (NaN where a corner is undefined)
  std::vector<char> flipped;  ///< per target triangle: 1 when its image is flipped
  Index measured = 0;         ///< triangles with all corners defined
  Index flipped_count = 0;
  double flipped_area_fraction = 0; ///< their share of the measured triangles' (target) area
  double stretch_all = 0;     ///< area-weighted RMS of sigma over the measured triangles
  double stretch_best95 = 0;  ///< the same over the 95% of them (by count) with the smallest sigma
};

/// The distortion of the map of the target's vertices @p vertex_map (from map_surface_points with
/// the target's vertices as points, in vertex order) onto @p source.
/// @throws Error(SizeMismatch) when the map does not have one entry per target vertex.
MapDistortion map_distortion(
  const SurfaceMesh& target, const SurfaceMesh& source, const SurfaceMap& vertex_map);

} // namespace bary
