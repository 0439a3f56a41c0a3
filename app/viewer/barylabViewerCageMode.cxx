#include "barylabViewerCageMode.h"

#include "barylabRender.h"
#include "barylabViewerSession.h"

#include "vtkBaryConversion.h"

#include "vtkCellArray.h"
#include "vtkExtractEdges.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

namespace barylab
{
namespace viewer
{

bool CageMode::serves(const std::string&, const Session&) const
{
  return true;
}

void CageMode::addControlActors(vtkRenderer* renderer, vtkPolyData* controls, vtkPoints* points,
  const SceneOptions& options, vtkPoints* selected) const
{
  const double grey[3] = { 0.25, 0.25, 0.3 };
  vtkNew<vtkCellArray> lines;
  if (controls->GetNumberOfPolys() > 0)
  {
    vtkNew<vtkPolyData> surface;
    surface->SetPoints(points);
    surface->SetPolys(controls->GetPolys());
    vtkNew<vtkExtractEdges> edges;
    edges->SetInputData(surface);
    edges->Update();
    lines->DeepCopy(edges->GetOutput()->GetLines());
    AddLines(renderer, edges->GetOutput()->GetPoints(), lines, 2.0, grey);
  }
  else
  {
    const vtkBaryCage cage = vtkBaryConversion::ToCage(controls, 2);
    const vtkIdType n = static_cast<vtkIdType>(cage.ControlPointIds.size());
    lines->InsertNextCell(n + 1);
    for (vtkIdType k = 0; k <= n; ++k)
      lines->InsertCellPoint(cage.ControlPointIds[static_cast<std::size_t>(k % n)]);
    AddLines(renderer, points, lines, 2.0, grey);
  }
  this->Mode::addControlActors(renderer, controls, points, options, selected);
}

QStringList CageMode::commandLineInputs(const Inputs& inputs) const
{
  return { "--cage", ShellQuoted(inputs.controls) };
}

} // namespace viewer
} // namespace barylab
