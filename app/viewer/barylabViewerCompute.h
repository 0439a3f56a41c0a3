#pragma once
/// @file barylabViewerCompute.h
/// The weights computation the viewer runs in a worker thread: ComputeWeights for the method
/// and, if any, the comparison method, with progress and cancellation through atomics only.

#include "barylabPipeline.h"

#include <QString>

#include "vtkDataSet.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <atomic>
#include <memory>

namespace barylab
{
namespace viewer
{

/// What one computation produced (worker thread result).
struct ComputeResult
{
  vtkSmartPointer<vtkDataSet> weighted;
  vtkSmartPointer<vtkDataSet> compare; ///< the comparison method's weights (side-by-side)
  QString error;
  double seconds = 0.0;
  bool cancelled = false;
};

/// Computes @p parameters' weights at @p model's points (then @p compare_method's, unless
/// empty) from the worker's own copies of the data: no Qt, no shared state but @p progress
/// (in [0, 1] over both runs) and @p cancel. Errors come back in ComputeResult::error.
ComputeResult RunCompute(vtkSmartPointer<vtkDataSet> model, vtkSmartPointer<vtkPolyData> controls,
  vtkSmartPointer<vtkDataSet> domain, WeightsParameters parameters, QString compare_method,
  std::shared_ptr<std::atomic<double>> progress, std::shared_ptr<std::atomic<bool>> cancel);

} // namespace viewer
} // namespace barylab
