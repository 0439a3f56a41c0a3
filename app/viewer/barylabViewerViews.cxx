#include "barylabViewerViews.h"

#include "barylabViewerScene.h"
#include "barylabViewerSession.h"

#include <QSplitter>
#include <QTimer>

#include <QVTKOpenGLNativeWidget.h>

#include "vtkActor.h"
#include "vtkCallbackCommand.h"
#include "vtkLineSource.h"
#include "vtkNew.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkCamera.h"
#include "vtkGenericOpenGLRenderWindow.h"
#include "vtkInteractorObserver.h"
#include "vtkPoints.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"

namespace barylab
{
namespace viewer
{

Views::Views(QSplitter* splitter, std::function<vtkPoints*()> controls)
  : QObject(splitter)
  , Controls(std::move(controls))
{
  this->Renderer = vtkSmartPointer<vtkRenderer>::New();
  this->CompareRenderer = vtkSmartPointer<vtkRenderer>::New();
  this->CompareRenderer->SetActiveCamera(this->Renderer->GetActiveCamera()); // linked cameras
  for (int k = 0; k < 2; ++k)
  {
    auto* widget = new QVTKOpenGLNativeWidget(splitter);
    vtkNew<vtkGenericOpenGLRenderWindow> window;
    window->SetMultiSamples(0);
    widget->setRenderWindow(window);
    window->AddRenderer(k == 0 ? this->Renderer : this->CompareRenderer);
    widget->setMinimumSize(320, 320);
    splitter->addWidget(widget);
    (k == 0 ? this->View : this->CompareView) = widget;
  }
  this->CompareView->hide();

  this->InteractorCallback = vtkSmartPointer<vtkCallbackCommand>::New();
  this->InteractorCallback->SetCallback(&Views::OnInteractorEvent);
  this->InteractorCallback->SetClientData(this);
  vtkRenderWindowInteractor* interactor = this->View->interactor();
  for (unsigned long e : { vtkCommand::LeftButtonPressEvent, vtkCommand::MouseMoveEvent,
         vtkCommand::LeftButtonReleaseEvent })
    interactor->AddObserver(e, this->InteractorCallback, 10.0f);
  this->CameraCallback = vtkSmartPointer<vtkCallbackCommand>::New();
  this->CameraCallback->SetCallback(&Views::OnCameraModified);
  this->CameraCallback->SetClientData(this);
  this->Renderer->GetActiveCamera()->AddObserver(vtkCommand::ModifiedEvent, this->CameraCallback);
}

Views::~Views()
{
  this->Renderer->GetActiveCamera()->RemoveObserver(this->CameraCallback);
}

void Views::build(const Session& session, SceneOptions options, const QString& control,
  bool compare, SceneInfo& info)
{
  const auto title = [&](const std::string& method) {
    std::string t = method + (options.field == SceneOptions::Field::Weight ? ": weight"
        : options.field == SceneOptions::Field::GradientNorm              ? ": |grad w|"
                                                                          : ": picture");
    if (!control.isEmpty())
      t += " of " + control.toStdString();
    return t;
  };
  vtkDataSet* weighted = session.weighted();
  options.title = weighted ? title(MethodName(session.computed())) : std::string();
  vtkPointSet* deformed = session.deformedModel();
  info = BuildScene(this->Renderer, weighted, weighted && deformed ? deformed->GetPoints() : nullptr,
    session.controls(), session.posedControls(), options);
  if (session.hasViewLine())
  {
    vtkNew<vtkLineSource> line;
    line->SetPoint1(session.viewLineStart());
    line->SetPoint2(session.viewLineEnd());
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(line->GetOutputPort());
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(0.95, 0.8, 0.1);
    actor->GetProperty()->SetLineWidth(3.0);
    this->Renderer->AddActor(actor);
  }
  if (!compare)
    return;
  vtkDataSet* compared = session.compareWeighted();
  vtkPointSet* compareDeformed = session.compareDeformed();
  options.title = compared ? title(session.computedCompare().toStdString()) : std::string();
  BuildScene(this->CompareRenderer, compared,
    compareDeformed ? compareDeformed->GetPoints() : nullptr, session.controls(),
    session.posedControls(), options);
}

void Views::render()
{
  this->SyncingCameras = true;
  this->Renderer->ResetCameraClippingRange();
  this->View->renderWindow()->Render();
  if (this->CompareView->isVisible())
  {
    this->CompareRenderer->ResetCameraClippingRange();
    this->CompareView->renderWindow()->Render();
  }
  this->View->update();
  this->CompareView->update();
  this->SyncingCameras = false;
}

void Views::OnCameraModified(vtkObject*, unsigned long, void* client, void*)
{
  auto* self = static_cast<Views*>(client);
  if (self->SyncingCameras || !self->CompareView->isVisible())
    return;
  // the cameras are one object; re-render the other view once the interaction step is done
  QTimer::singleShot(0, self, [self]() {
    self->SyncingCameras = true;
    self->CompareRenderer->ResetCameraClippingRange();
    self->CompareView->renderWindow()->Render();
    self->CompareView->update();
    self->SyncingCameras = false;
  });
}

int Views::pickControl(int x, int y) const
{
  vtkPoints* posed = this->Controls();
  if (!posed)
    return -1;
  int best = -1;
  double bestD2 = 12.0 * 12.0; // pixels
  for (vtkIdType i = 0; i < posed->GetNumberOfPoints(); ++i)
  {
    double p[3];
    posed->GetPoint(i, p);
    this->Renderer->SetWorldPoint(p[0], p[1], p[2], 1.0);
    this->Renderer->WorldToDisplay();
    const double* d = this->Renderer->GetDisplayPoint();
    const double d2 = (d[0] - x) * (d[0] - x) + (d[1] - y) * (d[1] - y);
    if (d2 < bestD2)
    {
      bestD2 = d2;
      best = static_cast<int>(i);
    }
  }
  return best;
}

void Views::OnInteractorEvent(vtkObject* caller, unsigned long event, void* client, void*)
{
  auto* self = static_cast<Views*>(client);
  auto* interactor = static_cast<vtkRenderWindowInteractor*>(caller);
  int pos[2];
  interactor->GetEventPosition(pos);
  if (event == vtkCommand::LeftButtonPressEvent && interactor->GetControlKey())
  {
    self->InteractorCallback->AbortFlagOn();
    emit self->viewClicked(pos[0], pos[1]);
  }
  else if (event == vtkCommand::LeftButtonPressEvent)
  {
    const int id = self->pickControl(pos[0], pos[1]);
    if (id < 0)
      return; // the camera moves
    self->InteractorCallback->AbortFlagOn();
    emit self->controlPressed(id);
  }
  else if (event == vtkCommand::MouseMoveEvent && self->Dragging >= 0)
  {
    self->InteractorCallback->AbortFlagOn();
    double p[3];
    self->Controls()->GetPoint(self->Dragging, p);
    double display[3];
    vtkInteractorObserver::ComputeWorldToDisplay(self->Renderer, p[0], p[1], p[2], display);
    double world[4];
    vtkInteractorObserver::ComputeDisplayToWorld(self->Renderer, pos[0], pos[1], display[2], world);
    emit self->controlDragged(self->Dragging, world);
  }
  else if (event == vtkCommand::LeftButtonReleaseEvent && self->Dragging >= 0)
  {
    self->InteractorCallback->AbortFlagOn();
    const int id = self->Dragging;
    self->Dragging = -1;
    emit self->controlReleased(id);
  }
}

} // namespace viewer
} // namespace barylab
