#include "barylabSplinePipeline.h"

#include "barylabPipeline.h"

#include "vtkBaryDataIO.h"
#include "vtkBarySplineData.h"
#include "vtkBarySplineDeform.h"
#include "vtkBarySplineEdit.h"
#include "vtkBarySplineSource.h"

#include "core/common/error.h"

#include "vtkMath.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#include <chrono>
#include <cmath>
#include <algorithm>
#include <filesystem>

namespace barylab
{

namespace
{
double bend(double x)
{
  return 0.18 * std::sin(vtkMath::Pi() * x);
}
} // namespace

OrganismSpline OrganismSplineExample(const std::string& data_dir, nlohmann::json* summary)
{
  namespace fs = std::filesystem;
  const fs::path data(data_dir);
  OrganismSpline out;
  auto domain = vtkBaryDataIO::ReadPolyData((data / "spline_domain.obj").string());
  out.model = vtkPointSet::SafeDownCast(vtkBaryDataIO::Read((data / "spline_organism.obj").string()));
  if (!out.model)
    throw bary::Error(bary::ErrorCode::InvalidArgument, "the organism model has no points");
  out.picture = (data / "spline_organism_picture.png").string();
  auto bent = vtkSmartPointer<vtkPolyData>::New();
  bent->DeepCopy(out.model);
  for (vtkIdType p = 0; p < bent->GetNumberOfPoints(); ++p)
  {
    double x[3];
    bent->GetPoint(p, x);
    x[1] += bend(x[0]);
    bent->GetPoints()->SetPoint(p, x);
  }
  const auto t0 = std::chrono::steady_clock::now();
  auto make_source = [&](bool fit) {
    auto source = vtkSmartPointer<vtkBarySplineSource>::New();
    source->SetInputData(domain);
    source->PrismOn();
    source->SetPrismBottom(-0.1);
    source->SetPrismTop(0.1);
    source->PinBorderOn();
    if (fit)
    {
      source->SetFitFromData(out.model);
      source->SetFitToData(bent);
    }
    RunAlgorithm(source, {}, bary::ErrorCode::InvalidArgument);
    return source;
  };
  auto rest = make_source(false);
  auto fitted = make_source(true);
  out.rest_grid = rest->GetOutput();
  std::vector<vtkBarySplineEdit::Edit> edits(3);
  edits[0].edit.op = bary::SplineEditOp::Rotate;
  edits[0].edit.near = { Eigen::Vector2d(0.75, bend(0.75)) };
  edits[0].edit.center = Eigen::Vector2d(0.5, bend(0.5));
  edits[0].edit.angle_degrees = 8;
  edits[0].edit.delta_max = 4;
  edits[1].target = vtkBarySplineEdit::TOP;
  edits[1].edit.near = { Eigen::Vector2d(0.0, 0.0) };
  edits[1].edit.by = Eigen::VectorXd::Constant(1, 0.03);
  edits[1].edit.delta_max = 6;
  edits[2].edit.op = bary::SplineEditOp::Scale;
  edits[2].edit.near = { Eigen::Vector2d(-0.75, bend(-0.75)) };
  edits[2].edit.center = Eigen::Vector2d(-0.75, bend(-0.75));
  edits[2].edit.factor = 0.85;
  edits[2].edit.delta_max = 3;
  auto edit = vtkSmartPointer<vtkBarySplineEdit>::New();
  edit->SetInputConnection(fitted->GetOutputPort());
  edit->SetEdits(edits);
  RunAlgorithm(edit, {}, bary::ErrorCode::InvalidArgument);
  out.grid = edit->GetOutput();
  auto deform = vtkSmartPointer<vtkBarySplineDeform>::New();
  deform->SetInputData(out.model);
  deform->SetSplineConnection(edit->GetOutputPort());
  RunAlgorithm(deform, {}, bary::ErrorCode::InvalidArgument);
  out.deformed = vtkPointSet::SafeDownCast(deform->GetOutput());
  if (summary)
  {
    auto& s = *summary;
    s["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    s["fit"] = { { "landmarks", out.model->GetNumberOfPoints() },
      { "rms_error", fitted->GetFitRMSError() }, { "max_error", fitted->GetFitMaxError() } };
    nlohmann::json list = nlohmann::json::array();
    for (const auto& r : edit->GetReports())
      list.push_back({ { "seconds", r.seconds }, { "derived", r.sets.derived.size() },
        { "constraints", r.sets.constraints.size() }, { "residual", r.residual } });
    s["edits"] = list;
    const vtkBarySpline spline = vtkBarySplineData::FromGrid(out.grid);
    const auto c = spline.xy->continuity();
    const auto jac = spline.xy->check_jacobian();
    s["c1_condition_residual"] = c.max_condition_residual;
    s["max_gradient_jump"] = c.max_gradient_jump;
    s["min_jacobian"] = jac.min_jacobian;
    s["folded_triangles"] = jac.folded.size();
  }
  return out;
}

GingerbreadSpline GingerbreadSplineExample(const std::string& data_dir, nlohmann::json* summary)
{
  namespace fs = std::filesystem;
  const fs::path data(data_dir);
  GingerbreadSpline out;
  auto cage = vtkBaryDataIO::ReadPolyData((data / "cage2d.obj").string());
  out.picture = (data / "gingerbread.png").string();
  double b[6];
  cage->GetBounds(b);
  const double side = std::max(b[1] - b[0], b[3] - b[2]) * 1.1;
  const double cx = 0.5 * (b[0] + b[1]), cy = 0.5 * (b[2] + b[3]);
  out.bounds[0] = cx - side / 2;
  out.bounds[1] = cx + side / 2;
  out.bounds[2] = cy - side / 2;
  out.bounds[3] = cy + side / 2;
  auto source = vtkSmartPointer<vtkBarySplineSource>::New();
  source->SetInputData(cage);
  source->SetTargetTriangles(150);
  RunAlgorithm(source, {}, bary::ErrorCode::InvalidArgument);
  out.rest_grid = source->GetOutput();
  std::vector<vtkBarySplineEdit::Edit> edits(3);
  // The left hand's two corners up, the right hand's two corners turned about the shoulder,
  // the head's five corners turned about the neck.
  edits[0].edit.near = { Eigen::Vector2d(-0.92, 0.1), Eigen::Vector2d(-0.92, 0.34) };
  edits[0].edit.by = Eigen::Vector2d(0.0, 0.3);
  edits[0].edit.delta_max = 15;
  edits[1].edit.op = bary::SplineEditOp::Rotate;
  edits[1].edit.near = { Eigen::Vector2d(0.92, 0.1), Eigen::Vector2d(0.92, 0.34) };
  edits[1].edit.center = Eigen::Vector2d(0.3, 0.22);
  edits[1].edit.angle_degrees = -25;
  edits[1].edit.delta_max = 15;
  edits[2].edit.op = bary::SplineEditOp::Rotate;
  edits[2].edit.near = { Eigen::Vector2d(0.0, 0.92), Eigen::Vector2d(0.24, 0.82),
    Eigen::Vector2d(-0.24, 0.82), Eigen::Vector2d(0.32, 0.56), Eigen::Vector2d(-0.32, 0.56) };
  edits[2].edit.center = Eigen::Vector2d(0.0, 0.42);
  edits[2].edit.angle_degrees = 12;
  edits[2].edit.delta_max = 8;
  auto edit = vtkSmartPointer<vtkBarySplineEdit>::New();
  edit->SetInputConnection(source->GetOutputPort());
  edit->SetEdits(edits);
  RunAlgorithm(edit, {}, bary::ErrorCode::InvalidArgument);
  out.grid = edit->GetOutput();
  if (summary)
  {
    auto& s = *summary;
    nlohmann::json list = nlohmann::json::array();
    for (const auto& r : edit->GetReports())
      list.push_back({ { "seconds", r.seconds }, { "derived", r.sets.derived.size() },
        { "constraints", r.sets.constraints.size() }, { "residual", r.residual } });
    s["edits"] = list;
    const vtkBarySpline spline = vtkBarySplineData::FromGrid(out.grid);
    const auto c = spline.xy->continuity();
    const auto jac = spline.xy->check_jacobian();
    s["triangles"] = spline.xy->net().num_triangles();
    s["c1_condition_residual"] = c.max_condition_residual;
    s["max_gradient_jump"] = c.max_gradient_jump;
    s["min_jacobian"] = jac.min_jacobian;
    s["folded_triangles"] = jac.folded.size();
  }
  return out;
}

} // namespace barylab
