#include "barylabSurfacePipeline.h"

#include "vtkBaryConversion.h"
#include "vtkBaryDataIO.h"
#include "vtkBarySurfaceCorrespondence.h"
#include "vtkBarySurfaceCurve.h"
#include "vtkBarySurfaceData.h"
#include "vtkBarySurfaceRemesh.h"
#include "vtkBarySurfaceEmbedding.h"
#include "vtkBarySurfaceWeights.h"
#include "vtkBaryWeightedAverage.h"

#include "core/common/error.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>

using bary::Error;
using bary::ErrorCode;
using nlohmann::json;

namespace barylab
{
namespace
{

bool is_data_extension(const std::string& path)
{
  const std::string ext = vtkBaryDataIO::Extension(path);
  return ext == ".vtp" || ext == ".vtu" || ext == ".vtk";
}

} // namespace

vtkSmartPointer<vtkPolyData> ReadSurface(const std::string& path)
{
  return vtkBaryDataIO::ReadPolyData(path);
}

vtkSmartPointer<vtkPolyData> ReadSurfacePoints(const std::string& path)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  if (vtkBaryDataIO::CanRead(path))
  {
    auto data = vtkBaryDataIO::Read(path);
    const Eigen::MatrixXd P = vtkBaryConversion::PointsToMatrix(data, 3);
    for (Eigen::Index i = 0; i < P.rows(); ++i)
      points->InsertNextPoint(P(i, 0), P(i, 1), P(i, 2));
  }
  else
  {
    const Eigen::MatrixXd P = vtkBaryDataIO::ReadMatrix(path);
    if (P.cols() != 3)
      throw Error(ErrorCode::Io, "'" + path + "' has " + std::to_string(P.cols()) +
          " numbers a line; points on a surface are written x y z, one a line");
    for (Eigen::Index i = 0; i < P.rows(); ++i)
      points->InsertNextPoint(P(i, 0), P(i, 1), P(i, 2));
  }
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->SetPoints(points);
  return result;
}

void WritePointsText(vtkPointSet* points, const std::string& path)
{
  Eigen::MatrixXd P(points->GetNumberOfPoints(), 3);
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
  {
    double x[3];
    points->GetPoint(i, x);
    P.row(i) << x[0], x[1], x[2];
  }
  vtkBaryDataIO::WriteMatrix(P, path);
}

vtkSmartPointer<vtkPolyData> ComputeEmbedding(vtkPolyData* surface,
  const bary::EmbeddingOptions& options, const RunCallbacks& callbacks, json* summary)
{
  vtkNew<vtkBarySurfaceEmbedding> embed;
  embed->SetInputData(surface);
  embed->SetDimension(options.dimension);
  embed->SetNumberOfLandmarks(options.landmarks);
  embed->SetLandmarkMethod(options.landmark_method == bary::LandmarkMethod::Decimation
      ? vtkBarySurfaceEmbedding::LANDMARKS_DECIMATION
      : vtkBarySurfaceEmbedding::LANDMARKS_FARTHEST_POINT);
  embed->SetStressTolerance(options.stress_tolerance);
  embed->SetMaximumIterations(options.max_iterations);
  embed->SetHeatTimeFactor(options.heat_time_factor);
  embed->SetQualitySources(options.quality_sources);
  embed->SetNumberOfThreads(options.threads);
  RunAlgorithm(embed, callbacks);
  vtkSmartPointer<vtkPolyData> result = embed->GetOutput();
  if (summary)
  {
    json& s = *summary;
    s["vertices"] = surface->GetNumberOfPoints();
    s["triangles"] = surface->GetNumberOfPolys();
    s["dimension"] = options.dimension;
    s["landmarks"] = result->GetFieldData()->GetArray("Landmarks")->GetNumberOfTuples();
    s["landmark_method"] =
      options.landmark_method == bary::LandmarkMethod::Decimation ? "decimation" : "farthest-point";
    s["stress"] = { { "classical_mds", embed->GetInitialStress() }, { "final", embed->GetStress() },
      { "smacof_iterations", embed->GetSMACOFIterations() },
      { "smacof_converged", embed->GetSMACOFConverged() } };
    s["quality"] = { { "pairs", embed->GetNumberOfQualityPairs() },
      { "mean_relative_error", embed->GetMeanRelativeError() },
      { "median_relative_error", embed->GetMedianRelativeError() },
      { "max_relative_error", embed->GetMaximumRelativeError() } };
    json stages = json::object();
    double total = 0;
    for (int i = 0; i < embed->GetNumberOfStages(); ++i)
    {
      stages[embed->GetStageName(i)] = embed->GetStageSeconds(i);
      total += embed->GetStageSeconds(i);
    }
    stages["total"] = total;
    s["seconds"] = stages;
  }
  return result;
}

vtkSmartPointer<vtkPolyData> AttachEmbedding(vtkPolyData* surface, const std::string& path)
{
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->ShallowCopy(surface);
  const std::string name = vtkBarySurfaceData::DefaultEmbeddingName();
  if (is_data_extension(path))
  {
    auto data = vtkBaryDataIO::Read(path);
    vtkDataArray* array = data->GetPointData()->GetArray(name.c_str());
    if (!array)
      throw Error(ErrorCode::Io, "'" + path + "' has no point array '" + name + "'");
    if (array->GetNumberOfTuples() != surface->GetNumberOfPoints())
      throw Error(ErrorCode::SizeMismatch, "the embedding in '" + path + "' has " +
          std::to_string(array->GetNumberOfTuples()) + " points but the surface has " +
          std::to_string(surface->GetNumberOfPoints()));
    result->GetPointData()->AddArray(array);
    return result;
  }
  const Eigen::MatrixXd E = vtkBaryDataIO::ReadMatrix(path);
  if (E.rows() != surface->GetNumberOfPoints())
    throw Error(ErrorCode::SizeMismatch, "the embedding '" + path + "' has " +
        std::to_string(E.rows()) + " lines but the surface has " +
        std::to_string(surface->GetNumberOfPoints()) + " points (one line per point, in order)");
  if (E.cols() < 2)
    throw Error(ErrorCode::Io, "the embedding '" + path + "' has 1 number a line; at least 2 are needed");
  vtkNew<vtkDoubleArray> array;
  array->SetName(name.c_str());
  array->SetNumberOfComponents(static_cast<int>(E.cols()));
  array->SetNumberOfTuples(E.rows());
  for (vtkIdType i = 0; i < E.rows(); ++i)
    for (int d = 0; d < E.cols(); ++d)
      array->SetTypedComponent(i, d, E(i, d));
  result->GetPointData()->AddArray(array);
  return result;
}

void WriteEmbedding(vtkPolyData* surface, const std::string& path)
{
  if (is_data_extension(path))
  {
    vtkBaryDataIO::Write(surface, path);
    return;
  }
  vtkDataArray* array = surface->GetPointData()->GetArray(vtkBarySurfaceData::DefaultEmbeddingName());
  if (!array)
    throw Error(ErrorCode::Internal, "the surface has no embedding to write");
  vtkBaryDataIO::WriteMatrix(vtkBaryConversion::ArrayToMatrix(array), path);
}

vtkSmartPointer<vtkPolyData> WeightedAverage(vtkPolyData* surface, vtkPointSet* anchors,
  const bary::DenseWeights& W, const bary::ForwardOptions& options, double surface_tolerance,
  const RunCallbacks& callbacks, json* summary)
{
  vtkNew<vtkDoubleArray> weights;
  weights->SetNumberOfComponents(static_cast<int>(W.cols()));
  weights->SetNumberOfTuples(W.rows());
  std::copy(W.data(), W.data() + W.size(), weights->GetPointer(0));
  vtkNew<vtkBaryWeightedAverage> average;
  average->SetInputData(0, surface);
  average->SetInputData(1, anchors);
  average->SetWeights(weights);
  average->SetBruteForce(options.search == bary::ForwardOptions::Search::BruteForce);
  average->SetWarmStart(options.warm_start);
  average->SetMaximumTriangles(options.max_triangles);
  average->SetNumberOfThreads(options.threads);
  average->SetSurfaceTolerance(surface_tolerance);
  RunAlgorithm(average, callbacks);
  if (summary)
  {
    json& s = *summary;
    s["queries"] = W.rows();
    s["anchors"] = W.cols();
    s["failures"] = average->GetNumberOfFailures();
    s["triangles_tried"] = average->GetTrianglesTried();
    s["search"] = options.search == bary::ForwardOptions::Search::BruteForce ? "brute-force" : "local";
    s["warm_start"] = options.warm_start;
    s["seconds"] = average->GetQuerySeconds();
    s["microseconds_per_query"] = W.rows() > 0 ? 1e6 * average->GetQuerySeconds() / static_cast<double>(W.rows()) : 0.0;
  }
  return average->GetOutput();
}

vtkSmartPointer<vtkPointSet> SurfaceWeights(vtkPointSet* points, vtkPolyData* surface,
  vtkPointSet* anchors, const bary::InverseOptions& options, double surface_tolerance,
  double round_trip_tolerance, const RunCallbacks& callbacks, json* summary,
  const Eigen::MatrixXd* anchor_uv)
{
  vtkNew<vtkBarySurfaceWeights> weights;
  if (anchor_uv)
  {
    vtkNew<vtkDoubleArray> uv;
    uv->SetNumberOfComponents(2);
    uv->SetNumberOfTuples(anchor_uv->rows());
    for (vtkIdType i = 0; i < anchor_uv->rows(); ++i)
      for (int c = 0; c < 2; ++c)
        uv->SetComponent(i, c, (*anchor_uv)(i, c));
    weights->SetAnchorTextureCoordinates(uv);
  }
  weights->SetInputData(0, points);
  weights->SetInputData(1, surface);
  weights->SetInputData(2, anchors);
  weights->SetGamma(options.gamma);
  weights->SetNumberOfThreads(options.threads);
  weights->SetSurfaceTolerance(surface_tolerance);
  weights->SetRoundTripTolerance(round_trip_tolerance);
  RunAlgorithm(weights, callbacks);
  vtkSmartPointer<vtkPointSet> result = vtkPointSet::SafeDownCast(weights->GetOutputDataObject(0));
  if (summary)
  {
    json& s = *summary;
    s["points"] = points->GetNumberOfPoints();
    s["anchors"] = anchors->GetNumberOfPoints();
    s["gamma"] = options.gamma;
    s["seconds"] = weights->GetQuerySeconds();
    s["microseconds_per_query"] = points->GetNumberOfPoints() > 0
      ? 1e6 * weights->GetQuerySeconds() / static_cast<double>(points->GetNumberOfPoints())
      : 0.0;
    s["round_trip"] = { { "tolerance", round_trip_tolerance },
      { "failures", weights->GetNumberOfRoundTripFailures() },
      { "not_returned", weights->GetNumberOfUndefined() },
      { "median_error", weights->GetMedianRoundTripError() },
      { "max_error", weights->GetMaximumRoundTripError() },
      { "seconds", weights->GetRoundTripSeconds() } };
  }
  return result;
}

vtkSmartPointer<vtkPolyData> SurfaceCurve(vtkPolyData* surface, vtkPointSet* controls,
  int samples_per_segment, bool closed, double surface_tolerance, int threads,
  const RunCallbacks& callbacks, json* summary)
{
  vtkNew<vtkBarySurfaceCurve> curve;
  curve->SetInputData(0, surface);
  curve->SetControlPointsData(controls);
  curve->SetSamplesPerSegment(samples_per_segment);
  curve->SetClosed(closed);
  curve->SetSurfaceTolerance(surface_tolerance);
  curve->SetNumberOfThreads(threads);
  RunAlgorithm(curve, callbacks);
  vtkSmartPointer<vtkPolyData> result = curve->GetOutput();
  if (summary)
  {
    json& s = *summary;
    s["control_points"] = controls->GetNumberOfPoints();
    s["samples"] = result->GetNumberOfPoints();
    s["closed"] = closed;
    s["failures"] = curve->GetNumberOfFailures();
    s["polylines"] = result->GetNumberOfLines();
  }
  return result;
}

vtkSmartPointer<vtkPolyData> Remesh(vtkPolyData* surface, vtkPolyData* coarse,
  const bary::RemeshOptions& options, double surface_tolerance, const RunCallbacks& callbacks,
  json* summary)
{
  vtkNew<vtkBarySurfaceRemesh> remesh;
  remesh->SetInputData(0, surface);
  remesh->SetCoarseMeshData(coarse);
  remesh->SetLevels(options.levels);
  remesh->SetSmoothingSteps(options.smoothing_steps);
  remesh->SetNumberOfThreads(options.threads);
  remesh->SetSurfaceTolerance(surface_tolerance);
  RunAlgorithm(remesh, callbacks);
  vtkSmartPointer<vtkPolyData> result = remesh->GetOutput();
  if (summary)
  {
    json& s = *summary;
    s["coarse_vertices"] = coarse->GetNumberOfPoints();
    s["coarse_quads"] = coarse->GetNumberOfPolys();
    s["levels"] = options.levels;
    s["smoothing_steps"] = options.smoothing_steps;
    s["vertices"] = result->GetNumberOfPoints();
    s["quads"] = result->GetNumberOfPolys();
    s["failures"] = remesh->GetNumberOfFailures();
  }
  return result;
}

vtkSmartPointer<vtkPolyData> Transfer(vtkPolyData* target, vtkPointSet* target_anchors,
  vtkPolyData* source, vtkPointSet* source_anchors, const std::vector<std::string>& arrays,
  const bary::CorrespondenceOptions& options, double surface_tolerance,
  const RunCallbacks& callbacks, json* summary)
{
  vtkNew<vtkBarySurfaceCorrespondence> map;
  map->SetInputData(0, target);
  map->SetTargetAnchorsData(target_anchors);
  map->SetSourceData(source);
  map->SetSourceAnchorsData(source_anchors);
  for (const std::string& a : arrays)
    map->AddArrayName(a.c_str());
  map->SetGamma(options.inverse.gamma);
  map->SetRoundTripTolerance(options.round_trip_tolerance);
  map->SetSurfaceTolerance(surface_tolerance);
  map->SetNumberOfThreads(options.inverse.threads);
  RunAlgorithm(map, callbacks);
  if (summary)
  {
    json& s = *summary;
    s["target_points"] = target->GetNumberOfPoints();
    s["anchors"] = target_anchors->GetNumberOfPoints();
    s["undefined"] = map->GetNumberOfUndefined();
    s["flipped_triangles"] = map->GetNumberOfFlipped();
    s["flipped_area_fraction"] = map->GetFlippedAreaFraction();
    s["stretch"] = { { "all", map->GetStretch() }, { "best_95_percent", map->GetStretchBest95() } };
  }
  return map->GetOutput();
}

std::string WriteMorph(vtkPolyData* transferred, int frames, const std::string& output_dir,
  const std::string& prefix)
{
  if (frames < 1)
    throw Error(ErrorCode::InvalidArgument, "a morph needs at least 1 frame, got " + std::to_string(frames));
  vtkDataArray* image = transferred->GetPointData()->GetArray("SourcePosition");
  if (!image)
    throw Error(ErrorCode::Internal, "the transferred surface has no SourcePosition");
  std::vector<vtkSmartPointer<vtkDataSet>> series;
  for (int f = 0; f <= frames; ++f)
  {
    const double t = static_cast<double>(f) / frames;
    auto frame = vtkSmartPointer<vtkPolyData>::New();
    frame->ShallowCopy(transferred);
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(transferred->GetNumberOfPoints());
    for (vtkIdType v = 0; v < transferred->GetNumberOfPoints(); ++v)
    {
      double x[3], y[3];
      transferred->GetPoint(v, x);
      image->GetTuple(v, y);
      for (int c = 0; c < 3; ++c)
        x[c] = std::isnan(y[c]) ? x[c] : (1 - t) * x[c] + t * y[c];
      points->SetPoint(v, x);
    }
    frame->SetPoints(points);
    series.push_back(frame);
  }
  return WriteTimeSeries(series, output_dir, prefix, 1.0);
}

} // namespace barylab
