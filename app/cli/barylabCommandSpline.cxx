// The spline family's subcommands (C1 spline deformations, Rodrigues, Stolfi, Gomide 2014):
//   barylab spline create  the identity spline on a triangulation or a meshed polygon (§3)
//   barylab spline edit    DECLeS edits from a JSON file (§4, §5.1)
//   barylab spline deform  a model deformed by the spline, 2D or 2.5D (§5)
// One file for the family.

#include "barylabCli.h"

#include "vtkBaryDataIO.h"
#include "vtkBarySplineData.h"
#include "vtkBarySplineDeform.h"
#include "vtkBarySplineEdit.h"
#include "vtkBarySplineSource.h"

#include "core/common/error.h"

#include "vtkFieldData.h"
#include "vtkDataArray.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <fstream>
#include <iostream>
#include <set>

using nlohmann::json;

namespace barylab
{
namespace cli
{
namespace
{

void check_vtu(const std::string& path, const std::vector<std::string>& inputs)
{
  if (vtkBaryDataIO::Extension(path) != ".vtu")
    throw UsageError("a spline is written as .vtu (VTK Bézier triangles), not '" + path + "'");
  check_output(path, OutputKind::Data, inputs);
}

/// Runs @p algorithm; its first error becomes a bary::Error.
void Run(vtkAlgorithm* algorithm)
{
  RunAlgorithm(algorithm, RunCallbacks{}, bary::ErrorCode::InvalidArgument);
}

vtkSmartPointer<vtkUnstructuredGrid> ReadSpline(const std::string& path)
{
  vtkSmartPointer<vtkDataSet> data = vtkBaryDataIO::Read(path);
  auto grid = vtkUnstructuredGrid::SafeDownCast(data);
  if (!grid)
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "'" + path + "' is not an unstructured grid of Bézier triangles",
      "make one with barylab spline create");
  vtkBarySplineData::FromGrid(grid); // validates
  return vtkSmartPointer<vtkUnstructuredGrid>(grid);
}

json SplineSummary(const vtkBarySpline& s)
{
  json j;
  const auto c = s.xy->continuity();
  const auto jac = s.xy->check_jacobian();
  j["degree"] = s.xy->net().degree();
  j["triangles"] = s.xy->net().num_triangles();
  j["control_points"] = s.xy->net().num_points();
  j["c1_condition_residual"] = c.max_condition_residual;
  j["c1_condition_residual_relative"] = c.max_condition_residual / s.xy->net().mean_edge_length();
  j["max_gradient_jump"] = c.max_gradient_jump;
  j["min_jacobian"] = jac.min_jacobian;
  j["jacobian_positive_everywhere"] = jac.positive_everywhere();
  j["folded_triangles"] = jac.folded;
  j["prism"] = s.is_prism();
  return j;
}

// --- create ------------------------------------------------------------------------------------

struct CreateArgs
{
  std::string domain, output, json_path;
  int degree = bary::kDefaultSplineDegree;
  int target_triangles = 200;
  std::vector<double> prism;
  std::string fit_from, fit_to;
  bool pin_border = false;
  bool quiet = false;
};

int run_create(const CreateArgs& a)
{
  check_vtu(a.output, { a.domain, a.fit_from, a.fit_to });
  if (!a.json_path.empty())
    check_output(a.json_path, OutputKind::Json, { a.domain, a.output });
  if (!a.prism.empty() && (a.prism.size() != 2 || !(a.prism[1] > a.prism[0])))
    throw UsageError("--prism takes BOTTOM TOP with BOTTOM < TOP");
  auto source = vtkSmartPointer<vtkBarySplineSource>::New();
  source->SetInputData(vtkBaryDataIO::ReadPolyData(a.domain));
  source->SetDegree(a.degree);
  source->SetTargetTriangles(a.target_triangles);
  source->SetPinBorder(a.pin_border);
  if (a.fit_from.empty() != a.fit_to.empty())
    throw UsageError("--fit-from and --fit-to go together");
  vtkSmartPointer<vtkDataSet> from, to;
  if (!a.fit_from.empty())
  {
    from = vtkBaryDataIO::Read(a.fit_from);
    to = vtkBaryDataIO::Read(a.fit_to);
    source->SetFitFromData(from);
    source->SetFitToData(to);
  }
  if (!a.prism.empty())
  {
    source->PrismOn();
    source->SetPrismBottom(a.prism[0]);
    source->SetPrismTop(a.prism[1]);
  }
  Run(source);
  vtkBaryDataIO::Write(source->GetOutput(), a.output);
  json summary = SplineSummary(vtkBarySplineData::FromGrid(source->GetOutput()));
  summary["domain"] = a.domain;
  summary["output"] = a.output;
  if (from)
    summary["fit"] = { { "samples", from->GetNumberOfPoints() },
      { "rms_error", source->GetFitRMSError() }, { "max_error", source->GetFitMaxError() } };
  if (!a.json_path.empty())
    WriteJson(summary, a.json_path);
  if (!a.quiet && from)
    std::cerr << "barylab: spline fitted to " << from->GetNumberOfPoints()
              << " samples (rms error " << source->GetFitRMSError() << ", max "
              << source->GetFitMaxError() << ")\n";
  if (!a.quiet && !from)
    std::cerr << "barylab: identity spline of degree " << a.degree << " on "
              << summary["triangles"] << " triangles, " << summary["control_points"]
              << " control points -> " << a.output << "\n";
  return 0;
}

// --- edit --------------------------------------------------------------------------------------

struct EditArgs
{
  std::string spline, edits, output, json_path;
  bool quiet = false;
};

Eigen::Vector2d Pair(const json& v, const std::string& what)
{
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
    throw bary::Error(bary::ErrorCode::InvalidArgument, what + " must be [x, y]");
  return { v[0].get<double>(), v[1].get<double>() };
}

double Number(const json& v, const std::string& what)
{
  if (!v.is_number())
    throw bary::Error(bary::ErrorCode::InvalidArgument, what + " must be a number");
  return v.get<double>();
}

/// The edits of an EDITS.json: {"edits": [ {...}, ... ]}.
std::vector<vtkBarySplineEdit::Edit> ParseEdits(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw bary::Error(bary::ErrorCode::Io, "cannot read the edits file '" + path + "'");
  json doc;
  try
  {
    doc = json::parse(in);
  }
  catch (const json::exception& e)
  {
    throw bary::Error(bary::ErrorCode::Io, "the edits file '" + path + "' is not JSON: " + e.what());
  }
  if (!doc.is_object() || !doc.contains("edits") || !doc["edits"].is_array())
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "the edits file '" + path + "' has no \"edits\" list", "write {\"edits\": [...]}");
  static const std::set<std::string> known = { "op", "near", "index", "by", "center",
    "angle_degrees", "factor", "delta_max", "spline" };
  std::vector<vtkBarySplineEdit::Edit> out;
  for (size_t k = 0; k < doc["edits"].size(); ++k)
  {
    const json& e = doc["edits"][k];
    const std::string where = "edit " + std::to_string(k);
    if (!e.is_object())
      throw bary::Error(bary::ErrorCode::InvalidArgument, where + " is not an object");
    for (auto it = e.begin(); it != e.end(); ++it)
      if (!known.count(it.key()))
        throw bary::Error(bary::ErrorCode::InvalidArgument,
          where + " has an unknown key \"" + it.key() + "\"",
          "keys: op, near, index, by, center, angle_degrees, factor, delta_max, spline");
    vtkBarySplineEdit::Edit edit;
    const std::string op = e.value("op", std::string());
    if (op == "translate")
      edit.edit.op = bary::SplineEditOp::Translate;
    else if (op == "rotate")
      edit.edit.op = bary::SplineEditOp::Rotate;
    else if (op == "scale")
      edit.edit.op = bary::SplineEditOp::Scale;
    else
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        where + " has op \"" + op + "\"; one of translate, rotate, scale");
    const std::string target = e.value("spline", std::string("xy"));
    if (target == "xy")
      edit.target = vtkBarySplineEdit::XY;
    else if (target == "bottom")
      edit.target = vtkBarySplineEdit::BOTTOM;
    else if (target == "top")
      edit.target = vtkBarySplineEdit::TOP;
    else
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        where + " has spline \"" + target + "\"; one of xy, bottom, top");
    if (e.contains("near"))
    {
      const json& n = e["near"];
      if (n.is_array() && !n.empty() && n[0].is_array())
        for (const json& p : n)
          edit.edit.near.push_back(Pair(p, where + "'s near"));
      else
        edit.edit.near.push_back(Pair(n, where + "'s near"));
    }
    if (e.contains("index"))
    {
      const json& i = e["index"];
      auto one = [&](const json& v) {
        if (!v.is_number_integer())
          throw bary::Error(bary::ErrorCode::InvalidArgument, where + "'s index must be an integer");
        edit.edit.anchors.push_back(v.get<bary::Index>());
      };
      if (i.is_array())
        for (const json& v : i)
          one(v);
      else
        one(i);
    }
    if (edit.edit.near.empty() && edit.edit.anchors.empty())
      throw bary::Error(bary::ErrorCode::InvalidArgument, where + " names no anchor (\"near\" or \"index\")");
    if (e.contains("delta_max"))
    {
      if (!e["delta_max"].is_number_integer())
        throw bary::Error(bary::ErrorCode::InvalidArgument, where + "'s delta_max must be an integer");
      edit.edit.delta_max = e["delta_max"].get<int>();
    }
    switch (edit.edit.op)
    {
      case bary::SplineEditOp::Translate:
        if (!e.contains("by"))
          throw bary::Error(bary::ErrorCode::InvalidArgument, where + " (translate) needs \"by\"");
        if (edit.target == vtkBarySplineEdit::XY)
          edit.edit.by = Pair(e["by"], where + "'s by");
        else
          edit.edit.by = Eigen::VectorXd::Constant(1,
            e["by"].is_array() && e["by"].size() == 1 ? Number(e["by"][0], where + "'s by")
                                                      : Number(e["by"], where + "'s by"));
        break;
      case bary::SplineEditOp::Rotate:
        edit.edit.center = Pair(e.value("center", json()), where + "'s center");
        edit.edit.angle_degrees = Number(e.value("angle_degrees", json()), where + "'s angle_degrees");
        break;
      case bary::SplineEditOp::Scale:
        edit.edit.center = Pair(e.value("center", json()), where + "'s center");
        edit.edit.factor = Number(e.value("factor", json()), where + "'s factor");
        break;
    }
    out.push_back(edit);
  }
  return out;
}

int run_edit(const EditArgs& a)
{
  check_vtu(a.output, { a.spline, a.edits });
  if (!a.json_path.empty())
    check_output(a.json_path, OutputKind::Json, { a.spline, a.edits, a.output });
  const auto grid = ReadSpline(a.spline);
  const auto edits = ParseEdits(a.edits);
  auto filter = vtkSmartPointer<vtkBarySplineEdit>::New();
  filter->SetInputData(grid);
  filter->SetEdits(edits);
  Run(filter);
  vtkBaryDataIO::Write(filter->GetOutput(), a.output);
  json summary = SplineSummary(vtkBarySplineData::FromGrid(filter->GetOutput()));
  json list = json::array();
  for (const auto& r : filter->GetReports())
    list.push_back({ { "seconds", r.seconds }, { "exact_seconds", r.exact_seconds },
      { "anchors", r.sets.anchors }, { "slaves", r.sets.slaves.size() },
      { "derived", r.sets.derived.size() }, { "constraints", r.sets.constraints.size() },
      { "independent_constraints", r.sets.independent.size() },
      { "expansions", r.sets.expansions }, { "residual", r.residual },
      { "max_move", r.max_move } });
  summary["edits"] = list;
  summary["spline"] = a.spline;
  summary["output"] = a.output;
  if (!a.json_path.empty())
    WriteJson(summary, a.json_path);
  if (!a.quiet)
  {
    std::cerr << "barylab: " << edits.size() << " edits; C1 condition residual "
              << summary["c1_condition_residual"].get<double>() << ", min Jacobian "
              << summary["min_jacobian"].get<double>() << "\n";
    if (!summary["jacobian_positive_everywhere"].get<bool>())
      std::cerr << "barylab: warning: the deformation folds or is not proven one-to-one in "
                << summary["folded_triangles"].size() << " triangles\n";
  }
  return 0;
}

// --- deform ------------------------------------------------------------------------------------

struct DeformArgs
{
  std::string spline, points, output, json_path;
  bool quiet = false;
};

int run_deform(const DeformArgs& a)
{
  check_output(a.output, OutputKind::Data, { a.spline, a.points });
  if (!a.json_path.empty())
    check_output(a.json_path, OutputKind::Json, { a.spline, a.points, a.output });
  const auto grid = ReadSpline(a.spline);
  auto model = vtkBaryDataIO::Read(a.points);
  if (!vtkPointSet::SafeDownCast(model))
    throw bary::Error(bary::ErrorCode::InvalidArgument, "'" + a.points + "' has no points to deform");
  auto filter = vtkSmartPointer<vtkBarySplineDeform>::New();
  filter->SetInputData(model);
  filter->SetSplineData(grid);
  const auto t0 = std::chrono::steady_clock::now();
  Run(filter);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  vtkBaryDataIO::Write(vtkDataSet::SafeDownCast(filter->GetOutput()), a.output);
  json summary;
  summary["points"] = model->GetNumberOfPoints();
  summary["seconds"] = seconds;
  summary["prism"] = vtkBarySplineData::FromGrid(grid).is_prism();
  summary["spline"] = a.spline;
  summary["output"] = a.output;
  if (!a.json_path.empty())
    WriteJson(summary, a.json_path);
  if (!a.quiet)
    std::cerr << "barylab: " << summary["points"] << " points deformed ("
              << (summary["prism"].get<bool>() ? "2.5D" : "2D") << ") -> " << a.output << "\n";
  return 0;
}

} // namespace

void AddSplineCommand(Subcommands& subcommands)
{
  auto create = std::make_shared<CreateArgs>();
  auto edit = std::make_shared<EditArgs>();
  auto deform = std::make_shared<DeformArgs>();
  auto which = std::make_shared<std::array<CLI::App*, 3>>();
  CLI::App* spline = subcommands.Add("spline",
    "C1 spline deformations (Rodrigues et al. 2014): create, edit, deform", [=]() -> int {
      if ((*which)[0]->parsed())
        return run_create(*create);
      if ((*which)[1]->parsed())
        return run_edit(*edit);
      return run_deform(*deform);
    });
  spline->require_subcommand(1);

  CLI::App* c = spline->add_subcommand("create", "the identity spline on a domain");
  c->add_option("--domain,-d", create->domain,
     "triangulation (triangles in a plane) or one polygon to mesh")->required();
  c->add_option("--degree", create->degree, "degree of the pieces")
    ->default_val(bary::kDefaultSplineDegree)
    ->check(CLI::Range(bary::kMinSplineDegree, bary::kMaxSplineDegree));
  c->add_option("--target-triangles", create->target_triangles,
     "triangles to aim for when the domain is a polygon")->default_val(200)->check(CLI::Range(2, 1000000));
  c->add_option("--prism", create->prism, "BOTTOM TOP: a 2.5D deformation with this z range")
    ->expected(2);
  c->add_option("--fit-from", create->fit_from,
    "points where a map is sampled (with --fit-to: fit the spline to the map)");
  c->add_option("--fit-to", create->fit_to, "the images of --fit-from's points, as many");
  c->add_flag("--pin-border", create->pin_border, "no edit moves the control points on the border");
  c->add_option("--output,-o", create->output, "the spline (.vtu)")->required();
  c->add_option("--json", create->json_path, "write a JSON summary");
  c->add_flag("--quiet,-q", create->quiet, "no summary (errors still)");

  CLI::App* e = spline->add_subcommand("edit", "apply DECLeS edits from a JSON file");
  e->add_option("--spline,-s", edit->spline, "the spline (.vtu)")->required();
  e->add_option("--edits", edit->edits, "{\"edits\": [...]} applied in order")->required();
  e->add_option("--output,-o", edit->output, "the edited spline (.vtu)")->required();
  e->add_option("--json", edit->json_path, "per-edit times, sets, C1 residual, min Jacobian");
  e->add_flag("--quiet,-q", edit->quiet, "no summary (errors still)");

  CLI::App* d = spline->add_subcommand("deform", "deform a model by the spline (2D or 2.5D)");
  d->add_option("--spline,-s", deform->spline, "the spline (.vtu)")->required();
  d->add_option("--points,-p", deform->points, "the model (points, mesh)")->required();
  d->add_option("--output,-o", deform->output, "the deformed model")->required();
  d->add_option("--json", deform->json_path, "write a JSON summary");
  d->add_flag("--quiet,-q", deform->quiet, "no summary (errors still)");
  *which = { c, e, d };
}

} // namespace cli
} // namespace barylab
