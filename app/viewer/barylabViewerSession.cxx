#include "barylabViewerSession.h"

#include "barylabViewerMode.h"
#include "barylabViewerParameters.h"

#include "vtkBaryDataIO.h"

#include "core/common/error.h"

#include <QFileInfo>

#include "vtkDataArray.h"
#include "vtkPointData.h"

#include <fstream>

namespace barylab
{
namespace viewer
{
namespace
{
using json = nlohmann::json;

std::string to_std(const QString& s)
{
  return s.toStdString();
}

const char* field_name(SceneOptions::Field field)
{
  return field == SceneOptions::Field::Weight ? "weight"
    : field == SceneOptions::Field::GradientNorm ? "gradient_norm"
                                                 : "image";
}
} // namespace

bool IsSkeletonFile(const QString& path)
{
  return QFileInfo(path).suffix().toLower() == "tgf";
}

vtkSmartPointer<vtkPoints> CopyPoints(vtkPoints* points)
{
  if (!points)
    return nullptr;
  auto copy = vtkSmartPointer<vtkPoints>::New();
  copy->SetDataTypeToDouble();
  copy->DeepCopy(points);
  return copy;
}

// ------------------------------------------------------------------------------------------
// inputs

void Session::open(const Inputs& given)
{
  Inputs in = given; // absolute paths: sessions work from any folder
  for (QString* path : { &in.controls, &in.model, &in.domain, &in.pose })
    if (!path->isEmpty())
      *path = QFileInfo(*path).absoluteFilePath();
  if (IsSkeletonFile(in.controls) && in.domain.isEmpty())
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "the skeleton '" + to_std(in.controls) +
        "' needs a domain to mesh (a polygon, closed surface or tet mesh) as third file");
  vtkSmartPointer<vtkPolyData> controls = vtkBaryDataIO::ReadPolyData(to_std(in.controls));
  vtkSmartPointer<vtkDataSet> model, domain;
  vtkSmartPointer<vtkImageData> picture;
  if (IsPictureFile(to_std(in.model)))
  {
    // 2D image mode: the model is the cage's interior meshed, carrying the picture
    picture = ReadPicture(to_std(in.model));
    model = TexturedCageMesh(controls, picture);
  }
  else
    model = vtkBaryDataIO::Read(to_std(in.model));
  if (!vtkPointSet::SafeDownCast(model))
    throw bary::Error(bary::ErrorCode::Io, "'" + to_std(in.model) + "' does not hold a point set");
  if (!in.domain.isEmpty())
    domain = vtkBaryDataIO::Read(to_std(in.domain));

  this->In = in;
  this->Controls = controls;
  this->Model = model;
  this->Domain = domain;
  this->Picture = picture;
  this->Weighted = nullptr;
  this->CompareWeighted = nullptr;
  this->Deformed = nullptr;
  this->CompareDeformed = nullptr;
  this->PosedControls = CopyPoints(controls->GetPoints());
  this->UndoStack.clear();
  this->Twists.clear();
  this->HasViewLine = false;
}

int Session::modelDimension() const
{
  if (!this->Model)
    return 3;
  double b[6];
  this->Model->GetBounds(b);
  const double extent = std::max(1.0, std::max(b[1] - b[0], b[3] - b[2]));
  return b[5] - b[4] <= 1e-9 * extent ? 2 : 3;
}

// ------------------------------------------------------------------------------------------
// weights

void Session::setWeights(vtkDataSet* weighted, vtkDataSet* compare,
  const WeightsParameters& computed, const QString& compare_method)
{
  this->Computed = computed;
  this->ComputedCompare = compare_method;
  this->Weighted = weighted;
  this->CompareWeighted = compare;
  const vtkIdType n = this->Controls->GetNumberOfPoints();
  if (this->PendingPose && this->PendingPose->GetNumberOfPoints() == n)
    this->PosedControls = this->PendingPose;
  else if (!this->PosedControls || this->PosedControls->GetNumberOfPoints() != n)
    this->PosedControls = CopyPoints(this->Controls->GetPoints());
  this->PendingPose = nullptr;
  if (!this->PendingTwists.empty())
    this->Twists = std::move(this->PendingTwists);
  this->PendingTwists.clear();
}

void Session::clearCompare()
{
  this->CompareWeighted = nullptr;
  this->CompareDeformed = nullptr;
}

int Session::componentCount(const std::string& weights_name) const
{
  if (this->Weighted)
    if (vtkDataArray* w = this->Weighted->GetPointData()->GetArray(weights_name.c_str()))
      return w->GetNumberOfComponents();
  return 0;
}

// ------------------------------------------------------------------------------------------
// pose

bool Session::isPosed() const
{
  for (vtkIdType i = 0; i < this->PosedControls->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3];
    this->PosedControls->GetPoint(i, a);
    this->Controls->GetPoint(i, b);
    if (a[0] != b[0] || a[1] != b[1] || a[2] != b[2])
      return true;
  }
  for (const HandleTwist& t : this->Twists)
    if (!t.IsIdentity())
      return true;
  return false;
}

void Session::pushUndo()
{
  if (this->PosedControls)
    this->UndoStack.push_back({ CopyPoints(this->PosedControls), this->Twists });
}

bool Session::undo()
{
  if (this->UndoStack.empty())
    return false;
  PoseState& last = this->UndoStack.back();
  if (last.controls) // an edit of the controls
  {
    this->Controls = last.controls;
    this->Weighted = last.weighted;
    this->clearCompare();
  }
  this->PosedControls = last.points;
  this->Twists = last.twists;
  this->UndoStack.pop_back();
  return true;
}

void Session::replaceControls(vtkSmartPointer<vtkPolyData> controls,
  vtkSmartPointer<vtkPoints> posed, vtkSmartPointer<vtkDataSet> weighted)
{
  this->UndoStack.push_back(
    { CopyPoints(this->PosedControls), this->Twists, this->Controls, this->Weighted });
  this->Controls = controls;
  this->PosedControls = posed;
  this->Weighted = weighted;
  this->Twists.clear();
  this->clearCompare();
  this->HasViewLine = false;
}

void Session::setViewLine(const double a[3], const double b[3])
{
  for (int k = 0; k < 3; ++k)
  {
    this->ViewLine[0][k] = a[k];
    this->ViewLine[1][k] = b[k];
  }
  this->HasViewLine = true;
}

void Session::moveControl(int id, const double x[3])
{
  this->PosedControls->SetPoint(id, x);
  this->PosedControls->Modified();
}

void Session::setPose(vtkSmartPointer<vtkPoints> posed)
{
  this->pushUndo();
  this->PosedControls = posed;
}

void Session::resetPose()
{
  this->pushUndo();
  this->PosedControls = CopyPoints(this->Controls->GetPoints());
  this->Twists.clear();
}

HandleTwist Session::twist(int handle) const
{
  if (handle < 0 || handle >= static_cast<int>(this->Twists.size()))
    return {};
  return this->Twists[static_cast<std::size_t>(handle)];
}

void Session::setTwist(int handle, const HandleTwist& twist, int handles)
{
  this->pushUndo();
  this->Twists.resize(static_cast<std::size_t>(handles));
  this->Twists[static_cast<std::size_t>(handle)] = twist;
}

void Session::setPending(vtkSmartPointer<vtkPoints> pose, std::vector<HandleTwist> twists)
{
  this->PendingPose = pose;
  this->PendingTwists = std::move(twists);
}

// ------------------------------------------------------------------------------------------
// deformation

void Session::updateDeformation(const Mode& mode)
{
  this->Deformed = nullptr;
  this->CompareDeformed = nullptr;
  if (!this->Weighted || !this->PosedControls || !this->isPosed())
    return;
  try
  {
    WeightsParameters p = this->Computed;
    this->Deformed = mode.deform(*this, this->Weighted, p);
    if (this->CompareWeighted)
    {
      p.method = bary::method_from_name(to_std(this->ComputedCompare));
      this->CompareDeformed = mode.deform(*this, this->CompareWeighted, p);
    }
  }
  catch (const std::exception&)
  {
    this->Deformed = nullptr;
    this->CompareDeformed = nullptr;
    throw;
  }
}

vtkPointSet* Session::deformedModel() const
{
  if (this->Deformed)
    return this->Deformed;
  return vtkPointSet::SafeDownCast(this->Weighted ? this->Weighted.Get() : this->Model.Get());
}

// ------------------------------------------------------------------------------------------
// session files

json SessionToJson(const SessionFile& file)
{
  json s;
  s["barylab_viewer_session"] = 1;
  const Inputs& in = file.inputs;
  s["inputs"] = { { "controls", to_std(in.controls) }, { "model", to_std(in.model) },
    { "domain", to_std(in.domain) }, { "example", to_std(in.example) },
    { "pose_file", to_std(in.pose) } };
  s["parameters"] = ParametersToJson(file.parameters);
  s["compare_method"] = to_std(file.compare_method);
  s["selected"] = file.selected;
  const SceneOptions& v = file.view;
  s["view"] = { { "field", field_name(v.field) }, { "log_scale", v.log_scale },
    { "isolines", v.isolines }, { "influence_level", v.influence_level }, { "clip", v.clip },
    { "clip_axis", v.clip_axis }, { "clip_position", v.clip_position } };
  json pose = json::array();
  if (file.pose)
    for (vtkIdType i = 0; i < file.pose->GetNumberOfPoints(); ++i)
    {
      double p[3];
      file.pose->GetPoint(i, p);
      pose.push_back({ p[0], p[1], p[2] });
    }
  s["pose"] = pose;
  return s;
}

SessionFile ReadSessionFile(const QString& path)
{
  const std::string name = to_std(path);
  std::ifstream stream(name);
  if (!stream)
    throw bary::Error(bary::ErrorCode::Io, "cannot open the session '" + name + "'");
  json s;
  try
  {
    stream >> s;
  }
  catch (const json::exception& e)
  {
    throw bary::Error(bary::ErrorCode::Io,
      "the session '" + name + "' is not valid JSON: " + e.what());
  }
  if (!s.is_object() || !s.contains("barylab_viewer_session"))
    throw bary::Error(bary::ErrorCode::Io, "'" + name + "' is not a BaryLab viewer session");
  SessionFile file;
  const json& i = s.at("inputs");
  file.inputs.controls = QString::fromStdString(i.value("controls", ""));
  file.inputs.model = QString::fromStdString(i.value("model", ""));
  file.inputs.domain = QString::fromStdString(i.value("domain", ""));
  file.inputs.example = QString::fromStdString(i.value("example", ""));
  file.inputs.pose = QString::fromStdString(i.value("pose_file", ""));
  file.parameters = ParametersFromJson(s.value("parameters", json::object()));
  file.compare_method = QString::fromStdString(s.value("compare_method", ""));
  file.selected = s.value("selected", 0);
  const json v = s.value("view", json::object());
  const std::string field = v.value("field", "weight");
  file.view.field = field == "image" ? SceneOptions::Field::Image
    : field == "weight"              ? SceneOptions::Field::Weight
                                     : SceneOptions::Field::GradientNorm;
  file.view.log_scale = v.value("log_scale", false);
  file.view.isolines = v.value("isolines", 9);
  file.view.influence_level = v.value("influence_level", true);
  file.view.clip = v.value("clip", false);
  file.view.clip_axis = v.value("clip_axis", 0);
  file.view.clip_position = v.value("clip_position", 0.5);
  if (s.contains("pose") && s["pose"].is_array() && !s["pose"].empty())
  {
    file.pose = vtkSmartPointer<vtkPoints>::New();
    file.pose->SetDataTypeToDouble();
    for (const json& p : s["pose"])
      file.pose->InsertNextPoint(p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>());
  }
  for (const Mode* mode : Modes())
    mode->readSession(s, file);
  return file;
}

} // namespace viewer
} // namespace barylab
