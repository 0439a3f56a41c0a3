#pragma once
// The pipeline builder of the surface family (weighted averages on surfaces, Panozzo et al.
// 2013): what the command line (barylab embed, barylab average) and the viewer assemble from
// the BaryLabSurface filters. No algorithm code here: settings, defaults and ranges are the
// core option structs' (core/surface/euclidean_embedding.h, weighted_averages.h).

#include "barylabPipeline.h"

#include "core/surface/euclidean_embedding.h"
#include "core/surface/correspondence.h"
#include "core/surface/remeshing.h"
#include "core/surface/weighted_averages.h"

#include "vtkSmartPointer.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

class vtkPointSet;
class vtkPolyData;

namespace barylab
{

/// A triangle surface read from @p path (.obj .off .ply .stl .vtp .vtk ...): it must be a
/// vtkPolyData (bary::Error(Io) otherwise); the surface itself is validated by the filters.
vtkSmartPointer<vtkPolyData> ReadSurface(const std::string& path);

/// Points on a surface from @p path: a data file (its points; cells ignored) or a text file
/// (.txt, .xyz, .csv-like whitespace text: x y z a line).
vtkSmartPointer<vtkPolyData> ReadSurfacePoints(const std::string& path);

/// Writes points as text, x y z a line (NaN rows written as "nan nan nan").
void WritePointsText(vtkPointSet* points, const std::string& path);

/// The embedding of @p surface (vtkBarySurfaceEmbedding): a shallow copy with the `Embedding`
/// array. @p summary (optional) receives its figures (landmarks, stress, SMACOF iterations,
/// quality, seconds per stage).
vtkSmartPointer<vtkPolyData> ComputeEmbedding(vtkPolyData* surface,
  const bary::EmbeddingOptions& options, const RunCallbacks& callbacks = {},
  nlohmann::json* summary = nullptr);

/// A shallow copy of @p surface with the embedding read from @p path (a text matrix: one line
/// per surface point in point order, D numbers; or a .vtp/.vtk/.vtu whose `Embedding` array is
/// taken). @throws bary::Error(SizeMismatch) when the rows are not the surface's points.
vtkSmartPointer<vtkPolyData> AttachEmbedding(vtkPolyData* surface, const std::string& path);

/// Writes the `Embedding` array of @p surface: a text matrix (.txt and any extension that is not
/// a data format) or the surface with its array (.vtp .vtu .vtk).
void WriteEmbedding(vtkPolyData* surface, const std::string& path);

/// Forward problems (vtkBaryWeightedAverage): one point per row of @p W.
vtkSmartPointer<vtkPolyData> WeightedAverage(vtkPolyData* surface, vtkPointSet* anchors,
  const bary::DenseWeights& W, const bary::ForwardOptions& options, double surface_tolerance,
  const RunCallbacks& callbacks = {}, nlohmann::json* summary = nullptr);

/// Inverse problems (vtkBarySurfaceWeights) with the round trip: @p points with `Weights`,
/// `FaceId`, `Barycentric`, `RoundTripError`, `Defined`.
/// @p anchor_uv (optional, #anchors by 2): the anchors' texture coordinates; the result then
/// has `TCoords` (a local parametrisation / decal, §4.2; NaN where not Defined).
vtkSmartPointer<vtkPointSet> SurfaceWeights(vtkPointSet* points, vtkPolyData* surface,
  vtkPointSet* anchors, const bary::InverseOptions& options, double surface_tolerance,
  double round_trip_tolerance, const RunCallbacks& callbacks = {},
  nlohmann::json* summary = nullptr, const Eigen::MatrixXd* anchor_uv = nullptr);

/// A cubic B-spline on the surface through forward problems (vtkBarySurfaceCurve): samples,
/// polylines and FaceId, Barycentric, Valid.
vtkSmartPointer<vtkPolyData> SurfaceCurve(vtkPolyData* surface, vtkPointSet* controls,
  int samples_per_segment, bool closed, double surface_tolerance, int threads,
  const RunCallbacks& callbacks = {}, nlohmann::json* summary = nullptr);

/// Semiregular remeshing from a coarse quad layout on the surface (vtkBarySurfaceRemesh).
vtkSmartPointer<vtkPolyData> Remesh(vtkPolyData* surface, vtkPolyData* coarse,
  const bary::RemeshOptions& options, double surface_tolerance, const RunCallbacks& callbacks = {},
  nlohmann::json* summary = nullptr);

/// The target with the source's point arrays transferred through corresponding anchors
/// (vtkBarySurfaceCorrespondence): transferred arrays, SourcePosition, SourceFaceId,
/// SourceBarycentric, RoundTripError, Defined; cell data Stretch, Flipped. @p arrays empty:
/// every point array of the source but the embedding.
vtkSmartPointer<vtkPolyData> Transfer(vtkPolyData* target, vtkPointSet* target_anchors,
  vtkPolyData* source, vtkPointSet* source_anchors, const std::vector<std::string>& arrays,
  const bary::CorrespondenceOptions& options, double surface_tolerance,
  const RunCallbacks& callbacks = {}, nlohmann::json* summary = nullptr);

/// A morph from the target (t = 0) to its image on the source (t = 1, SourcePosition of
/// @p transferred) in @p frames + 1 frames, linear in space; undefined points stay put. Written
/// with WriteTimeSeries; returns the .pvd path.
std::string WriteMorph(vtkPolyData* transferred, int frames, const std::string& output_dir,
  const std::string& prefix);

} // namespace barylab
