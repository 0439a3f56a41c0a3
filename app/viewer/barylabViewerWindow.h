#pragma once
/// @file barylabViewerWindow.h
/// barylab-viewer's main window: a thin shell over barylab::WeightsParameters and the pipeline
/// builder (ComputeWeights, Deform, Skin). Every user action is a public slot, so tests (and
/// scripts) drive the window exactly as a person does. No algorithm code here. The inputs,
/// weights and pose live in a Session; what differs between families of methods (cage,
/// skeleton, free points) is asked of their Mode; the side panel is a ControlPanel.

#include "barylabPipeline.h"
#include "barylabViewerCompute.h"
#include "barylabViewerScene.h"
#include "barylabViewerSession.h"

#include <QMainWindow>
#include <QStringList>

#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkPoints.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"

#include <vector>

class QProgressBar;
class QVTKOpenGLNativeWidget;

namespace barylab
{
namespace viewer
{
class ControlPanel;
class LocalityDock;
class LocalityPanel;
class Mode;
class Views;

class ViewerWindow : public QMainWindow
{
  Q_OBJECT
public:
  explicit ViewerWindow(QWidget* parent = nullptr);
  ~ViewerWindow() override;

  /// Bundled examples: name -> description (the File > Examples menu).
  static QStringList ExampleNames();

  // --- state, for tests and scripts ---------------------------------------------------------
  bool isComputing() const { return this->Runner.isBusy(); }
  bool hasWeights() const { return this->State.weighted() != nullptr; }
  vtkDataSet* weighted() const { return this->State.weighted(); }
  vtkDataSet* compareWeighted() const { return this->State.compareWeighted(); }
  /// The model at the current pose (the rest model when nothing was moved).
  vtkPointSet* deformedModel() const { return this->State.deformedModel(); }
  vtkPolyData* controls() const { return this->State.controls(); }
  vtkPoints* posedControls() const { return this->State.posedControls(); }
  /// The inputs, weights and pose.
  const Session& session() const { return this->State; }
  /// The mode of the current method (cage, skeleton, free points).
  const Mode& currentMode() const;
  /// The mode of the weights shown (the current method's before any weights).
  const Mode& shownMode() const;
  /// What the controls are for the current method (cage, skeleton, free points).
  ControlKind controlKind() const;
  /// What the controls were for the weights shown (the current method before any weights).
  ControlKind shownKind() const;
  int selectedControl() const { return this->Options.component; }
  int componentCount() const { return this->State.componentCount(this->Parameters.weights_name); }
  const WeightsParameters& parameters() const { return this->Parameters; }
  const Inputs& inputs() const { return this->State.inputs(); }
  const SceneOptions& sceneOptions() const { return this->Options; }
  const SceneInfo& sceneInfo() const { return this->Info; }
  QString compareMethod() const { return this->CompareMethod; }
  /// Every error reported so far (also shown in the status bar, and in a dialog when
  /// interactive).
  const QStringList& errors() const { return this->Errors; }
  double lastComputeSeconds() const { return this->LastSeconds; }
  /// Seconds the last control point edit took to update the weights (addControlPointAt,
  /// removeControlPoint).
  double lastEditSeconds() const { return this->LastEditSeconds; }
  std::size_t undoDepth() const { return this->State.undoDepth(); }
  /// BBW handle @p handle's rotation / scale (identity when none or out of range).
  HandleTwist handleTwist(int handle) const { return this->State.twist(handle); }
  /// The equivalent `barylab weights ...` command line.
  QString commandLine() const;
  QVTKOpenGLNativeWidget* view() const;
  QVTKOpenGLNativeWidget* compareView() const;
  vtkRenderer* renderer() const;
  vtkRenderer* compareRenderer() const;

  /// The locality charts (P(t), Q(k)) and the statistics they show (an array of
  /// barylab::LocalityStatisticsJson objects with "method"; empty before showLocality()).
  LocalityPanel* localityPanel() const;
  const nlohmann::json& localityStatistics() const;
  bool isLocalityShown() const;

  /// Interactive (default): errors also open a message box. Off for tests and --screenshot.
  void setInteractive(bool on) { this->Interactive = on; }
  /// Synchronous: compute() runs in the calling thread (--screenshot, scripts).
  void setSynchronous(bool on) { this->Runner.setSynchronous(on); }

public slots:
  /// Opens CONTROLS MODEL [DOMAIN] (a .tgf CONTROLS file is a BBW skeleton and needs DOMAIN).
  bool openFiles(const QStringList& files);
  bool openInputs(const barylab::viewer::Inputs& inputs);
  /// gingerbread-mvc, kidney-mvc, gingerbread-bbw, heart-scc; computes unless @p compute is
  /// false.
  bool loadExample(const QString& name, bool compute = true);
  void setMethod(const QString& method);
  /// Sets one parameter by its table key (WeightsParameterFields); false and an error if the
  /// key is unknown or the value has the wrong type.
  bool setParameter(const QString& key, const QVariant& value);
  void setParameters(const barylab::WeightsParameters& parameters);
  /// Second method shown side by side with linked cameras ("" = none).
  void setCompareMethod(const QString& method);
  /// Computes the weights (in a worker thread unless synchronous); emits computeFinished.
  void compute();
  void cancel();
  /// Waits (processing events) until no computation runs; false on timeout.
  bool waitForComputation(int timeout_ms = 60000);

  void selectControl(int component);
  void showWeight();
  void showGradientNorm();
  /// 2D image mode: the picture warped by the deformation (needs a picture as the model).
  void showImage();
  void setLogScale(bool on);
  void setIsolines(int count);
  void setInfluenceLevel(bool on);
  void setClipping(bool on);
  void setClipAxis(int axis);
  void setClipPosition(double fraction);
  void resetCamera();
  /// Shows (computing them) or hides the locality charts P(t), Q(k) of the shown method and
  /// the comparison method (the LBC paper's Fig. 14-15).
  void showLocality(bool on = true);
  /// PREFIX_P.csv and PREFIX_Q.csv (columns as `barylab stats --locality --csv`).
  bool exportLocalityCsv(const QString& prefix);
  /// Both charts side by side, 1000 x 420 pixels.
  bool exportLocalityPng(const QString& path);

  /// Moves control @p id (cage / control point / skeleton joint) to (x, y, z); undoable.
  void setControlPosition(int id, double x, double y, double z);
  void resetPose();
  /// BBW (skeleton shown): rotates handle @p handle (weights component) by @p angle_degrees and
  /// scales it by @p scale about its posed centre (HandleTwist); undoable. False with an error
  /// for other controls, a handle out of range or a scale that is not > 0.
  bool setHandleTwist(int handle, double angle_degrees, double scale);
  void undo();

  /// Free control points (tcc, scc) with weights: adds a control point where the user clicks,
  /// along the view line (the celestial paper's Fig. 7). (@p x, @p y) is a display position
  /// (VTK's, origin bottom left; the view does a Ctrl + click). 3D: the first click defines the
  /// line through that pixel (drawn; rotate the view to see it); a later click within 12 pixels
  /// of the drawn line places the point at the point of the line nearest to the view ray
  /// through the click, and a click away from it starts a new line. 2D: the point is placed at
  /// once, in the controls' plane. The weights are then updated incrementally
  /// (FreePointsMode::EditedWeights; a failure, e.g. a point left outside, is reported and
  /// changes nothing); undoable. True when a point was added.
  bool addControlPointAt(double x, double y);
  /// Drops the view line of a point being added (Esc).
  void cancelAddControlPoint();
  /// Removes free control point @p id (not a hull point) and updates the weights; undoable.
  bool removeControlPoint(int id);

  /// The example's pose, or a pose file: posed cage / control points, or BBW transforms.
  bool loadPose(const QString& path);
  bool applyExamplePose();
  bool savePose(const QString& path);
  bool saveDeformedModel(const QString& path);
  bool saveSession(const QString& path);
  bool loadSession(const QString& path);
  // --- the organ workflow (docs/organ-workflow.md; barylabViewerOrgan.cxx) -----------------
  /// Reads a label map (NIfTI, NRRD, MetaImage), extracts label @p label's closed surface in
  /// LPS (vtkBaryLabelMapSurface; 0: the image's only label), makes a cage of about
  /// @p cage_vertices vertices around it (vtkBaryEnclosingCage), writes both into @p folder
  /// (default: organFolder()) as <image>_label<K>_surface.vtp and <image>_label<K>_cage.obj and
  /// opens them as the cage and the model. The label map is kept: saveTransform() takes its
  /// grid and saveWarpedLabelMap() warps it.
  bool openLabelMap(const QString& image, long long label = 0, int cage_vertices = 60,
    const QString& folder = QString());
  /// A new cage of about @p vertices vertices around the current model (vtkBaryEnclosingCage),
  /// written to @p path (default: <organFolder()>/<model>_cage<N>.obj) and opened with the
  /// model. The weights are computed again by Compute.
  bool makeCage(int vertices, const QString& path = QString());
  /// The deformation shown (the weights' method, the controls at rest and at the current
  /// pose) as a displacement field T(x) = x + u(x) in LPS (what ITK and 3D Slicer load as a grid
  /// transform), written to @p path (.mha, .mhd, .nii, .nii.gz, .nrrd), and its inverse to
  /// @p inverse_path if given. The grid is the label map's (openLabelMap), else the cage's
  /// bounds grown by a tenth on every side with @p spacing (0: a 64th of the bounds' longest
  /// side). Not for BBW skeletons (a cage or free control points).
  bool saveTransform(const QString& path, const QString& inverse_path = QString(), double spacing = 0.0);
  /// The label map of openLabelMap() warped into the deformed space (nearest neighbour: the
  /// labels kept), on its own grid, written to @p path.
  bool saveWarpedLabelMap(const QString& path);
  /// The label map opened by openLabelMap() (null otherwise) and its file.
  vtkImageData* labelMap() const { return this->LabelMap; }
  const QString& labelMapPath() const { return this->LabelMapPath; }
  /// Where openLabelMap() and makeCage() write by default: the application's data folder's
  /// "organ" folder.
  static QString organFolder();

  bool saveScreenshot(const QString& path);
  void showCommandLine();

signals:
  void computeFinished(bool ok);
  void errorReported(const QString& message);
  void sceneUpdated();

private:
  void finishCompute(const ComputeResult& result);
  void buildViews();
  void reportError(const QString& message);
  /// Runs @p action; a bary::Error or other exception it throws is reported: false.
  template <class Action>
  bool reporting(Action&& action, const QString& prefix = QString());
  void updateControlList();
  /// The pose changed: deforms the weighted models to it (errors reported) and redraws.
  void poseChanged();
  void updateScene();
  void renderViews();
  void moveControlLive(int id, const double x[3]);
  /// Display options changed: panel and scene follow.
  void optionsChanged();
  /// A click on control @p id in the view: selects it (when a control point is a weight) and
  /// starts a drag (one undo step) when there are weights to deform with.
  void onControlPressed(int id);
  void onControlDragged(int id, const double* world);

  Session State;
  WeightsParameters Parameters;
  QString CompareMethod;
  SceneOptions Options;
  SceneInfo Info;
  int PendingSelection = -1; ///< applied when a computation finishes (example, session load)

  QStringList Errors;
  vtkSmartPointer<vtkImageData> LabelMap; ///< openLabelMap's image (the transform's grid)
  QString LabelMapPath;
  bool Interactive = true;
  double LastSeconds = 0.0;
  double LastEditSeconds = 0.0;
  /// New controls (rest and posed) for the weights shown: weights updated, undoable.
  bool editControls(vtkSmartPointer<vtkPolyData> controls, vtkSmartPointer<vtkPoints> posed,
    int select, const QString& what);
  bool CameraNeedsReset = true;

  ComputeRunner Runner; ///< declared after the session: a worker still running stops first

  // widgets
  ControlPanel* Panel = nullptr;
  LocalityDock* Locality = nullptr;
  Views* ViewPair = nullptr;
  QProgressBar* ProgressBar = nullptr;
};

} // namespace viewer
} // namespace barylab
