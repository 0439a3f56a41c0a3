#pragma once
/// @file barylabViewerFreePointsMode.h
/// The free control points mode: celestial coordinates (tcc, scc), whose controls are points
/// with no cage. Weights component i is control point i; the points are drawn as spheres,
/// dragged, and the model follows (barylab::Deform).

#include "barylabViewerMode.h"

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
  QStringList commandLineInputs(const Inputs& inputs) const override;
};

} // namespace viewer
} // namespace barylab
