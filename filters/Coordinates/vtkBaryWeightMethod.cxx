#include "vtkBaryWeightMethod.h"

#include "vtkBaryConversion.h"

#include "core/common/error.h"
#include "core/coordinates/weight_method.h"

#include "vtkCell.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

vtkStandardNewMacro(vtkBaryWeightMethod);
vtkCxxSetObjectMacro(vtkBaryWeightMethod, UserWeights, vtkDataArray);

static_assert(vtkBaryWeightMethod::LBC == static_cast<int>(bary::MethodId::LBC),
  "vtkBaryWeightMethod::Methods follows bary::MethodId");
static_assert(vtkBaryWeightMethod::GREEN == static_cast<int>(bary::MethodId::Green),
  "vtkBaryWeightMethod::Methods follows bary::MethodId");

vtkBaryWeightMethod::vtkBaryWeightMethod() = default;

vtkBaryWeightMethod::~vtkBaryWeightMethod()
{
  this->SetUserWeights(nullptr);
}

vtkMTimeType vtkBaryWeightMethod::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->UserWeights)
    t = std::max(t, this->UserWeights->GetMTime());
  return t;
}

void vtkBaryWeightMethod::SetMethod(int method)
{
  method = std::clamp(method, 0, static_cast<int>(NUMBER_OF_METHODS) - 1);
  if (static_cast<int>(this->Settings.method) == method)
    return;
  this->Settings.method = static_cast<bary::MethodId>(method);
  this->Modified();
}

int vtkBaryWeightMethod::GetMethod() const
{
  return static_cast<int>(this->Settings.method);
}

bool vtkBaryWeightMethod::SetMethodByName(const char* name)
{
  const int method = GetMethodFromName(name);
  if (method < 0)
    return false;
  this->SetMethod(method);
  return true;
}

const char* vtkBaryWeightMethod::GetMethodName(int method)
{
  const auto& table = bary::method_table();
  return method >= 0 && method < static_cast<int>(table.size())
    ? table[static_cast<std::size_t>(method)].name.c_str()
    : nullptr;
}

int vtkBaryWeightMethod::GetMethodFromName(const char* name)
{
  const bary::MethodInfo* m = name ? bary::find_method(name) : nullptr;
  return m ? static_cast<int>(m->id) : -1;
}

bool vtkBaryWeightMethod::IsPointBased(int method)
{
  return method >= 0 && method < NUMBER_OF_METHODS &&
    bary::method_info(static_cast<bary::MethodId>(method)).controls ==
    bary::ControlKind::FreePoints;
}

bool vtkBaryWeightMethod::HasFaceTerms(int method)
{
  return method >= 0 && method < NUMBER_OF_METHODS &&
    bary::method_info(static_cast<bary::MethodId>(method)).face_terms;
}

void vtkBaryWeightMethod::SetSetting(const char* key, double value)
{
  const bary::SettingField* field = nullptr;
  try
  {
    field = &bary::setting_field(key ? key : "");
  }
  catch (const bary::Error& e)
  {
    vtkErrorMacro(<< e.what());
    return;
  }
  if (field->kind == bary::SettingField::Kind::Numbers || !std::isfinite(value))
  {
    vtkErrorMacro(<< "setting '" << key << "': " << value << " refused ("
                  << field->range_text() << ")");
    return;
  }
  value = std::clamp(value, field->minimum, field->maximum);
  if (field->kind != bary::SettingField::Kind::Double)
    value = std::round(value);
  if (!field->values.empty()) // the allowed value nearest to it
    value = *std::min_element(field->values.begin(), field->values.end(),
      [value](double a, double b) { return std::abs(a - value) < std::abs(b - value); });
  if (field->get(this->Settings) == value)
    return;
  field->set(this->Settings, value);
  this->Modified();
}

double vtkBaryWeightMethod::GetSetting(const char* key) const
{
  try
  {
    return bary::setting_field(key ? key : "").get(this->Settings);
  }
  catch (const bary::Error&)
  {
    return std::numeric_limits<double>::quiet_NaN();
  }
}

bary::WeightsSettings vtkBaryWeightMethod::GetSettings() const
{
  bary::WeightsSettings settings = this->Settings;
  settings.user_weights.clear();
  if (this->UserWeights)
    for (vtkIdType i = 0; i < this->UserWeights->GetNumberOfTuples(); ++i)
      settings.user_weights.push_back(this->UserWeights->GetComponent(i, 0));
  return settings;
}

void vtkBaryWeightMethod::SetSettings(const bary::WeightsSettings& settings)
{
  bary::validate_settings(settings);
  bary::WeightsSettings copy = settings;
  copy.user_weights.clear();
  if (copy == this->Settings)
    return;
  this->Settings = copy;
  this->Modified();
}

vtkTypeUInt64 vtkBaryWeightMethod::GetSettingsHash()
{
  return bary::settings_hash(this->GetSettings());
}

bool vtkBaryWeightMethod::Replace(
  vtkObjectBase* owner, vtkBaryWeightMethod*& slot, vtkBaryWeightMethod* method)
{
  if (!method || method == slot)
    return false;
  method->Register(owner);
  if (slot)
    slot->UnRegister(owner);
  slot = method;
  return true;
}

void vtkBaryWeightMethod::DeepCopy(vtkBaryWeightMethod* other)
{
  if (!other || other == this)
    return;
  this->SetSettings(other->Settings);
  this->SetUserWeights(other->UserWeights);
}

bool vtkBaryWeightMethod::IsSkeleton(vtkPolyData* controls, vtkDataObject* domain) const
{
  if (this->Settings.method != bary::MethodId::BBW || !controls ||
    controls->GetNumberOfPolys() > 0 || controls->GetNumberOfStrips() > 0)
    return false;
  if (domain)
    return true;
  // Without a domain: bare points, or one polyline through every point, are a 2D cage.
  const vtkIdType lines = controls->GetNumberOfLines();
  if (lines == 0)
    return false;
  if (lines > 1)
    return true;
  vtkIdType visited = 0;
  for (vtkIdType c = 0; c < controls->GetNumberOfCells(); ++c)
    if (controls->GetCellType(c) == VTK_LINE || controls->GetCellType(c) == VTK_POLY_LINE)
      visited = controls->GetCell(c)->GetNumberOfPoints();
  return visited < controls->GetNumberOfPoints();
}

vtkBaryCage vtkBaryWeightMethod::ReadControls(vtkPolyData* controls) const
{
  return IsPointBased(this->GetMethod())
    ? vtkBaryConversion::ToControlPoints(controls, this->Settings.cage_dimension)
    : vtkBaryConversion::ToCage(controls, this->Settings.cage_dimension);
}

bary::WeightsResult vtkBaryWeightMethod::Compute(vtkDataSet* input, vtkPolyData* controls,
  vtkDataSet* domain, const bary::ProgressCallback& progress, vtkBaryCage* columns,
  std::vector<std::string>* warnings, const vtkBaryShared& shared) const
{
  const bary::WeightsSettings settings = this->GetSettings();
  const bary::MethodInfo& info = bary::method_info(settings.method);
  bary::WeightsInput in;
  Eigen::MatrixXd V, points;
  Eigen::MatrixXi T, edges;
  vtkBaryCage cage;
  if (this->IsSkeleton(controls, domain))
  {
    // BBW with a skeleton (points and lines) in a domain: a simplicial mesh is used as is, a
    // closed surface or a polygon is meshed with the skeleton.
    const int dim = vtkBaryConversion::DomainDimension(domain);
    const bary::Skeleton skeleton = vtkBaryConversion::ToSkeleton(controls, dim);
    points = vtkBaryConversion::PointsToMatrix(input, dim);
    bool tets = false, triangles = false, polygons = false;
    for (vtkIdType c = 0; c < domain->GetNumberOfCells(); ++c)
    {
      const int type = domain->GetCellType(c);
      tets = tets || type == VTK_TETRA;
      triangles = triangles || type == VTK_TRIANGLE;
      polygons = polygons || type == VTK_POLYGON || type == VTK_POLY_LINE || type == VTK_QUAD;
    }
    vtkBaryCage boundary;
    if (tets || (dim == 2 && triangles && !polygons))
    {
      vtkBaryConversion::ToSimplices(domain, dim, V, T);
      in.domain_V = &V;
      in.domain_T = &T;
    }
    else
    {
      vtkPolyData* surface = vtkPolyData::SafeDownCast(domain);
      if (!surface)
        throw bary::Error(bary::ErrorCode::InvalidArgument,
          "a domain to be meshed must be a vtkPolyData (a closed triangle surface or a polygon)");
      boundary = vtkBaryConversion::ToCage(surface, dim);
      in.domain_boundary = &boundary.Cage;
    }
    in.skeleton = &skeleton;
    in.points = &points;
    in.mesh_weights = shared.MeshWeights;
    bary::WeightsResult result = bary::compute_weights(in, settings, progress);
    if (columns)
    {
      *columns = vtkBaryCage(); // identity column order: handle j is component j
      columns->ControlPointIds.resize(static_cast<std::size_t>(result.W.cols()));
      for (std::size_t j = 0; j < columns->ControlPointIds.size(); ++j)
        columns->ControlPointIds[j] = static_cast<vtkIdType>(j);
    }
    return result;
  }
  if (domain && warnings)
  {
    if (info.accepts_domain && settings.insert_points)
      warnings->push_back("InsertPointsIntoMesh is ignored: " + info.title +
        " use the domain mesh (input 2) as is; the points are interpolated on it.");
    if (!info.accepts_domain)
      warnings->push_back("The domain (input 2) is used by the mesh-based methods (harmonic, bbw, "
                          "lbc) only; ignored.");
  }
  cage = this->ReadControls(controls);
  const int dim = cage.Cage.dimension();
  points = vtkBaryConversion::PointsToMatrix(input, dim);
  if (dim == 2 && warnings)
  {
    double bounds[6];
    input->GetBounds(bounds);
    if (bounds[5] > bounds[4])
    {
      std::ostringstream text;
      text << "The cage is 2D (a polygon): the points' z coordinates (from " << bounds[4]
           << " to " << bounds[5] << ") are ignored.";
      warnings->push_back(text.str());
    }
  }
  if (info.controls == bary::ControlKind::FreePoints)
    edges = vtkBaryConversion::CellEdges(input);
  if (domain && info.accepts_domain)
  {
    vtkBaryConversion::ToSimplices(domain, dim, V, T);
    in.domain_V = &V;
    in.domain_T = &T;
  }
  in.cage = &cage.Cage;
  in.points = &points;
  in.edges = edges.rows() > 0 ? &edges : nullptr;
  in.mesh_weights = shared.MeshWeights;
  Eigen::MatrixXd all_points;
  if (shared.AllPoints)
  {
    all_points = vtkBaryConversion::PointsToMatrix(shared.AllPoints, dim);
    in.hull_reference_points = &all_points;
  }
  bary::WeightsResult result = bary::compute_weights(in, settings, progress);
  if (columns)
    *columns = std::move(cage);
  return result;
}

void vtkBaryWeightMethod::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << GetMethodName(this->GetMethod()) << "\n";
  for (const bary::SettingField& field : bary::weights_setting_fields())
  {
    os << indent << field.property << ": ";
    switch (field.kind)
    {
      case bary::SettingField::Kind::Numbers:
        os << (this->UserWeights ? "set" : "(none)");
        break;
      case bary::SettingField::Kind::Choice:
        os << field.choices[static_cast<std::size_t>(field.get(this->Settings))];
        break;
      default:
        os << field.get(this->Settings);
    }
    os << "\n";
  }
}
