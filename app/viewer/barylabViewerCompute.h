#pragma once
/// @file barylabViewerCompute.h
/// The weights computation the viewer runs in a worker thread: ComputeWeights for the method
/// and, if any, the comparison method, with progress and cancellation through atomics only;
/// and the ComputeRunner that starts it, polls its progress, cancels it and waits for it.

#include "barylabPipeline.h"

#include <QFutureWatcher>
#include <QObject>
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
  WeightsParameters parameters; ///< what was computed
  QString compare_method;       ///< the comparison method computed ("" = none)
};

/// Computes @p parameters' weights at @p model's points (then @p compare_method's, unless
/// empty) from the worker's own copies of the data: no Qt, no shared state but @p progress
/// (in [0, 1] over both runs) and @p cancel. Errors come back in ComputeResult::error.
ComputeResult RunCompute(vtkSmartPointer<vtkDataSet> model, vtkSmartPointer<vtkPolyData> controls,
  vtkSmartPointer<vtkDataSet> domain, WeightsParameters parameters, QString compare_method,
  std::shared_ptr<std::atomic<double>> progress, std::shared_ptr<std::atomic<bool>> cancel);

/// Runs RunCompute on copies of the inputs, in a worker thread (or, synchronous, in the
/// calling thread under a wait cursor), reports its progress every 100 ms while it runs and
/// its result when it is done. One computation at a time.
class ComputeRunner : public QObject
{
  Q_OBJECT
public:
  explicit ComputeRunner(QObject* parent = nullptr);
  /// Cancels a computation still running and waits for it.
  ~ComputeRunner() override;

  /// True while a worker runs (until its result is handled); never in synchronous mode.
  bool isBusy() const { return this->Busy; }
  /// Synchronous: start() computes in the calling thread and emits finished before returning.
  void setSynchronous(bool on) { this->Synchronous = on; }

  /// Computes @p parameters' weights (and @p compare_method's, unless empty) at @p model's
  /// points, from deep copies of the inputs (the views keep drawing the originals). Does
  /// nothing while busy.
  void start(vtkDataSet* model, vtkPolyData* controls, vtkDataSet* domain,
    const WeightsParameters& parameters, const QString& compare_method);
  /// Asks the worker to stop; false when none runs.
  bool cancel();
  /// Waits (processing events) until no computation runs; false on timeout.
  bool wait(int timeout_ms);

signals:
  /// The fraction done, in [0, 1], every 100 ms while a worker runs.
  void progressed(double fraction);
  /// A computation ended (failed and cancelled ones too: see ComputeResult::error).
  void finished(const barylab::viewer::ComputeResult& result);
  /// A worker ended without a result.
  void abandoned();

private:
  void onDone();
  void onPoll();

  bool Synchronous = false;
  bool Busy = false;
  QFutureWatcher<ComputeResult> Watcher;
  std::shared_ptr<std::atomic<double>> Progress;
  std::shared_ptr<std::atomic<bool>> CancelFlag;
};

} // namespace viewer
} // namespace barylab
