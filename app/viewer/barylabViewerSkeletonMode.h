#pragma once
/// @file barylabViewerSkeletonMode.h
/// The skeleton mode: bounded biharmonic weights (bbw) of a .tgf skeleton, or of mixed handles
/// (a .vtp with a HandleType cell array: points, bones, cage faces, regions; vtkBaryMixedHandles).
/// Weights components are the point handles, the bones, the cage vertices, then the regions;
/// the joints are dragged, the selected handle is
/// rotated and scaled about its centre (HandleTwist: keys ] [ + -, the panel's
/// "Rotate/scale handle" row), and the model is skinned with one transform per handle
/// (vtkBaryLinearBlendSkinning::PoseFromJoints, then the twist: Eq. 1 of the BBW paper).

#include "barylabViewerMode.h"

#include <Eigen/Core>

class vtkDataSet;

namespace barylab
{
namespace viewer
{

class SkeletonMode : public Mode
{
public:
  ControlKind controlKind() const override { return ControlKind::Skeleton; }
  /// bbw with controls that are a skeleton (lines and no polygons, or a .tgf file) or mixed
  /// handles (a HandleType cell array).
  bool serves(const std::string& method, const Session& session) const override;
  /// The bones, cage faces and region outlines; the selected handle's bone or region (thick,
  /// red) or joint.
  void addControlActors(vtkRenderer* renderer, vtkPolyData* controls, vtkPoints* points,
    const SceneOptions& options, vtkPoints* selected) const override;
  /// "point handle j (joint i)", "bone b (joints a-c)", "cage vertex k (joint i)", "region r".
  QStringList controlLabels(const Session& session, int components) const override;
  bool componentsAreControlPoints() const override { return false; }
  bool twistsHandles() const override { return true; }
  /// Rotate the selected handle by +-15 degrees (] [), scale it by 1.1 (+ -).
  void addActions(QMenu* edit, ViewerWindow& window) const override;
  /// The selected handle's angle and scale, and "Rotate/scale handle"; the "Shape brush" row:
  /// paint with the left mouse button on the domain mesh (radius in % of the domain's size, a
  /// strength s giving rho = s / size^2, erase, clear); a stroke's release recomputes.
  void addPanelWidgets(QBoxLayout* deformation, ViewerWindow& window) const override;
  /// barylab::Skin with transforms().
  vtkSmartPointer<vtkPointSet> deform(const Session& session, vtkDataSet* weighted,
    const WeightsParameters& parameters) const override;
  /// A .txt / .dmat file holds transforms (BaryLab pose text); other files posed joints.
  vtkSmartPointer<vtkPoints> readPose(const Session& session, const QString& path) const override;
  /// With weights, a .txt file gets the per-handle transforms; other files posed joints.
  void writePose(const Session& session, const QString& path) const override;
  /// "handle_twists": [[angle_degrees, scale], ...] per handle; "shape_brush": rho per domain
  /// vertex when painted.
  void writeSession(const Session& session, nlohmann::json& document) const override;
  void readSession(const nlohmann::json& document, SessionFile& file) const override;
  /// `--handles SKELETON --mesh DOMAIN`.
  QStringList commandLineInputs(const Inputs& inputs) const override;

  /// The per-handle 3 x 4 transforms at @p session's pose: from the joints, then the twists.
  static std::vector<Eigen::MatrixXd> Transforms(const Session& session);

  /// The shape-preservation brush (BBW paper §3.3, Fig. 5) lives on a given simplicial domain
  /// mesh (triangles or tetrahedra) as its point array "ShapePreservation", rho per vertex,
  /// which the weights computation reads (vtkBaryMixedHandles). True when @p domain is one.
  static bool CanPaint(vtkDataSet* domain);
  /// One dab of the brush at @p center (world coordinates): every domain vertex at distance
  /// d < @p radius gets max(rho, value f(d)) (paint) or rho (1 - f(d)) (erase), with the soft
  /// falloff f(d) = (1 - (d / radius)^2)^2. Creates the array (zeros) on the first dab.
  /// Returns the number of vertices within the radius.
  static int PaintShapeBrush(
    vtkDataSet* domain, const double center[3], double radius, double value, bool erase);
  /// Sets the domain's brush to @p values (one per vertex; empty: no brush).
  /// @throws bary::Error(SizeMismatch) for another count than the domain's vertices.
  static void SetShapeBrush(vtkDataSet* domain, const std::vector<double>& values);
};

} // namespace viewer
} // namespace barylab
