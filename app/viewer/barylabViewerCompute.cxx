#include "barylabViewerCompute.h"

#include "core/error.h"

#include <chrono>

namespace barylab
{
namespace viewer
{

ComputeResult RunCompute(vtkSmartPointer<vtkDataSet> model, vtkSmartPointer<vtkPolyData> controls,
  vtkSmartPointer<vtkDataSet> domain, WeightsParameters parameters, QString compare_method,
  std::shared_ptr<std::atomic<double>> progress, std::shared_ptr<std::atomic<bool>> cancel)
{
  ComputeResult result;
  const auto t0 = std::chrono::steady_clock::now();
  try
  {
    const int runs = compare_method.isEmpty() ? 1 : 2;
    for (int run = 0; run < runs; ++run)
    {
      WeightsParameters p = parameters;
      if (run == 1)
        p.method = compare_method.toStdString();
      RunCallbacks callbacks;
      callbacks.progress = [progress, run, runs](double f) {
        progress->store((run + f) / runs);
      };
      callbacks.cancel = [cancel]() { return cancel->load(); };
      auto weighted = ComputeWeights(model, controls, p, callbacks, nullptr, domain);
      (run == 0 ? result.weighted : result.compare) = weighted;
    }
  }
  catch (const bary::Error& e)
  {
    result.cancelled = e.code() == bary::ErrorCode::Cancelled;
    result.error = QString::fromStdString(e.what());
  }
  catch (const std::exception& e)
  {
    result.error = QString::fromStdString(e.what());
  }
  result.seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  progress->store(1.0);
  return result;
}

} // namespace viewer
} // namespace barylab
