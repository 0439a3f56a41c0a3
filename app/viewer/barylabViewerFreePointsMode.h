#pragma once
/// @file barylabViewerFreePointsMode.h
/// The free control points mode: celestial coordinates (tcc, scc), whose controls are points
/// with no cage. Weights component i is control point i; the hull points the method may add
/// (CelestialHullPoints::Auto: the weights' last components, "AddedControlPoints") are drawn
/// as small grey spheres and stay fixed. The points are drawn as spheres, dragged, and the
/// model follows (barylab::Deform).
///
/// Editing the control points (the celestial paper's Fig. 7): a control point is added where
/// the user clicks, along the view line (ViewerWindow::addControlPointAt: the first Ctrl +
/// click draws the line through that pixel; after rotating the view, a Ctrl + click on the line
/// places the point there; 2D: one click places it in the plane; Esc cancels), and removed
/// (Delete: the selected one). Each edit recomputes the weights incrementally (EditedWeights)
/// and can be undone (Ctrl+Z).

#include "barylabViewerMode.h"

#include "vtkSmartPointer.h"

class vtkDataSet;
class vtkPolyData;

namespace barylab
{
namespace viewer
{

class FreePointsMode : public Mode
{
public:
  ControlKind controlKind() const override { return ControlKind::FreePoints; }
  /// The methods whose controls are free points (bary::ControlKind::FreePoints).
  bool serves(const std::string& method, const Session& session) const override;
  /// "control point i", then "hull point k (fixed)" for the added hull points' components.
  QStringList controlLabels(const Session& session, int components) const override;
  /// Edit > Remove control point (Delete), Cancel adding a control point (Esc).
  void addActions(QMenu* edit, ViewerWindow& window) const override;
  QStringList commandLineInputs(const Inputs& inputs) const override;

  /// The weights of @p session's model w.r.t. @p controls (its controls with one added or
  /// removed), with the parameters of the weights shown (session.computed()): a shallow copy
  /// of the model with the weights array, "CageLocation", "AddedControlPoints" as
  /// vtkBaryCoordinates writes them, and "CelestialSolution" (#P by dim: each point's psi / c,
  /// CelestialResult::solution). Incremental: when the weights shown carry
  /// "CelestialSolution", each point's Newton starts from it (CelestialCoordinates::
  /// compute_from), else from its neighbours' (a full computation). @p seconds: the time taken.
  /// @throws bary::Error (e.g. points outside the new controls' hull without hull points, or
  /// fewer than dim + 1 controls; TCC user weights, which are per control point, are refused)
  static vtkSmartPointer<vtkDataSet> EditedWeights(
    const Session& session, vtkPolyData* controls, double* seconds = nullptr);
};

} // namespace viewer
} // namespace barylab
