#pragma once
/// @file barylabViewerSession.h
/// The viewer's session and pose model: the inputs as read, the weights shown, the controls'
/// current positions and BBW handle twists with their undo stack, and the session file (JSON).
/// No widgets and no rendering; errors are thrown as bary::Error for the window to report.

#include "barylabPipeline.h"
#include "barylabViewerScene.h"

#include <QMetaType>
#include <QString>

#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkPoints.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <nlohmann/json.hpp>

#include <vector>

namespace barylab
{
namespace viewer
{
class Mode;

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

/// True for a BBW skeleton file (.tgf).
bool IsSkeletonFile(const QString& path);

/// A deep copy of @p points as doubles (null for null).
vtkSmartPointer<vtkPoints> CopyPoints(vtkPoints* points);

/// The inputs, the weights and the pose. Every change of the pose (a move, a pose file, a
/// twist, a reset) can be undone; a drag is one undo step (pushUndo, then moveControl).
class Session
{
public:
  /// Reads @p inputs (paths made absolute): the controls, the model (a picture: the 2D image
  /// mode's textured mesh of the cage's interior, TexturedCageMesh) and the domain. On success
  /// the session starts over with them (no weights, rest pose, empty undo stack); on failure
  /// it is unchanged.
  /// @throws bary::Error naming the file that cannot be read or is of the wrong kind
  void open(const Inputs& inputs);

  const Inputs& inputs() const { return this->In; }
  vtkPolyData* controls() const { return this->Controls; }
  vtkDataSet* model() const { return this->Model; }
  vtkDataSet* domain() const { return this->Domain; }
  /// The 2D image mode's picture (null otherwise).
  vtkImageData* picture() const { return this->Picture; }
  /// 2 when the model is flat in z, else 3 (3 without a model).
  int modelDimension() const;

  // --- weights --------------------------------------------------------------------------
  /// The weights shown, the parameters they were computed with, the comparison method's
  /// weights (or null); applies the pending pose (setPending) when it fits the controls.
  void setWeights(vtkDataSet* weighted, vtkDataSet* compare, const WeightsParameters& computed,
    const QString& compare_method);
  /// Drops the comparison method's weights and deformed model.
  void clearCompare();
  vtkDataSet* weighted() const { return this->Weighted; }
  vtkDataSet* compareWeighted() const { return this->CompareWeighted; }
  const WeightsParameters& computed() const { return this->Computed; }
  const QString& computedCompare() const { return this->ComputedCompare; }
  /// Number of components of the weights array @p weights_name (0 without weights).
  int componentCount(const std::string& weights_name) const;

  // --- pose -----------------------------------------------------------------------------
  /// The controls' points at the current pose (the rest points after open()).
  vtkPoints* posedControls() const { return this->PosedControls; }
  /// True when a control is away from its rest position or a handle is twisted.
  bool isPosed() const;
  /// Saves the current pose on the undo stack.
  void pushUndo();
  /// Back to the last pose saved; false when there is none.
  bool undo();
  std::size_t undoDepth() const { return this->UndoStack.size(); }
  /// Moves control @p id to @p x without an undo step (a drag: pushUndo() once before).
  void moveControl(int id, const double x[3]);
  /// A new pose for every control (same count); undoable.
  void setPose(vtkSmartPointer<vtkPoints> posed);
  /// Every control at rest, no twists; undoable.
  void resetPose();
  /// Handle @p handle's twist (identity when none or out of range).
  HandleTwist twist(int handle) const;
  const std::vector<HandleTwist>& twists() const { return this->Twists; }
  /// Sets handle @p handle's twist, one of @p handles (all others identity if none yet);
  /// undoable.
  void setTwist(int handle, const HandleTwist& twist, int handles);
  /// Drops every twist (no undo step): the weights shown have no handles to twist.
  void clearTwists() { this->Twists.clear(); }
  /// A pose and twists to apply by the next setWeights (a session being loaded).
  void setPending(vtkSmartPointer<vtkPoints> pose, std::vector<HandleTwist> twists);
  /// Drops the pending pose (a computation failed); pending twists wait for the next weights.
  void clearPendingPose() { this->PendingPose = nullptr; }

  // --- editing the controls (free control points: added, removed) ------------------------
  /// New controls with their pose and the weights for them (an added or removed control
  /// point); undoable: undo() brings back the controls, pose and weights before. Drops the
  /// comparison method's weights (they are for the old controls).
  void replaceControls(vtkSmartPointer<vtkPolyData> controls, vtkSmartPointer<vtkPoints> posed,
    vtkSmartPointer<vtkDataSet> weighted);
  /// The view line of a control point being added (the paper's Fig. 7): the line through the
  /// pixel first clicked, from @p a to @p b (world, across the view's depth), drawn until the
  /// point is placed on it or the adding is cancelled.
  void setViewLine(const double a[3], const double b[3]);
  void clearViewLine() { this->HasViewLine = false; }
  bool hasViewLine() const { return this->HasViewLine; }
  const double* viewLineStart() const { return this->ViewLine[0]; }
  const double* viewLineEnd() const { return this->ViewLine[1]; }

  // --- deformation ----------------------------------------------------------------------
  /// Deforms the models that carry weights to the current pose with @p mode (null when at
  /// rest). On failure the deformed models are null and the error is thrown.
  void updateDeformation(const Mode& mode);
  /// The model at the current pose (the rest model, with weights if any, when not posed).
  vtkPointSet* deformedModel() const;
  vtkPointSet* compareDeformed() const { return this->CompareDeformed; }

private:
  Inputs In;
  vtkSmartPointer<vtkPolyData> Controls;
  vtkSmartPointer<vtkDataSet> Model;
  vtkSmartPointer<vtkDataSet> Domain;
  vtkSmartPointer<vtkImageData> Picture;
  vtkSmartPointer<vtkDataSet> Weighted;
  vtkSmartPointer<vtkDataSet> CompareWeighted;
  WeightsParameters Computed; ///< the parameters of the weights shown
  QString ComputedCompare;
  vtkSmartPointer<vtkPointSet> Deformed;
  vtkSmartPointer<vtkPointSet> CompareDeformed;
  vtkSmartPointer<vtkPoints> PosedControls;
  std::vector<HandleTwist> Twists; ///< per BBW handle (empty: none)
  struct PoseState
  {
    vtkSmartPointer<vtkPoints> points;
    std::vector<HandleTwist> twists;
    vtkSmartPointer<vtkPolyData> controls{}; ///< an edit of the controls: the controls before
    vtkSmartPointer<vtkDataSet> weighted{};  ///< and their weights (null for a pose change)
  };
  bool HasViewLine = false;
  double ViewLine[2][3] = { { 0, 0, 0 }, { 0, 0, 0 } };
  std::vector<PoseState> UndoStack;
  vtkSmartPointer<vtkPoints> PendingPose;
  std::vector<HandleTwist> PendingTwists;
};

/// What a session file holds (File > Save / Load session):
/// `{ "barylab_viewer_session": 1, "inputs": {...}, "parameters": {...}, "compare_method",
/// "selected", "view": {...}, "pose": [[x, y, z], ...] }` plus each mode's part
/// (Mode::writeSession, e.g. "handle_twists").
struct SessionFile
{
  Inputs inputs;
  WeightsParameters parameters;
  QString compare_method;
  int selected = 0;
  /// field, log_scale, isolines, influence_level, clip, clip_axis, clip_position
  SceneOptions view;
  vtkSmartPointer<vtkPoints> pose;   ///< null: the rest pose
  std::vector<HandleTwist> twists;   ///< filled by the modes' readSession
  std::vector<double> shape_brush;   ///< BBW's brush per domain vertex (SkeletonMode)
};

/// The JSON document of @p file (without the modes' parts).
nlohmann::json SessionToJson(const SessionFile& file);

/// Reads the session file @p path; the modes fill their parts (Mode::readSession).
/// @throws bary::Error(Io) when the file cannot be read, is not JSON or not a viewer session
SessionFile ReadSessionFile(const QString& path);

} // namespace viewer
} // namespace barylab

Q_DECLARE_METATYPE(barylab::viewer::Inputs)
