#include "barylabViewerCompute.h"

#include "core/common/error.h"

#include <QApplication>
#include <QElapsedTimer>
#include <QTimer>
#include <QtConcurrent/QtConcurrentRun>

#include <chrono>

namespace barylab
{
namespace viewer
{
namespace
{
template <class T>
vtkSmartPointer<T> deep_copy(T* data)
{
  if (!data)
    return nullptr;
  vtkSmartPointer<T> copy;
  copy.TakeReference(T::SafeDownCast(data->NewInstance()));
  copy->DeepCopy(data);
  return copy;
}
} // namespace

ComputeResult RunCompute(vtkSmartPointer<vtkDataSet> model, vtkSmartPointer<vtkPolyData> controls,
  vtkSmartPointer<vtkDataSet> domain, WeightsParameters parameters, QString compare_method,
  std::shared_ptr<std::atomic<double>> progress, std::shared_ptr<std::atomic<bool>> cancel)
{
  ComputeResult result;
  result.parameters = parameters;
  result.compare_method = compare_method;
  const auto t0 = std::chrono::steady_clock::now();
  try
  {
    const int runs = compare_method.isEmpty() ? 1 : 2;
    for (int run = 0; run < runs; ++run)
    {
      WeightsParameters p = parameters;
      if (run == 1)
        p.method = bary::method_from_name(compare_method.toStdString());
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

ComputeRunner::ComputeRunner(QObject* parent)
  : QObject(parent)
  , Progress(std::make_shared<std::atomic<double>>(0.0))
  , CancelFlag(std::make_shared<std::atomic<bool>>(false))
{
  connect(&this->Watcher, &QFutureWatcher<ComputeResult>::finished, this, &ComputeRunner::onDone);
}

ComputeRunner::~ComputeRunner()
{
  if (this->Watcher.isRunning())
  {
    this->CancelFlag->store(true);
    this->Watcher.waitForFinished();
  }
}

void ComputeRunner::start(vtkDataSet* model, vtkPolyData* controls, vtkDataSet* domain,
  const WeightsParameters& parameters, const QString& compare_method)
{
  if (this->Busy)
    return;
  this->Progress->store(0.0);
  this->CancelFlag->store(false);
  // the worker gets its own copies: the views keep drawing the originals
  auto model_copy = deep_copy(model);
  auto controls_copy = deep_copy(controls);
  auto domain_copy = deep_copy(domain);
  if (this->Synchronous)
  {
    QApplication::setOverrideCursor(Qt::WaitCursor);
    const ComputeResult result = RunCompute(model_copy, controls_copy, domain_copy, parameters,
      compare_method, this->Progress, this->CancelFlag);
    QApplication::restoreOverrideCursor();
    emit finished(result);
    return;
  }
  this->Busy = true;
  const auto progress = this->Progress;
  const auto cancel = this->CancelFlag;
  this->Watcher.setFuture(QtConcurrent::run([=]() {
    return RunCompute(model_copy, controls_copy, domain_copy, parameters, compare_method,
      progress, cancel);
  }));
  QTimer::singleShot(100, this, &ComputeRunner::onPoll);
}

void ComputeRunner::onPoll()
{
  if (!this->Busy)
    return;
  emit progressed(this->Progress->load());
  QTimer::singleShot(100, this, &ComputeRunner::onPoll);
}

bool ComputeRunner::cancel()
{
  if (!this->Busy)
    return false;
  this->CancelFlag->store(true);
  return true;
}

bool ComputeRunner::wait(int timeout_ms)
{
  QElapsedTimer timer;
  timer.start();
  while (this->Busy)
  {
    if (timer.elapsed() > timeout_ms)
      return false;
    QApplication::processEvents(QEventLoop::AllEvents, 20);
  }
  return true;
}

void ComputeRunner::onDone()
{
  const QFuture<ComputeResult> future = this->Watcher.future();
  this->Busy = false;
  if (future.resultCount() == 0)
  {
    emit abandoned();
    return;
  }
  const ComputeResult result = future.result();
  this->Watcher.setFuture(QFuture<ComputeResult>());
  emit finished(result);
}

} // namespace viewer
} // namespace barylab
