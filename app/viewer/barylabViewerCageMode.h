#pragma once
/// @file barylabViewerCageMode.h
/// The cage mode: the methods with a cage (mvc, harmonic, lbc, ...; also the 2D image mode's
/// warped picture). Weights component i is cage point i; the cage is drawn as a wireframe,
/// its points are dragged and the model follows (barylab::Deform).

#include "barylabViewerMode.h"

namespace barylab
{
namespace viewer
{

class CageMode : public Mode
{
public:
  ControlKind controlKind() const override { return ControlKind::Cage; }
  /// Every method (the last mode asked).
  bool serves(const std::string& method, const Session& session) const override;
  /// The cage's edges (a 3D surface) or its polygon (2D, in polygon order).
  void addControlActors(vtkRenderer* renderer, vtkPolyData* controls, vtkPoints* points,
    const SceneOptions& options, vtkPoints* selected) const override;
  QStringList commandLineInputs(const Inputs& inputs) const override;
};

} // namespace viewer
} // namespace barylab
