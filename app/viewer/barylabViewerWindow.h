#pragma once
/// @file barylabViewerWindow.h
/// barylab-viewer's main window: a thin shell over barylab::WeightsParameters and the pipeline
/// builder (ComputeWeights, Deform, Skin). Every user action is a public slot, so tests (and
/// scripts) drive the window exactly as a person does. No algorithm code here.

#include "barylabPipeline.h"
#include "barylabViewerScene.h"

#include <QFutureWatcher>
#include <QMainWindow>
#include <QStringList>

#include "vtkCallbackCommand.h"
#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkPoints.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"

#include <atomic>
#include <memory>
#include <vector>

class QCheckBox;
class QDockWidget;
class QComboBox;
class QDoubleSpinBox;
class QVBoxLayout;
class QLabel;
class QListWidget;
class QProgressBar;
class QPushButton;
class QSlider;
class QSpinBox;
class QVTKOpenGLNativeWidget;
class vtkObject;

namespace barylab
{
namespace viewer
{
class LocalityPanel;

/// The files a session works on.
struct Inputs
{
  QString controls; ///< cage, skeleton (.tgf: BBW handles) or free control points
  QString model;    ///< the points / mesh the weights are computed at (and that is deformed)
  QString domain;   ///< BBW with a skeleton: the polygon / closed surface / tet mesh to mesh
  QString example;  ///< bundled example name, if opened from the menu
  QString pose;     ///< the example's pose file (cage, control points or transforms)
};

/// A rotation and uniform scale of one BBW handle about its posed centre (a point handle's
/// position, a bone's first joint), applied after the pose that the joints give: 2D about z;
/// 3D about the bone's axis (a twist), for point handles about z.
struct HandleTwist
{
  double angle_degrees = 0.0;
  double scale = 1.0;
  bool IsIdentity() const { return angle_degrees == 0.0 && scale == 1.0; }
};

/// What one computation produced (worker thread result).
struct ComputeResult
{
  vtkSmartPointer<vtkDataSet> weighted;
  vtkSmartPointer<vtkDataSet> compare; ///< the comparison method's weights (side-by-side)
  QString error;
  double seconds = 0.0;
  bool cancelled = false;
};

class ViewerWindow : public QMainWindow
{
  Q_OBJECT
public:
  explicit ViewerWindow(QWidget* parent = nullptr);
  ~ViewerWindow() override;

  /// Bundled examples: name -> description (the File > Examples menu).
  static QStringList ExampleNames();

  // --- state, for tests and scripts ---------------------------------------------------------
  bool isComputing() const { return this->Busy; }
  bool hasWeights() const { return this->Weighted != nullptr; }
  vtkDataSet* weighted() const { return this->Weighted; }
  vtkDataSet* compareWeighted() const { return this->CompareWeighted; }
  /// The model at the current pose (the rest model when nothing was moved).
  vtkPointSet* deformedModel() const;
  vtkPolyData* controls() const { return this->Controls; }
  vtkPoints* posedControls() const { return this->PosedControls; }
  /// What the controls are for the current method (cage, skeleton, free points).
  ControlKind controlKind() const { return this->kindFor(this->Parameters.method); }
  /// What the controls were for the weights shown (the current method before any weights).
  ControlKind shownKind() const
  {
    return this->Weighted ? this->kindFor(this->Computed.method) : this->controlKind();
  }
  int selectedControl() const { return this->Options.component; }
  int componentCount() const;
  const WeightsParameters& parameters() const { return this->Parameters; }
  const Inputs& inputs() const { return this->In; }
  const SceneOptions& sceneOptions() const { return this->Options; }
  const SceneInfo& sceneInfo() const { return this->Info; }
  QString compareMethod() const { return this->CompareMethod; }
  /// Every error reported so far (also shown in the status bar, and in a dialog when
  /// interactive).
  const QStringList& errors() const { return this->Errors; }
  double lastComputeSeconds() const { return this->LastSeconds; }
  std::size_t undoDepth() const { return this->UndoStack.size(); }
  /// BBW handle @p handle's rotation / scale (identity when none or out of range).
  HandleTwist handleTwist(int handle) const;
  /// The equivalent `barylab weights ...` command line.
  QString commandLine() const;
  QVTKOpenGLNativeWidget* view() const { return this->View; }
  QVTKOpenGLNativeWidget* compareView() const { return this->CompareView; }
  vtkRenderer* renderer() const { return this->Renderer; }
  vtkRenderer* compareRenderer() const { return this->CompareRenderer; }

  /// The locality charts (P(t), Q(k)) and the statistics they show (an array of
  /// barylab::LocalityStatisticsJson objects with "method"; empty before showLocality()).
  LocalityPanel* localityPanel() const { return this->Locality; }
  const nlohmann::json& localityStatistics() const;
  bool isLocalityShown() const;

  /// Interactive (default): errors also open a message box. Off for tests and --screenshot.
  void setInteractive(bool on) { this->Interactive = on; }
  /// Synchronous: compute() runs in the calling thread (--screenshot, scripts).
  void setSynchronous(bool on) { this->Synchronous = on; }

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
  /// The example's pose, or a pose file: posed cage / control points, or BBW transforms.
  bool loadPose(const QString& path);
  bool applyExamplePose();
  bool savePose(const QString& path);
  bool saveDeformedModel(const QString& path);
  bool saveSession(const QString& path);
  bool loadSession(const QString& path);
  bool saveScreenshot(const QString& path);
  void showCommandLine();

signals:
  void computeFinished(bool ok);
  void errorReported(const QString& message);
  void sceneUpdated();

private slots:
  void onComputeDone();
  void onPollProgress();
  void openFilesDialog();
  void openSessionDialog();
  void saveSessionDialog();
  void loadPoseDialog();
  void savePoseDialog();
  void saveDeformedDialog();
  void saveScreenshotDialog();
  void exportLocalityDialog();

private:
  void finishCompute(const ComputeResult& result);
  void buildUi();
  void buildParameterPanel();
  void syncPanel();
  void reportError(const QString& message);
  void updateControlList();
  void updateDeformation();
  /// The skeleton's per-handle 3 x 4 transforms at the current pose (joints, then twists).
  std::vector<Eigen::MatrixXd> skeletonTransforms() const;
  void updateScene();
  void renderViews();
  void updateLocality();
  void pushUndo();
  void moveControlLive(int id, const double x[3]);
  int modelDimension() const;
  ControlKind kindFor(const std::string& method) const;
  static void OnInteractorEvent(vtkObject* caller, unsigned long event, void* client, void* call);
  static void OnCameraModified(vtkObject* caller, unsigned long event, void* client, void* call);
  int pickControl(int x, int y) const;

  Inputs In;
  WeightsParameters Parameters;
  WeightsParameters Running;  ///< the parameters of the computation under way
  QString RunningCompare;
  WeightsParameters Computed; ///< the parameters of the weights shown
  QString ComputedCompare;
  QString CompareMethod;
  SceneOptions Options;
  LocalityPanel* Locality = nullptr;
  QDockWidget* LocalityDock = nullptr;
  vtkSmartPointer<vtkImageData> Picture; ///< the 2D image mode's picture (null otherwise)
  SceneInfo Info;
  vtkSmartPointer<vtkDataSet> Model;
  vtkSmartPointer<vtkPolyData> Controls;
  vtkSmartPointer<vtkDataSet> Domain;
  vtkSmartPointer<vtkDataSet> Weighted;
  vtkSmartPointer<vtkDataSet> CompareWeighted;
  vtkSmartPointer<vtkPoints> PosedControls;
  vtkSmartPointer<vtkPointSet> Deformed;
  vtkSmartPointer<vtkPointSet> CompareDeformed;
  struct PoseState
  {
    vtkSmartPointer<vtkPoints> points;
    std::vector<HandleTwist> twists;
  };
  std::vector<PoseState> UndoStack;
  std::vector<HandleTwist> Twists; ///< per BBW handle (empty: none)
  std::vector<HandleTwist> PendingTwists;
  QDoubleSpinBox* TwistAngleBox = nullptr;
  QDoubleSpinBox* TwistScaleBox = nullptr;
  // pending state applied when a computation finishes (session load)
  vtkSmartPointer<vtkPoints> PendingPose;
  int PendingSelection = -1;

  QStringList Errors;
  bool Interactive = true;
  bool Synchronous = false;
  bool Busy = false; ///< a worker runs (until its result is handled)
  double LastSeconds = 0.0;
  bool CameraNeedsReset = true;
  int Dragging = -1;
  bool SyncingCameras = false;

  std::unique_ptr<QFutureWatcher<ComputeResult>> Watcher;
  std::shared_ptr<std::atomic<double>> Progress;
  std::shared_ptr<std::atomic<bool>> CancelFlag;

  // widgets
  QVTKOpenGLNativeWidget* View = nullptr;
  QVTKOpenGLNativeWidget* CompareView = nullptr;
  vtkSmartPointer<vtkRenderer> Renderer;
  vtkSmartPointer<vtkRenderer> CompareRenderer;
  vtkSmartPointer<vtkCallbackCommand> InteractorCallback;
  vtkSmartPointer<vtkCallbackCommand> CameraCallback;
  QLabel* InputsLabel = nullptr;
  QComboBox* MethodBox = nullptr;
  QComboBox* CompareBox = nullptr;
  QVBoxLayout* ParameterForm = nullptr;
  std::vector<std::pair<QWidget*, QWidget*>> ParameterWidgets; ///< (row, editor) per table row
  QPushButton* ComputeButton = nullptr;
  QPushButton* CancelButton = nullptr;
  QProgressBar* ProgressBar = nullptr;
  QListWidget* ControlList = nullptr;
  QComboBox* FieldBox = nullptr;
  QCheckBox* LogBox = nullptr;
  QSpinBox* IsolineBox = nullptr;
  QCheckBox* InfluenceBox = nullptr;
  QCheckBox* ClipBox = nullptr;
  QComboBox* ClipAxisBox = nullptr;
  QSlider* ClipSlider = nullptr;
  QSpinBox* MoveIdBox = nullptr;
  QDoubleSpinBox* MoveBox[3] = { nullptr, nullptr, nullptr };
  QLabel* StatsLabel = nullptr;
  bool Updating = false; ///< panel being synchronised from the state: ignore widget signals
};

} // namespace viewer
} // namespace barylab

Q_DECLARE_METATYPE(barylab::viewer::Inputs)
