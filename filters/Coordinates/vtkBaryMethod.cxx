#include "vtkBaryMethod.h"

#include "vtkBaryCoordinates.h"

#include "core/error.h"
#include "core/harmonic_coordinates.h"
#include "core/mean_value_coordinates.h"

#include "vtkObjectFactory.h"

#include <algorithm>

vtkStandardNewMacro(vtkBaryMethod);

bary::PolygonMeshOptions vtkBaryMethod::PolygonMeshOptions(
  const vtkBaryMethodParameters& parameters, const Eigen::MatrixXd& points)
{
  bary::PolygonMeshOptions options;
  options.target_cells = parameters.TargetNumberOfCells > 0 ? parameters.TargetNumberOfCells
                                                            : vtkBaryDefaultTargetCells(2);
  options.max_area = parameters.MaximumCellSize;
  if (parameters.InsertPointsIntoMesh)
    options.steiner_points = points;
  return options;
}

bary::SurfaceMeshOptions vtkBaryMethod::SurfaceMeshOptions(
  const vtkBaryMethodParameters& parameters, const Eigen::MatrixXd& points)
{
  bary::SurfaceMeshOptions options;
  options.target_cells = parameters.TargetNumberOfCells > 0 ? parameters.TargetNumberOfCells
                                                            : vtkBaryDefaultTargetCells(3);
  options.max_volume = parameters.MaximumCellSize;
  if (parameters.InsertPointsIntoMesh)
    options.steiner_points = points;
  return options;
}

bary::DenseWeights vtkBaryMethod::Compute(const vtkBaryCage& cage,
  const Eigen::MatrixXd& points, const vtkBaryMethodParameters& parameters,
  const bary::ProgressCallback& progress, vtkBaryMethodReport* report)
{
  switch (parameters.Method)
  {
    case vtkBaryCoordinates::MEAN_VALUE:
    {
      bary::MeanValueOptions options;
      options.boundary_tolerance = parameters.BoundaryTolerance;
      options.validate = parameters.ValidateCage;
      options.threads = parameters.NumberOfThreads;
      bary::MeanValueCoordinates mvc(cage.Cage, options);
      bary::MeanValueResult result = mvc.evaluate(points, progress);
      if (report)
      {
        report->Inside = result.inside;
        report->Outside = result.outside;
        report->Boundary = result.boundary;
        report->Undefined.assign(result.undefined.begin(), result.undefined.end());
        report->Location.resize(result.location.size());
        for (std::size_t i = 0; i < result.location.size(); ++i)
          report->Location[i] = static_cast<unsigned char>(result.location[i]);
      }
      return std::move(result.W);
    }
    case vtkBaryCoordinates::HARMONIC:
    {
      bary::HarmonicOptions options;
      options.validate = parameters.ValidateCage;
      options.polygon_mesh = PolygonMeshOptions(parameters, points);
      options.surface_mesh = SurfaceMeshOptions(parameters, points);
      const bary::HarmonicCoordinates harmonic(cage.Cage, options,
        [&progress](double f) { return !progress || progress(0.9 * f); });
      static const bary::OutsidePolicy policies[] = { bary::OutsidePolicy::Error,
        bary::OutsidePolicy::Nearest, bary::OutsidePolicy::NaN };
      const bary::OutsidePolicy policy = policies[std::clamp(parameters.OutsidePolicy, 0, 2)];
      std::vector<bary::Index> outside;
      bary::DenseWeights W = harmonic.evaluate(points, policy, &outside,
        [&progress](double f) { return !progress || progress(0.9 + 0.1 * f); });
      if (report)
      {
        const vtkIdType np = points.rows();
        report->Outside = static_cast<vtkIdType>(outside.size());
        report->Inside = np - report->Outside;
        report->Boundary = 0;
        report->Location.assign(static_cast<std::size_t>(np), 0);
        for (auto id : outside)
          report->Location[static_cast<std::size_t>(id)] = 1;
        report->Undefined.clear();
        if (policy == bary::OutsidePolicy::NaN)
          report->Undefined.assign(outside.begin(), outside.end());
      }
      return W;
    }
    default:
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "unknown coordinate method " + std::to_string(parameters.Method));
  }
}
