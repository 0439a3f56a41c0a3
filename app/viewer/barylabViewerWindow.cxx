#include "barylabViewerWindow.h"
#include "barylabViewerSkeletonMode.h"

#include "barylabViewerExamples.h"
#include "barylabViewerFreePointsMode.h"
#include "barylabViewerLocality.h"
#include "barylabViewerMenus.h"
#include "barylabViewerMode.h"
#include "barylabViewerPanel.h"
#include "barylabViewerParameters.h"
#include "barylabViewerViews.h"

#include "vtkBaryDataIO.h"

#include <QApplication>
#include <QFileInfo>
#include <QImage>
#include <QMessageBox>
#include <QProgressBar>
#include <QSplitter>
#include <QStatusBar>

#include <QVTKOpenGLNativeWidget.h>

#include "vtkInteractorObserver.h"
#include "vtkRenderer.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace barylab
{
namespace viewer
{
namespace
{
using json = nlohmann::json;
} // namespace

QStringList ViewerWindow::ExampleNames()
{
  return viewer::ExampleNames();
}

ViewerWindow::ViewerWindow(QWidget* parent)
  : QMainWindow(parent)
{
  qRegisterMetaType<barylab::viewer::Inputs>();
  connect(&this->Runner, &ComputeRunner::finished, this, &ViewerWindow::finishCompute);
  connect(&this->Runner, &ComputeRunner::abandoned, this, [this]() {
    this->ProgressBar->hide();
    this->Panel->sync();
  });
  this->setWindowTitle("BaryLab viewer");
  this->resize(1280, 800);
  this->buildViews();
  BuildMenus(*this);
  this->Panel->sync();
  this->updateScene();
  this->statusBar()->showMessage("Open a cage and a model (File > Open) or an example.");
}

ViewerWindow::~ViewerWindow() = default;

QVTKOpenGLNativeWidget* ViewerWindow::view() const
{
  return this->ViewPair->view();
}

QVTKOpenGLNativeWidget* ViewerWindow::compareView() const
{
  return this->ViewPair->compareView();
}

vtkRenderer* ViewerWindow::renderer() const
{
  return this->ViewPair->renderer();
}

vtkRenderer* ViewerWindow::compareRenderer() const
{
  return this->ViewPair->compareRenderer();
}

const Mode& ViewerWindow::currentMode() const
{
  return ModeFor(MethodName(this->Parameters), this->State);
}

const Mode& ViewerWindow::shownMode() const
{
  return this->State.weighted() ? ModeFor(MethodName(this->State.computed()), this->State)
                                : this->currentMode();
}

ControlKind ViewerWindow::controlKind() const
{
  return this->currentMode().controlKind();
}

ControlKind ViewerWindow::shownKind() const
{
  return this->shownMode().controlKind();
}

// ------------------------------------------------------------------------------------------
// user interface

void ViewerWindow::buildViews()
{
  auto* splitter = new QSplitter(Qt::Horizontal, this);
  this->ViewPair = new Views(splitter, [this]() { return this->State.posedControls(); });
  this->setCentralWidget(splitter);
  connect(this->ViewPair, &Views::controlPressed, this, &ViewerWindow::onControlPressed);
  connect(this->ViewPair, &Views::controlDragged, this, &ViewerWindow::onControlDragged);
  connect(this->ViewPair, &Views::controlReleased, this, [this](int id) {
    this->Panel->setMovePosition(this->posedControls()->GetPoint(id));
  });
  connect(this->ViewPair, &Views::viewClicked, this,
    [this](int x, int y) { this->addControlPointAt(x, y); });

  // locality charts (P(t), Q(k)), hidden until asked for
  this->Locality = new LocalityDock(this->State, this);
  this->addDockWidget(Qt::BottomDockWidgetArea, this->Locality);
  this->Locality->hide();
  connect(this->Locality, &LocalityDock::failed, this, &ViewerWindow::reportError);

  // side panel
  this->Panel = new ControlPanel(this);
  splitter->insertWidget(0, this->Panel);
  splitter->setStretchFactor(0, 0);
  splitter->setStretchFactor(1, 1);
  splitter->setStretchFactor(2, 1);

  this->ProgressBar = new QProgressBar;
  this->ProgressBar->setRange(0, 1000);
  this->ProgressBar->setMaximumWidth(220);
  this->ProgressBar->hide();
  this->statusBar()->addPermanentWidget(this->ProgressBar);
  connect(&this->Runner, &ComputeRunner::progressed, this->ProgressBar,
    [this](double fraction) { this->ProgressBar->setValue(static_cast<int>(1000.0 * fraction)); });
}

void ViewerWindow::reportError(const QString& message)
{
  this->Errors << message;
  this->statusBar()->showMessage("Error: " + message);
  emit errorReported(message);
  if (this->Interactive)
    QMessageBox::warning(this, "BaryLab viewer", message);
}

template <class Action>
bool ViewerWindow::reporting(Action&& action, const QString& prefix)
{
  try
  {
    action();
  }
  catch (const std::exception& e)
  {
    this->reportError(prefix + QString::fromStdString(e.what()));
    return false;
  }
  return true;
}

// ------------------------------------------------------------------------------------------
// inputs

bool ViewerWindow::openFiles(const QStringList& files)
{
  if (files.size() < 2 || files.size() > 3)
  {
    this->reportError("open CONTROLS MODEL [DOMAIN]: a cage, skeleton (.tgf) or control points, "
                      "the model, and for a skeleton the domain to mesh (" +
      QString::number(files.size()) + " file(s) given)");
    return false;
  }
  Inputs in;
  in.controls = files[0];
  in.model = files[1];
  if (files.size() == 3)
    in.domain = files[2];
  return this->openInputs(in);
}

bool ViewerWindow::openInputs(const Inputs& given)
{
  if (this->isComputing())
  {
    this->reportError("a computation is running: cancel it first");
    return false;
  }
  if (!this->reporting([&]() { this->State.open(given); }))
    return false;
  // other inputs: the label map of openLabelMap (the transform's grid) no longer applies
  this->LabelMap = nullptr;
  this->LabelMapPath.clear();
  const Inputs& in = this->State.inputs();
  this->Options.component = 0;
  this->Options.dimension = this->State.modelDimension();
  this->Options.clip = false;
  this->Options.texture = this->State.picture();
  if (this->State.picture())
    this->Options.field = SceneOptions::Field::Image;
  else if (this->Options.field == SceneOptions::Field::Image)
    this->Options.field = SceneOptions::Field::Weight;
  this->CameraNeedsReset = true;
  if (IsSkeletonFile(in.controls) && this->Parameters.method != bary::MethodId::BBW)
    this->Parameters.method = bary::MethodId::BBW;
  this->Panel->setInputs(this->State);
  this->setWindowTitle("BaryLab viewer - " +
    (in.example.isEmpty() ? QFileInfo(in.model).fileName() : in.example));
  this->updateControlList();
  this->Panel->sync();
  this->updateScene();
  this->statusBar()->showMessage("Opened " + QFileInfo(in.model).fileName() + ": press Compute (F5).");
  return true;
}

bool ViewerWindow::loadExample(const QString& name, bool compute)
{
  const Example* example = FindExample(name);
  if (!example)
  {
    this->reportError("unknown example '" + name + "' (known: " + ExampleNames().join(", ") + ")");
    return false;
  }
  this->Parameters = WeightsParameters();
  this->Parameters.method = bary::method_from_name(example->method);
  this->CompareMethod.clear();
  if (!this->openInputs(example->inputs()))
    return false;
  this->PendingSelection = example->selected;
  this->Panel->sync();
  if (compute)
    this->compute();
  return true;
}

void ViewerWindow::updateControlList()
{
  this->Panel->setControlLabels(
    this->shownMode().controlLabels(this->State, this->componentCount()), this->Options.component);
}

// ------------------------------------------------------------------------------------------
// parameters and computation

void ViewerWindow::setMethod(const QString& method)
{
  const auto names = MethodNames();
  if (std::find(names.begin(), names.end(), method.toStdString()) == names.end())
  {
    this->reportError("unknown method '" + method + "'");
    this->Panel->sync();
    return;
  }
  this->Parameters.method = bary::method_from_name(method.toStdString());
  this->Panel->sync();
  this->statusBar()->showMessage("Method " + method + ": press Compute (F5).");
}

bool ViewerWindow::setParameter(const QString& key, const QVariant& value)
{
  for (const ParameterField& f : WeightsParameterFields())
  {
    if (f.key != key.toStdString())
      continue;
    const bool set = this->reporting([&]() {
      json v;
      switch (f.kind)
      {
        case ParameterField::Kind::Bool: v = value.toBool(); break;
        case ParameterField::Kind::Int: v = value.toInt(); break;
        case ParameterField::Kind::Double: v = value.toDouble(); break;
        case ParameterField::Kind::Choice:
          v = f.get(this->Parameters).is_number() ? json(value.toString().toInt())
                                                  : json(value.toString().toStdString());
          break;
        case ParameterField::Kind::String: v = value.toString().toStdString(); break;
      }
      f.set(this->Parameters, v);
    });
    if (!set)
      return false;
    this->Panel->sync();
    this->statusBar()->showMessage("Parameter " + key + " = " + value.toString() +
      ": press Compute (F5).");
    return true;
  }
  this->reportError("unknown parameter '" + key + "'");
  return false;
}

void ViewerWindow::setParameters(const WeightsParameters& parameters)
{
  this->Parameters = parameters;
  this->Panel->sync();
}

void ViewerWindow::setCompareMethod(const QString& method)
{
  this->CompareMethod = method;
  this->compareView()->setVisible(!method.isEmpty());
  this->CameraNeedsReset = true; // the views' aspect changes
  QApplication::processEvents(QEventLoop::ExcludeUserInputEvents); // lay the views out
  this->State.clearCompare();
  this->Panel->sync();
  if (!method.isEmpty())
    this->statusBar()->showMessage("Compare with " + method + ": press Compute (F5).");
  this->updateScene();
}

void ViewerWindow::compute()
{
  if (this->isComputing())
    return;
  if (!this->State.model() || !this->State.controls())
  {
    this->reportError("nothing to compute: open a cage and a model, or an example");
    return;
  }
  this->Runner.start(this->State.model(), this->State.controls(), this->State.domain(),
    this->Parameters, this->CompareMethod);
  if (!this->isComputing())
    return; // synchronous: done already
  this->ProgressBar->setValue(0);
  this->ProgressBar->show();
  this->Panel->sync();
  this->statusBar()->showMessage("Computing " + QString::fromStdString(MethodName(this->Parameters)) +
    " weights...");
}

void ViewerWindow::cancel()
{
  if (this->Runner.cancel())
    this->statusBar()->showMessage("Cancelling...");
}

bool ViewerWindow::waitForComputation(int timeout_ms)
{
  return this->Runner.wait(timeout_ms);
}

void ViewerWindow::finishCompute(const ComputeResult& result)
{
  this->ProgressBar->hide();
  this->LastSeconds = result.seconds;
  if (!result.error.isEmpty())
  {
    this->Panel->sync();
    if (result.cancelled)
      this->statusBar()->showMessage("Computation cancelled.");
    else
      this->reportError("computing " + QString::fromStdString(MethodName(result.parameters)) +
        " weights failed: " + result.error);
    this->State.clearPendingPose();
    this->PendingSelection = -1;
    emit computeFinished(false);
    return;
  }
  this->State.setWeights(result.weighted, result.compare, result.parameters, result.compare_method);
  if (!this->State.twists().empty() &&
    (!this->shownMode().twistsHandles() ||
      static_cast<int>(this->State.twists().size()) != this->componentCount()))
    this->State.clearTwists();
  if (this->PendingSelection >= 0)
    this->Options.component = this->PendingSelection;
  this->PendingSelection = -1;
  this->Options.component = std::clamp(this->Options.component, 0, std::max(0, this->componentCount() - 1));
  this->updateControlList();
  this->Panel->sync();
  this->poseChanged();
  const QString method = QString::fromStdString(MethodName(this->State.computed()));
  this->Panel->setStatistics(method, result.seconds,
    WeightStatisticsJson(this->State.weighted(), this->Parameters.weights_name, nullptr, -1.0, 0));
  if (this->isLocalityShown())
    this->Locality->refresh();
  this->statusBar()->showMessage(
    QString("Computed %1 weights in %2 s.").arg(method).arg(result.seconds, 0, 'f', 3));
  emit computeFinished(true);
}

// ------------------------------------------------------------------------------------------
// display

void ViewerWindow::optionsChanged()
{
  this->Panel->sync();
  this->updateScene();
}

void ViewerWindow::selectControl(int component)
{
  const int n = this->componentCount();
  if (n <= 0)
    return;
  component = (component % n + n) % n;
  this->Options.component = component;
  this->Panel->sync();
  if (this->shownMode().componentsAreControlPoints())
    this->Panel->setMoveId(component);
  this->updateScene();
}

void ViewerWindow::showWeight()
{
  this->Options.field = SceneOptions::Field::Weight;
  this->optionsChanged();
}

void ViewerWindow::showImage()
{
  if (!this->State.picture())
  {
    this->reportError("no picture: open a cage and a picture (PNG/JPEG) as the model for the image mode");
    this->Panel->sync();
    return;
  }
  this->Options.field = SceneOptions::Field::Image;
  this->optionsChanged();
}

void ViewerWindow::showGradientNorm()
{
  this->Options.field = SceneOptions::Field::GradientNorm;
  this->optionsChanged();
}

void ViewerWindow::setLogScale(bool on)
{
  this->Options.log_scale = on;
  this->optionsChanged();
}

void ViewerWindow::setIsolines(int count)
{
  this->Options.isolines = std::clamp(count, 0, 50);
  this->optionsChanged();
}

void ViewerWindow::setInfluenceLevel(bool on)
{
  this->Options.influence_level = on;
  this->optionsChanged();
}

void ViewerWindow::setClipping(bool on)
{
  this->Options.clip = on;
  this->optionsChanged();
}

void ViewerWindow::setClipAxis(int axis)
{
  this->Options.clip_axis = std::clamp(axis, 0, 2);
  this->optionsChanged();
}

void ViewerWindow::setClipPosition(double fraction)
{
  this->Options.clip_position = std::clamp(fraction, 0.0, 1.0);
  this->optionsChanged();
}

void ViewerWindow::resetCamera()
{
  ResetSceneCamera(this->renderer(), this->Options.dimension);
  this->renderViews();
}

void ViewerWindow::updateScene()
{
  SceneOptions options = this->Options;
  options.controls = this->shownKind();
  options.weights_name = this->Parameters.weights_name;
  options.texture = this->State.picture();
  const QString control = this->Panel->currentControlLabel();
  this->reporting([&]() {
    this->ViewPair->build(this->State, options, control, !this->CompareMethod.isEmpty(), this->Info);
  });
  vtkDataSet* weighted = this->State.weighted();
  if (this->CameraNeedsReset && (weighted || this->State.controls()))
  {
    ResetSceneCamera(this->renderer(), this->Options.dimension);
    this->CameraNeedsReset = !weighted;
  }
  this->renderViews();
  emit sceneUpdated();
}

void ViewerWindow::renderViews()
{
  this->ViewPair->render();
}

// ------------------------------------------------------------------------------------------
// deformation

void ViewerWindow::poseChanged()
{
  this->reporting([this]() { this->State.updateDeformation(this->shownMode()); },
    "deformation failed: ");
  this->updateScene();
}

bool ViewerWindow::setHandleTwist(int handle, double angle_degrees, double scale)
{
  if (!this->hasWeights() || !this->shownMode().twistsHandles())
  {
    this->reportError("rotating / scaling a handle needs BBW weights of a skeleton (compute bbw "
                      "with a .tgf skeleton first); move cage and control points instead");
    return false;
  }
  const int n = this->componentCount();
  if (handle < 0 || handle >= n)
  {
    this->reportError(QString("handle %1 does not exist (the skeleton has %2 handles)").arg(handle).arg(n));
    return false;
  }
  if (!(scale > 0.0) || !std::isfinite(scale) || !std::isfinite(angle_degrees))
  {
    this->reportError(QString("the scale of a handle must be a number > 0 and the angle finite "
                              "(got %1, %2)").arg(scale).arg(angle_degrees));
    return false;
  }
  this->State.setTwist(handle, { angle_degrees, scale }, n);
  this->poseChanged();
  this->statusBar()->showMessage(QString("Handle %1 rotated by %2 deg, scaled by %3.")
                                   .arg(handle).arg(angle_degrees).arg(scale));
  return true;
}

void ViewerWindow::moveControlLive(int id, const double x[3])
{
  this->State.moveControl(id, x);
  this->poseChanged();
}

void ViewerWindow::setControlPosition(int id, double x, double y, double z)
{
  vtkPoints* posed = this->State.posedControls();
  if (!posed || id < 0 || id >= posed->GetNumberOfPoints())
  {
    this->reportError(QString("control %1 does not exist").arg(id));
    return;
  }
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
  {
    this->reportError("control positions must be finite numbers");
    return;
  }
  this->State.pushUndo();
  const double p[3] = { x, y, z };
  this->moveControlLive(id, p);
  this->Panel->setMoveId(id);
  this->Panel->setMovePosition(p);
}

void ViewerWindow::resetPose()
{
  if (!this->State.controls())
    return;
  this->State.resetPose();
  this->poseChanged();
}

void ViewerWindow::undo()
{
  if (!this->State.undo())
  {
    this->statusBar()->showMessage("Nothing to undo.");
    return;
  }
  // an edit of the controls undone: other controls, other weights
  this->Options.component =
    std::clamp(this->Options.component, 0, std::max(0, this->componentCount() - 1));
  this->updateControlList();
  this->Panel->sync();
  this->poseChanged();
}

// ------------------------------------------------------------------------------------------
// adding and removing free control points (celestial coordinates)

namespace
{
/// The world points of display position (x, y) on the near and far clipping planes.
void view_ray(vtkRenderer* renderer, double x, double y, Eigen::Vector3d& near, Eigen::Vector3d& far)
{
  double w[4];
  vtkInteractorObserver::ComputeDisplayToWorld(renderer, x, y, 0.0, w);
  near = Eigen::Vector3d(w[0], w[1], w[2]);
  vtkInteractorObserver::ComputeDisplayToWorld(renderer, x, y, 1.0, w);
  far = Eigen::Vector3d(w[0], w[1], w[2]);
}
} // namespace

bool ViewerWindow::addControlPointAt(double x, double y)
{
  if (!this->hasWeights() || this->shownKind() != ControlKind::FreePoints || this->isComputing())
  {
    this->reportError("adding control points needs the weights of celestial coordinates (tcc, "
                      "scc) of free control points: compute them first");
    return false;
  }
  vtkRenderer* renderer = this->renderer();
  renderer->ResetCameraClippingRange();
  Eigen::Vector3d near, far;
  view_ray(renderer, x, y, near, far);
  vtkPolyData* controls = this->State.controls();
  double point[3];
  if (this->Options.dimension == 2)
  {
    // the view looks down z: the point in the controls' plane
    const double z = controls->GetPoint(0)[2];
    const double t = std::abs(far.z() - near.z()) > 0.0 ? (z - near.z()) / (far.z() - near.z()) : 0.0;
    const Eigen::Vector3d p = near + t * (far - near);
    point[0] = p.x();
    point[1] = p.y();
    point[2] = z;
  }
  else
  {
    // the scene's extent: the view line is drawn across it
    double b[6];
    this->State.model()->GetBounds(b);
    double cb[6];
    controls->GetBounds(cb);
    for (int k = 0; k < 3; ++k)
    {
      b[2 * k] = std::min(b[2 * k], cb[2 * k]);
      b[2 * k + 1] = std::max(b[2 * k + 1], cb[2 * k + 1]);
    }
    const Eigen::Vector3d centre(0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]));
    const double diagonal =
      Eigen::Vector3d(b[1] - b[0], b[3] - b[2], b[5] - b[4]).norm();
    const Eigen::Vector3d e = (far - near).normalized();
    const auto new_line = [&]() {
      // the part of the view line within a diagonal of the scene's centre
      const Eigen::Vector3d m = near + (centre - near).dot(e) * e;
      const Eigen::Vector3d a = m - diagonal * e, c = m + diagonal * e;
      this->State.setViewLine(a.data(), c.data());
      this->updateScene();
      this->statusBar()->showMessage("Adding a control point: rotate the view and Ctrl + click on "
                                     "the yellow view line to place it (Esc cancels).");
      return false;
    };
    if (!this->State.hasViewLine())
      return new_line();
    const Eigen::Vector3d a(this->State.viewLineStart()), c(this->State.viewLineEnd());
    const Eigen::Vector3d d = (c - a).normalized();
    // the points of the view line and the click's ray nearest to each other
    const double de = d.dot(e);
    const double denominator = 1.0 - de * de;
    if (denominator < 1e-6) // seen end on: the view was not rotated
      return new_line();
    const Eigen::Vector3d w0 = a - near;
    const double s = (de * e.dot(w0) - d.dot(w0)) / denominator;
    const Eigen::Vector3d p = a + s * d;
    double display[3];
    vtkInteractorObserver::ComputeWorldToDisplay(renderer, p.x(), p.y(), p.z(), display);
    if (std::hypot(display[0] - x, display[1] - y) > 12.0)
      return new_line(); // not on the line: a new line through this pixel
    point[0] = p.x();
    point[1] = p.y();
    point[2] = p.z();
  }
  // the new point, at rest and posed where it was placed
  auto edited = vtkSmartPointer<vtkPolyData>::New();
  edited->SetPoints(CopyPoints(controls->GetPoints()));
  edited->GetPoints()->InsertNextPoint(point);
  auto posed = CopyPoints(this->State.posedControls());
  posed->InsertNextPoint(point);
  const int id = static_cast<int>(controls->GetNumberOfPoints());
  return this->editControls(edited, posed, id,
    QString("Added control point %1 at (%2, %3, %4)").arg(id).arg(point[0]).arg(point[1]).arg(point[2]));
}

void ViewerWindow::cancelAddControlPoint()
{
  if (!this->State.hasViewLine())
    return;
  this->State.clearViewLine();
  this->updateScene();
  this->statusBar()->showMessage("Adding a control point cancelled.");
}

bool ViewerWindow::removeControlPoint(int id)
{
  if (!this->hasWeights() || this->shownKind() != ControlKind::FreePoints || this->isComputing())
  {
    this->reportError("removing control points needs the weights of celestial coordinates (tcc, "
                      "scc) of free control points: compute them first");
    return false;
  }
  vtkPolyData* controls = this->State.controls();
  const int n = static_cast<int>(controls->GetNumberOfPoints());
  if (id < 0 || id >= n)
  {
    this->reportError(id >= n && id < this->componentCount()
        ? QString("hull point %1 is fixed: the method adds it (hull points: auto); remove the "
                  "control points, not the hull points").arg(id - n)
        : QString("control point %1 does not exist").arg(id));
    return false;
  }
  auto edited = vtkSmartPointer<vtkPolyData>::New();
  auto rest = vtkSmartPointer<vtkPoints>::New();
  auto posed = vtkSmartPointer<vtkPoints>::New();
  rest->SetDataTypeToDouble();
  posed->SetDataTypeToDouble();
  for (int i = 0; i < n; ++i)
    if (i != id)
    {
      rest->InsertNextPoint(controls->GetPoint(i));
      posed->InsertNextPoint(this->State.posedControls()->GetPoint(i));
    }
  edited->SetPoints(rest);
  return this->editControls(edited, posed, std::min(id, n - 2),
    QString("Removed control point %1").arg(id));
}

bool ViewerWindow::editControls(vtkSmartPointer<vtkPolyData> controls,
  vtkSmartPointer<vtkPoints> posed, int select, const QString& what)
{
  vtkSmartPointer<vtkDataSet> weighted;
  double seconds = 0.0;
  if (!this->reporting([&]() { weighted = FreePointsMode::EditedWeights(this->State, controls, &seconds); },
        what + " failed: "))
    return false;
  this->LastEditSeconds = seconds;
  this->State.replaceControls(controls, posed, weighted);
  this->Options.component = std::clamp(select, 0, std::max(0, this->componentCount() - 1));
  this->updateControlList();
  this->Panel->sync();
  if (this->shownMode().componentsAreControlPoints())
    this->Panel->setMoveId(this->Options.component);
  this->poseChanged();
  this->statusBar()->showMessage(
    what + QString(": weights updated in %1 s.").arg(seconds, 0, 'f', 3));
  return true;
}

bool ViewerWindow::loadPose(const QString& path)
{
  if (!this->State.controls())
  {
    this->reportError("open inputs before a pose");
    return false;
  }
  vtkSmartPointer<vtkPoints> posed;
  if (!this->reporting([&]() { posed = this->shownMode().readPose(this->State, path); }))
    return false;
  this->State.setPose(posed);
  this->poseChanged();
  return true;
}

bool ViewerWindow::applyExamplePose()
{
  if (this->inputs().pose.isEmpty())
  {
    this->reportError("these inputs have no bundled pose: use File > Load pose");
    return false;
  }
  return this->loadPose(this->inputs().pose);
}

bool ViewerWindow::savePose(const QString& path)
{
  if (!this->State.controls() || !this->State.posedControls())
  {
    this->reportError("no pose to save: open inputs first");
    return false;
  }
  if (!this->reporting([&]() { this->shownMode().writePose(this->State, path); }))
    return false;
  this->statusBar()->showMessage("Saved the pose to " + path);
  return true;
}

bool ViewerWindow::saveDeformedModel(const QString& path)
{
  vtkPointSet* deformed = this->deformedModel();
  if (!deformed || !this->hasWeights())
  {
    this->reportError("nothing to save: compute the weights first");
    return false;
  }
  if (!this->reporting([&]() { vtkBaryDataIO::Write(deformed, path.toStdString()); }))
    return false;
  this->statusBar()->showMessage("Saved the deformed model to " + path);
  return true;
}

// ------------------------------------------------------------------------------------------
// dragging control points in the view

void ViewerWindow::onControlPressed(int id)
{
  if (this->shownMode().componentsAreControlPoints() && id < this->componentCount())
    this->selectControl(id);
  if (!this->hasWeights())
    return;
  this->State.pushUndo();
  this->ViewPair->startDrag(id);
  this->Panel->setMoveId(id);
}

void ViewerWindow::onControlDragged(int id, const double* world)
{
  double x[3] = { world[0], world[1], world[2] };
  if (this->Options.dimension == 2)
    x[2] = this->posedControls()->GetPoint(id)[2];
  this->moveControlLive(id, x);
}

// ------------------------------------------------------------------------------------------
// sessions, screenshots, command line

bool ViewerWindow::saveSession(const QString& path)
{
  const bool saved = this->reporting([&]() {
    SessionFile file;
    file.inputs = this->inputs();
    file.parameters = this->Parameters;
    file.compare_method = this->CompareMethod;
    file.selected = this->Options.component;
    file.view = this->Options;
    file.pose = this->State.posedControls();
    json document = SessionToJson(file);
    this->shownMode().writeSession(this->State, document);
    WriteJson(document, path.toStdString());
  });
  if (saved)
    this->statusBar()->showMessage("Saved the session to " + path);
  return saved;
}

bool ViewerWindow::loadSession(const QString& path)
{
  SessionFile file;
  if (!this->reporting([&]() { file = ReadSessionFile(path); }))
    return false;
  this->Parameters = file.parameters;
  this->CompareMethod = file.compare_method;
  this->compareView()->setVisible(!this->CompareMethod.isEmpty());
  if (!this->openInputs(file.inputs))
    return false;
  // BBW's shape-preservation brush, painted on the domain mesh (SkeletonMode)
  if (!file.shape_brush.empty() &&
    !this->reporting([&]() { SkeletonMode::SetShapeBrush(this->State.domain(), file.shape_brush); }))
    return false;
  const SceneOptions& v = file.view;
  this->Options.field = v.field == SceneOptions::Field::Image && !this->State.picture()
    ? SceneOptions::Field::Weight
    : v.field;
  this->Options.log_scale = v.log_scale;
  this->Options.isolines = v.isolines;
  this->Options.influence_level = v.influence_level;
  this->Options.clip = v.clip;
  this->Options.clip_axis = v.clip_axis;
  this->Options.clip_position = v.clip_position;
  this->Options.component = 0;
  this->State.setPending(file.pose, file.twists);
  this->PendingSelection = file.selected;
  this->Panel->sync();
  this->compute();
  return true;
}

bool ViewerWindow::saveScreenshot(const QString& path)
{
  this->renderViews();
  QApplication::processEvents();
  const QImage image = this->grab().toImage();
  if (image.isNull() || !image.save(path, "PNG"))
  {
    this->reportError("cannot write the screenshot '" + path + "'");
    return false;
  }
  this->statusBar()->showMessage("Saved " + path);
  return true;
}

QString ViewerWindow::commandLine() const
{
  if (!this->State.controls())
    return QString();
  QStringList args = { "barylab", "weights" };
  for (const std::string& f : CommandLineFlags(this->Parameters))
    args << ShellQuoted(QString::fromStdString(f));
  args << this->currentMode().commandLineInputs(this->inputs());
  args << "--points" << ShellQuoted(this->inputs().model) << "--output" << "weights.vtp"
       << "--json" << "weights.json";
  return args.join(' ');
}

void ViewerWindow::showCommandLine()
{
  const QString line = this->commandLine();
  if (line.isEmpty())
  {
    this->reportError("open inputs first: there is no command line to show");
    return;
  }
  if (!this->Interactive)
  {
    this->statusBar()->showMessage(line);
    return;
  }
  ShowCommandLineDialog(this, line);
}

// ------------------------------------------------------------------------------------------
// locality statistics

LocalityPanel* ViewerWindow::localityPanel() const
{
  return this->Locality->panel();
}

const json& ViewerWindow::localityStatistics() const
{
  return this->Locality->panel()->statistics();
}

bool ViewerWindow::isLocalityShown() const
{
  return this->Locality && this->Locality->isVisible();
}

void ViewerWindow::showLocality(bool on)
{
  this->Locality->setShown(on);
}

bool ViewerWindow::exportLocalityCsv(const QString& prefix)
{
  if (!this->reporting([&]() { this->Locality->writeCsv(prefix); }))
    return false;
  this->statusBar()->showMessage("Wrote " + prefix + "_P.csv and " + prefix + "_Q.csv");
  return true;
}

bool ViewerWindow::exportLocalityPng(const QString& path)
{
  if (!this->reporting([&]() { this->Locality->writePng(path); }))
    return false;
  this->statusBar()->showMessage("Wrote " + path);
  return true;
}

} // namespace viewer
} // namespace barylab
