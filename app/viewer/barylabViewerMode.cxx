#include "barylabViewerMode.h"

#include "barylabViewerCageMode.h"
#include "barylabViewerFreePointsMode.h"
#include "barylabViewerSession.h"
#include "barylabViewerSkeletonMode.h"

#include "vtkBaryDataIO.h"

#include "core/common/error.h"

#include <QRegExp>

#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"

namespace barylab
{
namespace viewer
{

void Mode::addControlActors(vtkRenderer*, vtkPolyData*, vtkPoints* points,
  const SceneOptions& options, vtkPoints* selected) const
{
  if (options.component >= 0 && options.component < points->GetNumberOfPoints())
    selected->InsertNextPoint(points->GetPoint(options.component));
}

QStringList Mode::controlLabels(const Session&, int components) const
{
  QStringList labels;
  for (int i = 0; i < components; ++i)
    labels << QString("control point %1").arg(i);
  return labels;
}

void Mode::addActions(QMenu*, ViewerWindow&) const {}

void Mode::addPanelWidgets(QBoxLayout*, ViewerWindow&) const {}

vtkSmartPointer<vtkPointSet> Mode::deform(const Session& session, vtkDataSet* weighted,
  const WeightsParameters& parameters) const
{
  vtkNew<vtkPolyData> posed;
  posed->ShallowCopy(session.controls());
  posed->SetPoints(session.posedControls());
  return Deform(vtkPointSet::SafeDownCast(weighted), session.controls(), posed, parameters);
}

vtkSmartPointer<vtkPoints> Mode::readPose(const Session& session, const QString& path) const
{
  const std::string file = path.toStdString();
  auto data = vtkBaryDataIO::Read(file);
  auto* set = vtkPointSet::SafeDownCast(data);
  if (!set || set->GetNumberOfPoints() != session.controls()->GetNumberOfPoints())
    throw bary::Error(bary::ErrorCode::SizeMismatch,
      "the pose '" + file + "' must hold the " +
        std::to_string(session.controls()->GetNumberOfPoints()) + " controls, moved (same order)");
  return CopyPoints(set->GetPoints());
}

void Mode::writePose(const Session& session, const QString& path) const
{
  for (const HandleTwist& t : session.twists())
    if (!t.IsIdentity())
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "handles are rotated / scaled: save the pose as transforms (a .txt file), posed "
        "joints cannot hold rotations");
  vtkNew<vtkPolyData> posed;
  posed->DeepCopy(session.controls());
  posed->SetPoints(CopyPoints(session.posedControls()));
  vtkBaryDataIO::Write(posed, path.toStdString());
}

void Mode::writeSession(const Session&, nlohmann::json&) const {}

void Mode::readSession(const nlohmann::json&, SessionFile&) const {}

const std::vector<const Mode*>& Modes()
{
  static const SkeletonMode skeleton;
  static const FreePointsMode free_points;
  static const CageMode cage; // serves every method the others do not
  static const std::vector<const Mode*> modes = { &skeleton, &free_points, &cage };
  return modes;
}

const Mode& ModeFor(const std::string& method, const Session& session)
{
  for (const Mode* mode : Modes())
    if (mode->serves(method, session))
      return *mode;
  return *Modes().back();
}

const Mode& ModeFor(ControlKind kind)
{
  for (const Mode* mode : Modes())
    if (mode->controlKind() == kind)
      return *mode;
  return *Modes().back();
}

QString ShellQuoted(const QString& s)
{
  if (!s.isEmpty() && !s.contains(QRegExp("[^A-Za-z0-9_./=:+-]")))
    return s;
  QString q = s;
  q.replace("'", "'\\''");
  return "'" + q + "'";
}

} // namespace viewer
} // namespace barylab
