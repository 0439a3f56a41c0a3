#include "vtkBaryMethod.h"

#include "vtkBaryCoordinates.h"

#include "core/error.h"
#include "core/mean_value_coordinates.h"

#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkBaryMethod);

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
    default:
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "unknown coordinate method " + std::to_string(parameters.Method));
  }
}
