#pragma once
/// @file barylabViewerSplineMode.h
/// The viewer's spline mode: C1 spline deformations edited by DECLeS (Rodrigues, Stolfi,
/// Gomide 2014, §4-§5). A window of its own: the deformed grid (the Bézier triangles' curved
/// edges), the control points, the deformed model and a background picture to match, seen
/// from above. The three editing modes of the 2.5D deformation (§5): xy (the deformation phi),
/// bottom and top (the surfaces sigma0, sigma1: the model coloured by z, and a side view of it
/// with the two surfaces' section through the selected point).
///
/// In the view: pressing on a control point and dragging moves it (xy: to the mouse; bottom /
/// top: up or down by the mouse's vertical motion, scaled so that the domain's height is the
/// prism's) with its slaves within
/// delta_max (Shift + click adds points to the selection, and a drag on a selected point moves
/// all of them: several anchors); each mouse move re-applies the drag's edit from the drag's start (the previous
/// move's edit undone first), so the grid and the model follow live and one drag is one undo
/// step. Ctrl + left click picks the centre of rotations and scales. The rest of the mouse
/// moves the camera (2D: pan and zoom).
///
/// A thin shell over bary::SplineEditor (one per spline: xy, bottom, top, as vtkBarySplineEdit)
/// and TriangularSpline::evaluate (the model's points located once). Every user action is a
/// public slot, so tests and scripts drive the window as a person does.

#include <QMainWindow>
#include <QString>
#include <QStringList>

#include "vtkSmartPointer.h"

#include <memory>
#include <string>
#include <vector>

class QVTKOpenGLNativeWidget;
class vtkPoints;
class vtkPolyData;
class vtkRenderer;
class vtkRenderWindow;
struct vtkBarySpline;

namespace bary
{
class TriangularSpline;
class SplineEditor;
struct SplineEdit;
}

namespace barylab
{
namespace viewer
{

/// Which spline the edits change (vtkBarySplineEdit's targets).
enum class SplineTarget
{
  XY = 0,     ///< the deformation phi
  Bottom = 1, ///< the 2.5D bottom surface sigma0
  Top = 2     ///< the 2.5D top surface sigma1
};

class SplineWindow : public QMainWindow
{
  Q_OBJECT
public:
  explicit SplineWindow(QWidget* parent = nullptr);
  ~SplineWindow() override;

  /// The bundled spline examples, for --example and the File menu.
  static QStringList ExampleNames();
  static bool IsExample(const QString& name);

  // --- state, for tests and scripts ---------------------------------------------------------
  bool hasSpline() const;
  bool isPrism() const;
  /// The spline @p t (null when none: no spline, or bottom / top of a 2D deformation).
  const bary::TriangularSpline* spline(SplineTarget t = SplineTarget::XY) const;
  /// Its editor (null as spline()).
  bary::SplineEditor* editor(SplineTarget t = SplineTarget::XY) const;
  SplineTarget target() const { return this->Target; }
  /// The control point picked last (-1: none), and every selected one (the anchors of the next
  /// drag, translation, rotation or scale; the last picked at the end).
  int selectedPoint() const { return this->Selected; }
  const std::vector<int>& selection() const { return this->Selection; }
  int deltaMax() const { return this->DeltaMax; }
  bool hasCentre() const { return this->HasCentre; }
  const double* centre() const { return this->Centre; }
  /// The model at rest and deformed (same ids; null when none).
  vtkPolyData* model() const;
  vtkPolyData* deformedModel() const;
  /// The deformed grid: one polyline per domain edge, sampled and mapped by phi.
  vtkPolyData* deformedGrid() const;
  /// The control points where they are drawn (phi's control points).
  vtkPoints* controlPoints() const;
  /// Triangles where the Jacobian is <= 0 (check_jacobian), and the smallest value found.
  const std::vector<long long>& foldedTriangles() const { return this->Folded; }
  double minJacobian() const { return this->MinJacobian; }
  /// The warning shown in the panel ("" when phi is positive everywhere).
  QString warning() const;
  /// Seconds of the last edit (DECLeS) and of the update that followed it (model, grid,
  /// Jacobian test, redraw).
  double lastEditSeconds() const { return this->EditSeconds; }
  double lastUpdateSeconds() const { return this->UpdateSeconds; }
  /// Of which the Jacobian test (check_jacobian, and the folded triangles' fill).
  double lastJacobianSeconds() const { return this->JacobianSeconds; }
  bool canUndo() const;
  bool canRedo() const;
  const QStringList& errors() const { return this->Errors; }
  QVTKOpenGLNativeWidget* view() const;
  vtkRenderer* renderer() const;
  /// The side view of the bottom / top modes (drawn only in them): the model from -y and the
  /// bottom and top surfaces along the selected point's row (sectionData()).
  vtkRenderer* sideRenderer() const;
  vtkPolyData* sectionData() const;
  /// The view rendered offscreen at @p width x @p height, for regression images: the same
  /// actors and camera as on screen.
  vtkSmartPointer<vtkRenderWindow> snapshot(int width, int height);
  /// Interactive (default): errors also open a message box. Off for tests and --screenshot.
  void setInteractive(bool on) { this->Interactive = on; }

public slots:
  /// A spline grid (.vtu, as `barylab spline create|edit` write). Keeps the model when it lies
  /// in the new domain; clears the edit history.
  bool openSpline(const QString& path);
  /// The model (a point set or surface) in the spline's domain (and, for a 2.5D spline, within
  /// its prism).
  bool openModel(const QString& path);
  /// A picture placed on the domain's bounding rectangle.
  bool openPicture(const QString& path);
  /// organism-spline: the domain data/spline_domain.obj as an identity 2.5D spline with the
  /// prism [-0.1, 0.1], the organism and its picture.
  bool loadExample(const QString& name);
  void setTarget(barylab::viewer::SplineTarget t);
  /// delta_max of the next edits, [0, kMaxDeltaMax].
  void setDeltaMax(int delta_max);
  /// Selects control point @p i alone (-1: none).
  void selectPoint(int i);
  /// Adds @p i to the selection, or removes it when it is in it (Shift + click).
  void toggleSelection(int i);
  /// The centre of rotations and scales.
  void setCentre(double x, double y);
  /// xy: moves control point @p i by (dx, dy) (a Translate edit with delta_max); bottom / top:
  /// raises it by dz = dx (dy ignored).
  bool translatePoint(int i, double dx, double dy);
  /// xy: moves control point @p i to (x, y).
  bool movePointTo(int i, double x, double y);
  /// Translates the selected points together (xy: by (dx, dy); bottom / top: by dz = dx).
  bool translateSelection(double dx, double dy);
  /// Rotates the selected points about the centre by @p degrees (xy).
  bool rotateSelected(double degrees);
  /// Scales the selected points about the centre by @p factor (xy).
  bool scaleSelected(double factor);
  /// Undo / redo of the last edit, whichever spline it changed.
  bool undo();
  bool redo();
  /// The spline (.vtu, Bézier triangles) and the deformed model (any format vtkBaryDataIO
  /// writes).
  bool saveSpline(const QString& path);
  bool saveDeformedModel(const QString& path);
  bool saveScreenshot(const QString& path);
  void resetCamera();

signals:
  void errorReported(const QString& message);
  void sceneUpdated();

private:
  struct Internals;
  std::unique_ptr<Internals> I;

  /// Edits @p spline from now on (validated; clears the history). @p name: for the panel.
  bool useSpline(const vtkBarySpline& spline, const QString& name);
  void buildPanel();
  void buildMenus();
  void reportError(const QString& message);
  template <class Action>
  bool reporting(Action&& action);
  /// Applies @p edit to the spline of the current target (one undo step), then updates.
  bool applyEdit(const bary::SplineEdit& edit);
  /// After the splines changed: the model, the grid, the control points, the Jacobian test,
  /// the panel, the view.
  void update();
  void updateModel();
  void updateGrid();
  void updateJacobian();
  void updatePointColours();
  /// After the selection changed: Selected, colours, the section, the panel.
  void selectionChanged();
  void updatePanel();
  /// Fills the renderers: @p scene (picture, model), @p overlay (layer 1: grid, control points,
  /// folds, centre), @p side (may be null: the side view of the bottom / top modes), and sets
  /// their viewports.
  void drawScene(vtkRenderer* scene, vtkRenderer* overlay, vtkRenderer* side);
  /// The bottom and top surfaces along the selected point's row (2.5D), deformed.
  void updateSection();
  /// dz per world unit of a vertical drag (bottom / top): the domain's height is the prism's.
  double verticalScale() const;
  /// The colours' z range: the prism's, grown to the deformed model's.
  void zRange(double range[2]) const;
  void updateScene();
  /// The view's title: the mode, and whether the map folds.
  std::string titleText() const;
  /// The camera of resetCamera (from above, the domain fitted to the view), without rendering.
  void fitCamera();
  void installInteraction();
  int pickPoint(int x, int y) const;
  void displayToWorld(int x, int y, double world[2]) const;

  SplineTarget Target = SplineTarget::XY;
  int Selected = -1;
  std::vector<int> Selection;
  int DeltaMax = 4;
  bool HasCentre = false;
  double Centre[2] = { 0.0, 0.0 };
  std::vector<long long> Folded;
  double MinJacobian = 0.0;
  double EditSeconds = 0.0;
  double UpdateSeconds = 0.0;
  double JacobianSeconds = 0.0;
  QStringList Errors;
  bool Interactive = true;
  bool CameraNeedsReset = true;
};

} // namespace viewer
} // namespace barylab
