#pragma once
/// @file barylabViewerViews.h
/// The viewer's two VTK views: the weights shown and, beside it, the comparison method's, with
/// one camera for both. Clicking near a control point in the first view (12 pixels) and
/// dragging it is reported as signals in world coordinates, a Ctrl + click anywhere as
/// viewClicked; what a click or drag does is the window's (and its mode's) business. The view
/// line of a control point being added (Session::hasViewLine) is drawn as a yellow line. What they draw is a Session's weights (BuildScene).

#include <QObject>
#include <QString>

#include "vtkSmartPointer.h"

#include <functional>

class QSplitter;
class QVTKOpenGLNativeWidget;
class vtkCallbackCommand;
class vtkObject;
class vtkPoints;
class vtkRenderer;

namespace barylab
{
namespace viewer
{
class Session;
struct SceneInfo;
struct SceneOptions;

class Views : public QObject
{
  Q_OBJECT
public:
  /// Adds the views to @p splitter (the comparison view hidden); @p controls gives the control
  /// points at the current pose (or null), the ones a click picks.
  Views(QSplitter* splitter, std::function<vtkPoints*()> controls);
  ~Views() override;

  QVTKOpenGLNativeWidget* view() const { return this->View; }
  QVTKOpenGLNativeWidget* compareView() const { return this->CompareView; }
  vtkRenderer* renderer() const { return this->Renderer; }
  vtkRenderer* compareRenderer() const { return this->CompareRenderer; }

  /// Rebuilds the scenes (does not render): @p session's weights deformed to its pose in the
  /// first view and, when @p compare, the comparison weights in the second, drawn with
  /// @p options; the titles name the method, the field and @p control (the selected control's
  /// label, "" for none). @p info is set to the first view's as soon as it is built.
  /// @throws bary::Error (BuildScene)
  void build(const Session& session, SceneOptions options, const QString& control, bool compare,
    SceneInfo& info);
  /// Renders both views (the comparison view when visible).
  void render();
  /// Control @p id follows the mouse until the button is released (call on controlPressed).
  void startDrag(int id) { this->Dragging = id; }

signals:
  /// Left button pressed on control point @p id (the camera does not move).
  void controlPressed(int id);
  /// The control being dragged is under the mouse at @p world (x, y, z).
  void controlDragged(int id, const double* world);
  /// The drag of control @p id ended.
  void controlReleased(int id);
  /// Left button pressed with Ctrl at display position (@p x, @p y) (VTK's: origin bottom
  /// left): a control point to add there (the camera does not move).
  void viewClicked(int x, int y);

private:
  int pickControl(int x, int y) const;
  static void OnInteractorEvent(vtkObject* caller, unsigned long event, void* client, void* call);
  static void OnCameraModified(vtkObject* caller, unsigned long event, void* client, void* call);

  std::function<vtkPoints*()> Controls;
  QVTKOpenGLNativeWidget* View = nullptr;
  QVTKOpenGLNativeWidget* CompareView = nullptr;
  vtkSmartPointer<vtkRenderer> Renderer;
  vtkSmartPointer<vtkRenderer> CompareRenderer;
  vtkSmartPointer<vtkCallbackCommand> InteractorCallback;
  vtkSmartPointer<vtkCallbackCommand> CameraCallback;
  int Dragging = -1;
  bool SyncingCameras = false;
};

} // namespace viewer
} // namespace barylab
