#include "barylabViewerFreePointsMode.h"

#include "barylabPipeline.h"
#include "barylabViewerSession.h"

namespace barylab
{
namespace viewer
{

bool FreePointsMode::serves(const std::string& method, const Session&) const
{
  const bary::MethodInfo* info = bary::find_method(method);
  return info && info->controls == bary::ControlKind::FreePoints;
}

QStringList FreePointsMode::commandLineInputs(const Inputs& inputs) const
{
  return { "--control-points", ShellQuoted(inputs.controls) };
}

} // namespace viewer
} // namespace barylab
