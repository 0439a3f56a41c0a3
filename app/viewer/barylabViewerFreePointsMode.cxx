#include "barylabViewerFreePointsMode.h"

#include "barylabPipeline.h"
#include "barylabViewerSession.h"
#include "barylabViewerWindow.h"

#include "vtkBaryConversion.h"

#include "core/common/error.h"
#include "core/coordinates/celestial_coordinates.h"

#include <QAction>
#include <QMenu>

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkUnsignedCharArray.h"

#include <chrono>

namespace barylab
{
namespace viewer
{

bool FreePointsMode::serves(const std::string& method, const Session&) const
{
  const bary::MethodInfo* info = bary::find_method(method);
  return info && info->controls == bary::ControlKind::FreePoints;
}

QStringList FreePointsMode::controlLabels(const Session& session, int components) const
{
  const int n = session.controls() ? static_cast<int>(session.controls()->GetNumberOfPoints()) : 0;
  QStringList labels;
  for (int i = 0; i < components; ++i)
    labels << (i < n ? QString("control point %1").arg(i)
                     : QString("hull point %1 (fixed)").arg(i - n));
  return labels;
}

void FreePointsMode::addActions(QMenu* edit, ViewerWindow& window) const
{
  ViewerWindow* w = &window;
  edit->addAction("Remove control point", w,
    [w]() {
      if (w->hasWeights() && w->shownKind() == ControlKind::FreePoints)
        w->removeControlPoint(w->selectedControl());
    },
    QKeySequence(Qt::Key_Delete));
  edit->addAction("Cancel adding a control point", w, [w]() { w->cancelAddControlPoint(); },
    QKeySequence(Qt::Key_Escape));
}

QStringList FreePointsMode::commandLineInputs(const Inputs& inputs) const
{
  return { "--control-points", ShellQuoted(inputs.controls) };
}

vtkSmartPointer<vtkDataSet> FreePointsMode::EditedWeights(
  const Session& session, vtkPolyData* controls, double* seconds)
{
  const auto start = std::chrono::steady_clock::now();
  const WeightsParameters& p = session.computed();
  vtkDataSet* model = session.model();
  vtkDataSet* shown = session.weighted();
  if (!model || !controls)
    throw bary::Error(bary::ErrorCode::EmptyInput, "no model or control points to compute with");
  if (p.method != bary::MethodId::TCelestial && p.method != bary::MethodId::SCelestial)
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "control points are added and removed with celestial coordinates (tcc, scc) only");
  if (!p.user_weights.empty())
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "the TCC user weights are one per control point: clear them (user_weights) before adding "
      "or removing control points");
  if (p.outside == bary::OutsidePolicy::Nearest)
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "celestial coordinates take the outside policy 'error' or 'nan' (not 'nearest')");
  const vtkBaryCage cage = vtkBaryConversion::ToControlPoints(controls, p.cage_dimension);
  const int dim = cage.Cage.dimension();
  bary::CelestialOptions options;
  options.scheme =
    p.method == bary::MethodId::TCelestial ? bary::CelestialScheme::T : bary::CelestialScheme::S;
  options.lambda = p.lambda;
  options.hull_points = p.celestial_hull_points;
  options.hull_margin = p.celestial_hull_margin;
  options.outside = p.outside == bary::OutsidePolicy::NaN ? bary::CelestialOutsidePolicy::Flag
                                                          : bary::CelestialOutsidePolicy::Error;
  options.threads = p.threads;
  const bary::CelestialCoordinates celestial(cage.Cage.V, options);
  const bary::Points X = vtkBaryConversion::PointsToMatrix(model, dim);

  // the solution before the edit, when the weights shown carry it
  vtkDataArray* before = shown ? shown->GetPointData()->GetArray("CelestialSolution") : nullptr;
  bary::CelestialResult result;
  if (before && before->GetNumberOfComponents() == dim &&
    before->GetNumberOfTuples() == model->GetNumberOfPoints())
    result = celestial.compute_from(X, vtkBaryConversion::ArrayToMatrix(before));
  else
    result = celestial.compute(X, vtkBaryConversion::CellEdges(model));

  vtkSmartPointer<vtkDataSet> out;
  out.TakeReference(model->NewInstance());
  out->ShallowCopy(model);
  out->GetPointData()->AddArray(vtkBaryConversion::ToArray(result.W, cage, p.weights_name.c_str()));
  vtkNew<vtkUnsignedCharArray> location;
  location->SetName("CageLocation");
  location->SetNumberOfTuples(static_cast<vtkIdType>(result.location.size()));
  for (std::size_t i = 0; i < result.location.size(); ++i)
    location->SetValue(static_cast<vtkIdType>(i), static_cast<unsigned char>(result.location[i]));
  out->GetPointData()->AddArray(location);
  vtkNew<vtkDoubleArray> solution;
  solution->SetName("CelestialSolution");
  solution->SetNumberOfComponents(dim);
  solution->SetNumberOfTuples(result.solution.rows());
  for (vtkIdType i = 0; i < result.solution.rows(); ++i)
    for (int k = 0; k < dim; ++k)
      solution->SetComponent(i, k, result.solution(i, k));
  out->GetPointData()->AddArray(solution);
  vtkNew<vtkFieldData> field;
  if (model->GetFieldData())
    field->ShallowCopy(model->GetFieldData());
  field->RemoveArray("AddedControlPoints");
  if (result.added_controls.rows() > 0)
  {
    vtkNew<vtkDoubleArray> added;
    added->SetName("AddedControlPoints");
    added->SetNumberOfComponents(3);
    added->SetNumberOfTuples(result.added_controls.rows());
    for (vtkIdType k = 0; k < result.added_controls.rows(); ++k)
      for (int j = 0; j < 3; ++j)
        added->SetComponent(k, j, j < dim ? result.added_controls(k, j) : cage.PlaneZ);
    field->AddArray(added);
  }
  out->SetFieldData(field);
  if (seconds)
    *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

} // namespace viewer
} // namespace barylab
