#pragma once
/// @file barylabViewerSurfaceMode.h
/// The viewer's surface mode: weighted averages on a surface (Panozzo et al. 2013). A window of
/// its own (the main window's Modes deform a model by controls; here the controls live on the
/// surface itself): anchors are clicked onto the mesh and dragged on it, their weights are
/// edited with sliders and the weighted average (the forward problem) follows live; a cubic
/// B-spline is drawn on the surface from control points dragged on it (§4.1); the surface is
/// coloured by the selected anchor's weight (the inverse problem at every vertex, left
/// uncoloured where the round trip does not return, §4.4) or carries a picture as a decal whose
/// texture coordinates come from the inverse problem (§4.2); and a second mesh with
/// corresponding anchors is shown beside it (§4.3): the average's image, the shown field
/// transferred through the correspondence, and its stretch and flipped triangles.
///
/// A thin shell over the BaryLabSurface filters (one instance of each is kept, so the Phong
/// precomputation is made once per surface and moving an anchor costs only the queries). Every
/// user action is a public slot, so tests and scripts drive the window as a person does.
///
/// In the view: Ctrl + left click on the surface adds an anchor (or a curve point, when editing
/// the curve); pressing on an anchor or curve point and dragging moves it on the surface (the
/// point under the mouse); the rest of the mouse moves the camera.

#include <QMainWindow>
#include <QString>
#include <QStringList>

#include "vtkSmartPointer.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <vector>

class QVTKOpenGLNativeWidget;
class vtkImageData;
class vtkPoints;
class vtkPolyData;
class vtkRenderer;
class vtkRenderWindow;

namespace barylab
{
namespace viewer
{

/// What a Ctrl + click adds and a drag moves.
enum class SurfaceEdit
{
  Anchors,
  Curve
};

/// What colours the surface (and, through the correspondence, the target).
enum class SurfaceField
{
  None,         ///< plain surface
  AnchorWeight, ///< the selected anchor's weight (inverse problem at every vertex)
  Decal         ///< the picture, texture coordinates from the anchors' uv (inverse problem)
};

/// A weighted average found on a surface (or not: valid false).
struct SurfaceAverage
{
  bool valid = false;
  double point[3] = { 0.0, 0.0, 0.0 };
  long long face = -1;
  double barycentric[3] = { 0.0, 0.0, 0.0 };
};

class SurfaceWindow : public QMainWindow
{
  Q_OBJECT
public:
  explicit SurfaceWindow(QWidget* parent = nullptr);
  ~SurfaceWindow() override;

  /// The bundled surface examples (name: description), for --example and the File menu.
  static QStringList ExampleNames();
  static bool IsExample(const QString& name);

  // --- state, for tests and scripts ---------------------------------------------------------
  /// The surface with its `Embedding` array (null before openSurface).
  vtkPolyData* surface() const;
  /// The embedding's figures (landmarks, stress, quality, seconds), empty when read from a file.
  const nlohmann::json& embeddingSummary() const;
  vtkPoints* anchors() const;
  int anchorCount() const;
  int selectedAnchor() const { return this->Selected; }
  /// The weights as edited (one per anchor); the average uses them divided by their sum.
  const std::vector<double>& weights() const { return this->Weights; }
  std::vector<double> normalizedWeights() const;
  const SurfaceAverage& average() const { return this->Average; }
  /// The surface with `Weights`, `Defined` (and `TCoords` for the decal): the shown field;
  /// null when SurfaceField::None or no anchors.
  vtkPolyData* field() const;
  vtkPoints* curveControls() const;
  /// The B-spline's samples and polyline (null with fewer than 4 control points, or 3 closed).
  vtkPolyData* curve() const;
  bool curveClosed() const { return this->CurveClosed; }
  SurfaceField fieldShown() const { return this->Field; }
  SurfaceEdit editing() const { return this->Editing; }
  /// The semiregular quad mesh (§4.1, Fig. 7) of the quad layout opened (null when none).
  vtkPolyData* remeshed() const;
  int remeshLevels() const;
  /// The target (null when none) and its result: the average with the same weights on the
  /// target's anchors, the field transferred (vtkBarySurfaceCorrespondence's output).
  vtkPolyData* target() const;
  const SurfaceAverage& targetAverage() const { return this->TargetAverage; }
  vtkPolyData* transferred() const;
  /// Counts of the last transfer: undefined points, flipped triangles; the stretch of the best
  /// 95% of triangles (NaN before any).
  const nlohmann::json& transferSummary() const { return this->TransferSummary; }
  const QStringList& errors() const { return this->Errors; }
  QVTKOpenGLNativeWidget* view() const;
  QVTKOpenGLNativeWidget* targetView() const;
  vtkRenderer* renderer() const;
  vtkRenderer* targetRenderer() const;
  /// The views rendered offscreen at @p width x @p height (the surface left, the target right
  /// when there is one), for regression images: the same actors and cameras as on screen.
  vtkSmartPointer<vtkRenderWindow> snapshot(int width, int height);
  /// Interactive (default): errors also open a message box. Off for tests and --screenshot.
  void setInteractive(bool on) { this->Interactive = on; }

public slots:
  /// Reads the mesh, and its embedding from @p embedding (text or .vtp, as `barylab embed`
  /// writes) or computes it (the defaults of `barylab embed`). Clears anchors, curve, target.
  bool openSurface(const QString& mesh, const QString& embedding = QString());
  /// torus-averages: the bundled torus with its anchors, the first row of weights, the curve,
  /// a second torus with corresponding anchors and the gingerbread picture.
  bool loadExample(const QString& name);
  /// Anchors from a file (text x y z a line, or a data file's points): replaces the anchors;
  /// weights uniform.
  bool openAnchors(const QString& path);
  /// Row @p row of a text matrix of weights (one column per anchor).
  bool openWeights(const QString& path, int row = 0);
  /// Adds an anchor at the surface point closest to (x, y, z) (weight 1 / n, where n is the new
  /// count, the others scaled to keep their proportions); its index, or -1 with an error
  /// when the point is off the surface.
  int addAnchor(double x, double y, double z);
  /// Moves anchor @p i to the surface point closest to (x, y, z).
  bool moveAnchor(int i, double x, double y, double z);
  bool removeAnchor(int i);
  void selectAnchor(int i);
  /// Weight of anchor @p i (any real; the average uses the weights over their sum, which must
  /// not be 0).
  bool setWeight(int i, double w);
  bool setWeights(const std::vector<double>& w);
  void setEditing(barylab::viewer::SurfaceEdit edit);
  void setField(barylab::viewer::SurfaceField field);
  /// The decal's picture (PNG, JPEG, ...); the bundled gingerbread picture by default.
  bool openPicture(const QString& path);
  /// B-spline control points from a file (as openAnchors).
  bool openCurve(const QString& path);
  int addCurvePoint(double x, double y, double z);
  bool moveCurvePoint(int i, double x, double y, double z);
  bool removeCurvePoint(int i);
  void setCurveClosed(bool closed);
  void setCurveSamples(int samples_per_segment);
  /// A coarse quad layout on the surface (its vertices on the surface, polygons all quads):
  /// remeshed semiregularly (vtkBarySurfaceRemesh) and drawn as a wireframe.
  bool openQuadLayout(const QString& path);
  void setRemeshLevels(int levels);
  void closeQuadLayout();
  /// A second mesh and its anchors (as many as this surface's, corresponding in order), with
  /// its embedding read from @p embedding or computed: shown beside the surface.
  bool openTarget(const QString& mesh, const QString& anchors, const QString& embedding = QString());
  void closeTarget();
  /// The curve's samples (.vtp, or text x y z a line).
  bool saveCurve(const QString& path);
  bool saveScreenshot(const QString& path);
  void resetCamera();

signals:
  void errorReported(const QString& message);
  void sceneUpdated();

private:
  struct Internals;
  std::unique_ptr<Internals> I;

  void buildPanel();
  void buildMenus();
  void reportError(const QString& message);
  template <class Action>
  bool reporting(Action&& action);
  /// Recomputes what depends on the anchors / weights / curve (@p what: bit set of Changed)
  /// and redraws.
  void update(int what);
  void updateAverage();
  void updateField();
  void updateCurve();
  void updateTargetAverage();
  void updateTarget();
  void updateRemesh();
  void updateScene();
  /// Fills @p left with the surface's scene and @p right (may be null) with the target's.
  void drawScene(vtkRenderer* left, vtkRenderer* right);
  void updatePanel();
  void installInteraction();
  bool pickSurface(int x, int y, double world[3]) const;
  int pickPoint(vtkPoints* points, int x, int y) const;

  std::vector<double> Weights;
  int Selected = -1;
  SurfaceAverage Average;
  SurfaceAverage TargetAverage;
  nlohmann::json TransferSummary;
  bool CurveClosed = true;
  SurfaceField Field = SurfaceField::AnchorWeight;
  SurfaceEdit Editing = SurfaceEdit::Anchors;
  QStringList Errors;
  bool Interactive = true;
  bool CameraNeedsReset = true;
};

} // namespace viewer
} // namespace barylab
