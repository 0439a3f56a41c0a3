// barylab deform: a model moved with its cage or control points, or skinned by a BBW skeleton.

#include "barylabCli.h"

#include "vtkBaryConversion.h"
#include "vtkBaryLinearBlendSkinning.h"
#include "vtkBaryMixedHandles.h"
#include "vtkBaryDataIO.h"

#include "core/common/error.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkFieldData.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

using nlohmann::json;


namespace barylab
{
namespace cli
{
namespace
{

struct DeformArgs
{
  WeightsParameters parameters;
  std::string cage, posed, controls, posed_controls, user_weights;
  std::string handles, mesh, transforms, posed_handles, pseudo_edges, shape_preservation;
  std::string points, weights, output, json_path;
  bool quiet = false;
  bool drop_weights = false;
};

/// --drop-weights: the deformed model without its weights (the array @p name, or the compact
/// pair name + "Indices" / "Values" with the count in field data): a model of N points and C
/// controls otherwise writes N x C numbers beside its 3 N coordinates.
void drop_weights(vtkPointSet* deformed, const std::string& name)
{
  for (const std::string& array : { name, name + "Indices", name + "Values" })
    deformed->GetPointData()->RemoveArray(array.c_str());
  deformed->GetFieldData()->RemoveArray((name + "NumberOfControlPoints").c_str());
}

/// The model to deform with the weights read from @p weights_path attached (checked against
/// @p model when both are given), or @p model alone.
vtkSmartPointer<vtkDataSet> attach_weights(vtkSmartPointer<vtkDataSet> model,
  const std::string& model_path, const std::string& weights_path, const std::string& array,
  vtkIdType components, const std::string& what)
{
  if (weights_path.empty())
    return model;
  auto weighted = ReadPiece(weights_path); // a .pvtp / .pvtu: this process's piece
  vtkDataArray* w = vtkBaryConversion::FindPointArray(weighted, array);
  // or the compact pair written by 'barylab reduce' (sparse weights)
  vtkDataArray* wi = w ? nullptr : weighted->GetPointData()->GetArray((array + "Indices").c_str());
  vtkDataArray* wv = w ? nullptr : weighted->GetPointData()->GetArray((array + "Values").c_str());
  vtkDataArray* wn =
    weighted->GetFieldData()->GetArray((array + "NumberOfControlPoints").c_str());
  if (!w && !(wi && wv))
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "'" + weights_path + "' has no point-data array '" + array + "' and no compact pair '" +
        array + "Indices'/'" + array + "Values' (write them with 'barylab weights' / 'barylab reduce')");
  // compared as doubles: a NaN or huge count in the file is no integer to cast to
  if (!w && wn && wn->GetNumberOfTuples() > 0 &&
    !(wn->GetComponent(0, 0) == static_cast<double>(components)))
    throw bary::Error(bary::ErrorCode::SizeMismatch,
      "the compact weights in '" + weights_path + "' are for " +
        vtkBaryConversion::CountText(wn->GetComponent(0, 0)) + " control points but " + what + " has " +
        std::to_string(components));
  // control points the method added (celestial hull points) have the last columns
  vtkDataArray* added = weighted->GetFieldData()->GetArray("AddedControlPoints");
  if (w && added)
    components += added->GetNumberOfTuples();
  if (w && w->GetNumberOfComponents() != components)
    throw bary::Error(bary::ErrorCode::SizeMismatch,
      "the weights in '" + weights_path + "' have " + std::to_string(w->GetNumberOfComponents()) +
        " components but " + what + " has " + std::to_string(components));
  if (!model)
    return weighted;
  if (model->GetNumberOfPoints() != weighted->GetNumberOfPoints())
    throw bary::Error(bary::ErrorCode::SizeMismatch,
      "the weights in '" + weights_path + "' are for " +
        std::to_string(weighted->GetNumberOfPoints()) + " points but '" + model_path + "' has " +
        std::to_string(model->GetNumberOfPoints()));
  const double scale = model->GetLength();
  for (vtkIdType i = 0; i < model->GetNumberOfPoints(); ++i)
  {
    double x[3], y[3];
    model->GetPoint(i, x);
    weighted->GetPoint(i, y);
    if (std::abs(x[0] - y[0]) + std::abs(x[1] - y[1]) + std::abs(x[2] - y[2]) > 1e-9 * scale)
      throw bary::Error(bary::ErrorCode::SizeMismatch,
        "the weights in '" + weights_path + "' were computed for other points: point " +
          std::to_string(i) + " differs from '" + model_path + "'");
  }
  if (w)
  {
    model->GetPointData()->AddArray(w);
    if (added)
      model->GetFieldData()->AddArray(added);
  }
  else
  {
    model->GetPointData()->AddArray(wi);
    model->GetPointData()->AddArray(wv);
    if (wn)
      model->GetFieldData()->AddArray(wn);
  }
  return model;
}

/// The output and the summary are writable and none of the inputs (before any computation).
void check_outputs(const DeformArgs& a)
{
  const std::vector<std::string> inputs = { a.cage, a.posed, a.controls, a.posed_controls,
    a.handles, a.mesh, a.transforms, a.posed_handles, a.pseudo_edges, a.points, a.weights };
  check_output(a.output, OutputKind::Data, inputs);
  if (!a.json_path.empty())
    check_output(a.json_path, OutputKind::Json, inputs);
}

int run_deform_bbw(const DeformArgs& a)
{
  if (a.transforms.empty() == a.posed_handles.empty())
    throw UsageError("--method bbw with --handles needs either --transforms POSE or "
                     "--deformed-handles POSED");
  if (!a.pseudo_edges.empty() && a.posed_handles.empty())
    throw UsageError("--pseudo-edges goes with --deformed-handles");
  if (a.points.empty() && a.weights.empty())
    throw UsageError("give --points MODEL or --weights FILE");
  if (a.mesh.empty() && a.weights.empty())
    throw UsageError("--method bbw needs --mesh DOMAIN to compute the weights (or --weights FILE)");
  if (!a.shape_preservation.empty() && a.mesh.empty())
    throw UsageError("--shape-preservation needs the domain mesh (--mesh)");
  vtkSmartPointer<vtkPolyData> handles;
  vtkSmartPointer<vtkDataSet> domain, model;
  std::vector<Eigen::MatrixXd> pose;
  Collective([&]() { // every process reads the same inputs, and its piece of the model
  check_outputs(a);
  handles = vtkBaryDataIO::ReadPolyData(a.handles);
  domain = a.mesh.empty() ? nullptr : vtkBaryDataIO::Read(a.mesh);
  if (domain)
    domain = with_shape_preservation(domain, a.shape_preservation, a.mesh);
  int dim = 3;
  if (domain)
    dim = vtkBaryConversion::DomainDimension(domain);
  else
  {
    double b[6];
    handles->GetBounds(b);
    dim = b[5] - b[4] <= 1e-9 * std::max(1.0, std::max(b[1] - b[0], b[3] - b[2])) ? 2 : 3;
  }
  // Mixed handles (points, bones, cage faces, regions: vtkBaryMixedHandles; a plain skeleton
  // reads as before), then the domain's vertex regions (HandleRegion), in the weights' order.
  const bary::Skeleton skeleton = vtkBaryMixedHandles::ToHandles(handles, dim);
  const auto vertex_regions =
    static_cast<Eigen::Index>(domain ? vtkBaryMixedHandles::RegionVertices(domain).size() : 0);
  const Eigen::Index handle_count = skeleton.handle_count() + vertex_regions;
  if (!a.transforms.empty())
    pose = vtkBaryDataIO::ReadPose(a.transforms, handle_count, &skeleton);
  else
  {
    if (vertex_regions > 0)
      throw UsageError("the domain's HandleRegion regions have no joints to move: pose them "
                       "with --transforms");
    auto posed = vtkBaryDataIO::Read(a.posed_handles);
    auto* posedSet = vtkPointSet::SafeDownCast(posed);
    if (!posedSet || posedSet->GetNumberOfPoints() != handles->GetNumberOfPoints())
      throw bary::Error(bary::ErrorCode::SizeMismatch,
        "'" + a.posed_handles + "' must hold the " + std::to_string(handles->GetNumberOfPoints()) +
          " joints of '" + a.handles + "' moved (same points, same order)");
    pose = vtkBaryLinearBlendSkinning::PoseFromJoints(
      handles, posedSet, dim, a.pseudo_edges.empty() ? Eigen::MatrixXi() : vtkBaryDataIO::ReadPseudoEdges(a.pseudo_edges));
  }
  model = a.points.empty() ? nullptr : ReadPiece(a.points);
  model = attach_weights(model, a.points, a.weights, a.parameters.weights_name,
    handle_count, "the handles '" + a.handles + "'");
  CheckWritableData(model, a.output); // the skinned model has the model's type
  });
  const bool lead = ProcessRank() == 0;
  ProgressBar bar(!a.quiet && lead, "deform");
  json summary;
  bool computed = false;
  vtkSmartPointer<vtkPointSet> deformed;
  Collective([&]() {
    if (a.weights.empty())
    {
      json weights_summary;
      model = barylab::ComputeWeights(model, handles, a.parameters,
        callbacks(bar, a.quiet || !lead), &weights_summary, domain);
      summary["weights"] = weights_summary;
      computed = true;
    }
    vtkPointSet* weighted = vtkPointSet::SafeDownCast(model);
    if (!weighted)
      throw bary::Error(bary::ErrorCode::Io, "the model does not hold a point set");
    json skin_summary;
    deformed = barylab::Skin(weighted, pose, a.parameters, {}, &skin_summary);
    summary["skinning"] = skin_summary;
  });
  bar.done();
  summary["weights_computed"] = computed;
  summary["points"] = OwnedPoints(deformed)->GetNumberOfPoints();
  summary = CombineSummaries(summary);
  if (a.drop_weights)
    drop_weights(deformed, a.parameters.weights_name);
  WriteData(deformed, a.output);
  if (!lead)
    return 0;
  if (!a.json_path.empty())
    barylab::WriteJson(summary, a.json_path);
  if (!a.quiet)
    std::cerr << "barylab: skinned " << summary["points"] << " points with "
              << pose.size() << " handle transforms ("
              << (computed ? "weights computed" : "weights from the input") << ")\n";
  return 0;
}

int run_deform(DeformArgs a)
{
  if (a.parameters.method == bary::MethodId::BBW && !a.handles.empty())
    return run_deform_bbw(a);
  if (!a.controls.empty() && !a.cage.empty())
    throw UsageError("give --cage or --control-points, not both");
  if (!a.posed_controls.empty() && !a.posed.empty())
    throw UsageError("give --deformed-cage or --deformed-control-points, not both");
  if (a.parameters.method != bary::MethodId::BBW &&
    bary::method_info(a.parameters.method).accepts_domain && !a.mesh.empty())
  {
    const std::string name = MethodName(a.parameters);
    throw UsageError("deform --method " + name + " meshes the cage; for weights on a given mesh "
      "run 'barylab weights --method " + name + " --mesh DOMAIN --points MODEL' and pass them "
      "with --weights");
  }
  check_bbw_inputs(a.parameters.method, a.controls.empty() ? a.cage : a.controls, a.handles,
    a.mesh, !a.controls.empty());
  if (!a.user_weights.empty() && a.parameters.method != bary::MethodId::TCelestial)
    throw UsageError("--user-weights is for --method tcc (Eq. 8's s_i)");
  use_control_points(a.controls, a.posed_controls, a.cage, a.posed);
  a.parameters.user_weights = read_user_weights(a.user_weights);
  if (a.posed.empty())
    throw UsageError("--deformed-cage is required (or, for --method bbw, --handles with "
                     "--transforms / --deformed-handles)");
  if (!a.transforms.empty() || !a.posed_handles.empty())
    throw UsageError("--transforms and --deformed-handles go with --method bbw --handles");
  if (a.points.empty() && a.weights.empty())
    throw UsageError("give --points MODEL or --weights FILE");
  vtkSmartPointer<vtkPolyData> cage;
  vtkSmartPointer<vtkDataSet> posedData, modelData;
  vtkPointSet* posed = nullptr;
  vtkPointSet* model = nullptr;
  Collective([&]() { // every process reads the same inputs, and its piece of the model
  check_outputs(a);
  cage = vtkBaryDataIO::ReadPolyData(a.cage);
  posedData = vtkBaryDataIO::Read(a.posed);
  posed = vtkPointSet::SafeDownCast(posedData);
  if (!posed)
    throw bary::Error(bary::ErrorCode::Io, "'" + a.posed + "' does not hold a point set");

  modelData = a.points.empty() ? nullptr : ReadPiece(a.points);
  modelData = attach_weights(modelData, a.points, a.weights, a.parameters.weights_name,
    cage->GetNumberOfPoints(), "the cage '" + a.cage + "'");
  model = vtkPointSet::SafeDownCast(modelData);
  if (!model)
    throw bary::Error(bary::ErrorCode::Io, "the model does not hold a point set");
  CheckWritableData(model, a.output); // the deformed model has the model's type
  });
  const bool lead = ProcessRank() == 0;
  ProgressBar bar(!a.quiet && lead, "deform");
  json summary;
  vtkSmartPointer<vtkPointSet> deformed;
  Collective([&]() {
    deformed = barylab::Deform(
      model, cage, posed, a.parameters, callbacks(bar, a.quiet || !lead), &summary);
  });
  bar.done();
  summary["points"] = OwnedPoints(deformed)->GetNumberOfPoints();
  summary = CombineSummaries(summary);
  if (a.drop_weights)
    drop_weights(deformed, a.parameters.weights_name);
  WriteData(deformed, a.output);
  if (!lead)
    return 0;
  if (!a.json_path.empty())
    barylab::WriteJson(summary, a.json_path);
  if (!a.quiet)
    std::cerr << "barylab: deformed " << summary["points"] << " points in "
              << summary["seconds"].get<double>() << " s ("
              << (summary["weights_computed"].get<bool>() ? "weights computed"
                                                          : "weights from the input")
              << ")\n";
  return 0;
}

} // namespace

void AddDeformCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<DeformArgs>("deform",
    "deform a model by moving its cage or handles", run_deform);
  command->add_option("--cage,-c", a->cage, "rest cage");
  command->add_option("--deformed-cage,-d", a->posed, "moved cage (same points, same order)");
  command->add_option("--control-points", a->controls, "tcc|scc: rest control points");
  command->add_option("--deformed-control-points", a->posed_controls,
    "tcc|scc: the control points moved (same points, same order)");
  command->add_option("--user-weights", a->user_weights, "tcc: s_i of Eq. 8 (text or .dmat)");
  command->add_option("--handles", a->handles,
    "bbw: skeleton (.tgf or .vtp points + lines) or mixed handles (see 'weights')");
  command->add_option("--mesh", a->mesh, "bbw: domain mesh or closed surface (see 'weights')");
  command->add_option("--shape-preservation", a->shape_preservation,
    "bbw: shape-preservation brush per --mesh vertex (a file or a point array; see 'weights')");
  command->add_option("--transforms", a->transforms,
    "bbw: pose, one affine transform per handle (text: 12 numbers [A|t] row-major per line, 6 "
    "in 2D; or libigl .dmat: per-bone quaternions or stacked transforms)");
  command->add_option("--deformed-handles", a->posed_handles,
    "bbw: the skeleton's joints moved (same points, same order): bones rotate onto them");
  command->add_option("--pseudo-edges", a->pseudo_edges,
    "bbw with --deformed-handles: pairs of point-handle indices whose rotations drive the "
    "point handles' rotations (paper §3.4)");
  command->add_option("--points,-p", a->points, "model to deform");
  command->add_option("--weights,-w", a->weights,
    "reuse weights from a file written by 'barylab weights', or the compact (sparse) ones "
    "written by 'barylab reduce' (then --points is optional)");
  command->add_option("--output,-o", a->output, "output file")->required();
  command->add_option("--json", a->json_path, "write a JSON summary");
  command->add_flag("--drop-weights", a->drop_weights,
    "write the deformed model without its weights array (smaller files, faster writes)");
  command->add_flag("--quiet,-q", a->quiet, "no progress bar, summary or warnings (errors still)");
  add_method_options(command, a->parameters);
}

} // namespace cli
} // namespace barylab
