// barylab — the command line: a thin shell over the pipeline builder (barylabPipeline.h).
//
//   barylab weights --method mvc --cage CAGE --points MODEL --output OUT [--json SUMMARY]
//   barylab weights --method bbw --mesh DOMAIN --handles HANDLES [--points MODEL] --output OUT
//                   [--fast]
//   barylab weights --method lbc --cage CAGE [--mesh DOMAIN | --cells N] [--points MODEL]
//                   --output OUT [--locality squared|constant|linear] [--max-iterations N] ...
//   barylab deform  --method mvc --cage REST --deformed-cage POSED --points MODEL --output OUT
//                   [--weights FILE]
//   barylab deform  --method bbw --mesh DOMAIN --handles HANDLES --points MODEL --output OUT
//                   (--transforms POSE | --deformed-handles POSED [--pseudo-edges FILE])
//                   [--weights FILE] [--fast]
//   barylab stats   --input WEIGHTS_FILE [--cage CAGE] [--json] [--threshold T]
//   barylab stats   --locality --input W1 [--input W2 ...] [--csv PREFIX] [--json]
//                   [--json-output FILE] [--threshold T] [--no-measure]
//   barylab reduce  --input WEIGHTS_FILE [--cage CAGE] --output OUT [--threshold T]
//                   [--renormalize rowsum|affine|none] [--keep-dense] [--json]
//   barylab mesh    --cage CAGE [--points MODEL] [--max-volume V | --cells N] --output DOMAIN
//   barylab render  --input WEIGHTS_FILE [--cage CAGE] --output PNG [--control I]
//   barylab demo    [--output-dir DIR]
//
// Exit codes: 0 success, 1 bad input or failed computation (one line on stderr naming the
// problem), 2 bad command line.

#include "barylabCli.h"
#include "barylabPipeline.h"
#include "barylabRender.h"

#include "vtkBaryConversion.h"
#include "vtkBaryCoordinates.h"
#include "vtkBaryDataIO.h"

#include "core/error.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkFieldData.h"
#include "vtkMath.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkUnstructuredGrid.h"

#include <CLI/CLI.hpp>

#include "core/skeleton.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <iostream>
#include <unistd.h>

namespace fs = std::filesystem;

using namespace barylab::cli;
using barylab::RunCallbacks;
using barylab::WeightsParameters;
using nlohmann::json;

namespace
{

struct StatsArgs
{
  std::vector<std::string> inputs;
  std::string cage, array = "Weights";
  double threshold = -1.0;
  bool json_out = false;
  int cage_dimension = 0;
  // --locality
  bool locality = false, no_measure = false;
  std::string csv_prefix, json_file;
};

/// Column labels for several inputs: the file names without folder and extension, made unique.
std::vector<std::string> input_labels(const std::vector<std::string>& inputs)
{
  std::vector<std::string> labels;
  for (const std::string& f : inputs)
  {
    std::string label = fs::path(f).stem().string();
    const std::string base = label;
    for (int n = 2; std::find(labels.begin(), labels.end(), label) != labels.end(); ++n)
      label = base + "_" + std::to_string(n);
    labels.push_back(label);
  }
  return labels;
}

int run_locality(const StatsArgs& a)
{
  if (!a.cage.empty())
    throw UsageError("--locality needs no --cage (use 'barylab reduce --cage' for reproduction)");
  if (!a.json_file.empty())
    check_output(a.json_file, OutputKind::Json);
  if (!a.csv_prefix.empty())
  {
    const fs::path parent = fs::path(a.csv_prefix).parent_path();
    if (!parent.empty() && !fs::is_directory(parent))
      throw bary::Error(bary::ErrorCode::Io,
        "cannot write '" + a.csv_prefix + "_P.csv': folder '" + parent.string() + "' does not exist");
  }
  const std::vector<std::string> labels = input_labels(a.inputs);
  json inputs = json::array();
  for (std::size_t i = 0; i < a.inputs.size(); ++i)
  {
    auto data = vtkBaryDataIO::Read(a.inputs[i]);
    json s;
    try
    {
      s = barylab::LocalityStatisticsJson(data, a.array, a.threshold, !a.no_measure);
    }
    catch (const bary::Error& e)
    {
      throw bary::Error(e.code(), "'" + a.inputs[i] + "': " + e.what());
    }
    s["input"] = a.inputs[i];
    s["label"] = labels[i];
    inputs.push_back(s);
  }
  const std::size_t nt = inputs[0]["t"].size();
  for (const json& s : inputs)
    if (s["t"] != inputs[0]["t"] || s["t"].size() != nt)
      throw bary::Error(bary::ErrorCode::Internal, "inputs sampled P(t) at different t");
  json result;
  result["locality"] = inputs;
  if (!a.csv_prefix.empty())
  {
    write_locality_csv(a.csv_prefix + "_P.csv", inputs, "t", "P", labels);
    write_locality_csv(a.csv_prefix + "_Q.csv", inputs, "k", "Q", labels);
  }
  if (!a.json_file.empty())
    barylab::WriteJson(result, a.json_file);
  if (a.json_out)
  {
    std::cout << result.dump(2) << "\n";
    return 0;
  }
  for (const json& s : inputs)
  {
    std::cout << s["input"].get<std::string>() << ": " << s["points"] << " points x "
              << s["controls"] << " controls\n"
              << "  threshold " << s["threshold"].get<double>() << ", measure "
              << s["measure"].get<std::string>() << "\n"
              << "  support (weights > threshold per point): mean "
              << s["mean_support"].get<double>() << ", max " << s["max_support"].get<double>()
              << "\n  Q(k), k = 1..max support:";
    const int kmax = static_cast<int>(s["max_support"].get<double>());
    for (int k = 0; k < kmax && k < static_cast<int>(s["Q"].size()); ++k)
      std::cout << " " << s["Q"][static_cast<std::size_t>(k)].get<double>();
    std::cout << "\n  P(t) at t = 1e-6, 1e-4, 1e-2, 1:";
    for (std::size_t j = 0; j < s["t"].size(); ++j)
    {
      const double t = s["t"][j].get<double>();
      for (double want : { 1e-6, 1e-4, 1e-2, 1.0 })
        if (std::abs(t - want) <= 1e-9 * want)
          std::cout << " " << s["P"][j].get<double>();
    }
    std::cout << "\n";
  }
  return 0;
}

int run_stats(const StatsArgs& a)
{
  if (a.locality)
    return run_locality(a);
  if (a.inputs.size() != 1)
    throw UsageError("several --input files are for --locality");
  if (!a.csv_prefix.empty() || !a.json_file.empty() || a.no_measure)
    throw UsageError("--csv, --json-output and --no-measure go with --locality");
  auto data = vtkBaryDataIO::Read(a.inputs.front());
  vtkSmartPointer<vtkPolyData> cage = a.cage.empty() ? nullptr : vtkBaryDataIO::ReadPolyData(a.cage);
  json s = barylab::WeightStatisticsJson(data, a.array, cage, a.threshold, a.cage_dimension);
  if (a.json_out)
  {
    std::cout << s.dump(2) << "\n";
    return 0;
  }
  std::cout << "points                     " << s["points"] << "\n"
            << "control points             " << s["controls"] << "\n"
            << "min / max weight           " << s["min_weight"] << " / " << s["max_weight"] << "\n"
            << "negative weights           " << s["negative_weights"] << "\n"
            << "non-finite rows            " << s["non_finite_rows"] << "\n"
            << "partition of unity error   max " << s["partition_of_unity"]["max_error"]
            << ", mean " << s["partition_of_unity"]["mean_error"] << "\n";
  if (s.contains("reproduction"))
    std::cout << "reproduction error         max " << s["reproduction"]["max_error"] << ", mean "
              << s["reproduction"]["mean_error"] << " (relative to the cage diagonal)\n";
  std::cout << "weights > " << s["significant"]["threshold"] << " per point: mean "
            << s["significant"]["mean_per_point"] << ", max " << s["significant"]["max_per_point"]
            << "\n";
  return 0;
}

struct ReduceArgs
{
  barylab::ReduceParameters parameters;
  std::string input, cage, output;
  bool json_out = false;
};

int run_reduce(const ReduceArgs& a)
{
  check_output(a.output, OutputKind::Data);
  const std::string ext = vtkBaryDataIO::Extension(a.output);
  if (ext != ".vtp" && ext != ".vtu" && ext != ".vtk")
    throw bary::Error(bary::ErrorCode::Io,
      "cannot write '" + a.output + "': compact weights are point-data arrays, kept only by "
      ".vtp, .vtu or .vtk");
  auto data = vtkBaryDataIO::Read(a.input);
  vtkSmartPointer<vtkPolyData> cage = a.cage.empty() ? nullptr : vtkBaryDataIO::ReadPolyData(a.cage);
  json summary;
  auto reduced = barylab::ReduceWeights(data, cage, a.parameters, {}, &summary);
  vtkBaryDataIO::Write(reduced, a.output);
  summary["input"] = a.input;
  summary["output"] = a.output;
  if (a.json_out)
  {
    std::cout << summary.dump(2) << "\n";
    return 0;
  }
  std::cout << "kept weights > " << summary["threshold"].get<double>() << ": K = "
            << summary["K"] << " per point at most, " << summary["mean_support"].get<double>()
            << " on average, of " << summary["controls"] << "\n"
            << "renormalization            " << summary["renormalization"].get<std::string>() << "\n"
            << "partition of unity error   " << summary["partition_error"].get<double>() << "\n"
            << "reproduction error         "
            << (summary["reproduction_error"].is_null()
                   ? std::string("(give --cage)")
                   : summary["reproduction_error"].dump() + " (relative to the controls' diameter)")
            << "\n"
            << "max dropped weight sum     " << summary["max_dropped"].get<double>() << "\n"
            << "memory                     " << 100.0 * summary["memory_fraction"].get<double>()
            << "% of the dense array (CSR: "
            << 100.0 * summary["csr_memory_fraction"].get<double>() << "%)\n";
  return 0;
}

struct FieldsArgs
{
  std::string input, output, level_sets, array = "Weights";
  int control = 0;
  std::vector<double> levels;
  bool json_out = false;
};

/// Gradient norms of every weight and level sets of one (VTK's gradient and contour filters
/// through barylab::WeightGradientNorms / WeightLevelSets).
int run_fields(const FieldsArgs& a)
{
  if (a.output.empty() && a.level_sets.empty())
    throw UsageError("give --output (gradient norms) and/or --level-sets (contours)");
  if (!a.output.empty())
  {
    check_output(a.output, OutputKind::Data);
    const std::string ext = vtkBaryDataIO::Extension(a.output);
    if (ext != ".vtp" && ext != ".vtu" && ext != ".vtk")
      throw bary::Error(bary::ErrorCode::Io,
        "cannot write '" + a.output + "': gradient norms are a point-data array, kept only by "
        ".vtp, .vtu or .vtk");
  }
  if (!a.level_sets.empty())
    check_output(a.level_sets, OutputKind::Data);
  auto data = vtkBaryDataIO::Read(a.input);
  json summary;
  summary["input"] = a.input;
  if (!a.output.empty())
  {
    auto with = barylab::WeightGradientNorms(data, a.array, &summary);
    vtkBaryDataIO::Write(with, a.output);
    summary["output"] = a.output;
  }
  if (!a.level_sets.empty())
  {
    auto lines = barylab::WeightLevelSets(data, a.control, a.levels, a.array);
    vtkBaryDataIO::Write(lines, a.level_sets);
    const int n = data->GetPointData()->GetArray(a.array.c_str())->GetNumberOfComponents();
    summary["level_sets"] = { { "file", a.level_sets }, { "control", a.control },
      { "levels", a.levels.empty() ? std::vector<double>{ 1e-3 / n } : a.levels },
      { "points", lines->GetNumberOfPoints() }, { "cells", lines->GetNumberOfCells() } };
  }
  if (a.json_out)
  {
    std::cout << summary.dump(2) << "\n";
    return 0;
  }
  if (summary.contains("gradient_norm"))
  {
    const auto& g = summary["gradient_norm"];
    double top = 0.0;
    for (const auto& v : g["max"])
      top = std::max(top, v.get<double>());
    std::cout << "wrote " << a.output << ": array " << g["array"].get<std::string>() << " ("
              << g["max"].size() << " components), largest |grad w| " << top << "\n";
  }
  if (summary.contains("level_sets"))
    std::cout << "wrote " << a.level_sets << ": " << summary["level_sets"]["cells"]
              << " cells of the level sets " << summary["level_sets"]["levels"].dump()
              << " of control " << a.control << "\n";
  return 0;
}

struct MeshArgs
{
  barylab::MeshParameters parameters;
  std::string cage, points, output, json_path;
  bool quiet = false;
};

int run_mesh(const MeshArgs& a)
{
  check_output(a.output, OutputKind::Data);
  if (!a.json_path.empty())
    check_output(a.json_path, OutputKind::Json);
  auto cage = vtkBaryDataIO::ReadPolyData(a.cage);
  vtkSmartPointer<vtkDataSet> pointsData = a.points.empty() ? nullptr : vtkBaryDataIO::Read(a.points);
  vtkPointSet* points = vtkPointSet::SafeDownCast(pointsData);
  if (pointsData && !points)
    throw bary::Error(bary::ErrorCode::Io, "'" + a.points + "' does not hold a point set");
  ProgressBar bar(!a.quiet, "mesh");
  json summary;
  auto grid = barylab::MeshCage(cage, points, a.parameters, callbacks(bar, a.quiet), &summary);
  bar.done();
  vtkBaryDataIO::Write(grid, a.output);
  summary["cage"] = a.cage;
  summary["output"] = a.output;
  if (!a.json_path.empty())
    barylab::WriteJson(summary, a.json_path);
  if (!a.quiet)
    std::cerr << "barylab: meshed the cage: " << summary["vertices"] << " vertices, "
              << summary["cells"] << " cells in " << summary["seconds"].get<double>() << " s\n";
  return 0;
}

struct RenderArgs
{
  std::string input, cage, handles, controls, output, title;
  barylab::RenderOptions options;
};

int run_render(const RenderArgs& a)
{
  if ((!a.cage.empty()) + (!a.handles.empty()) + (!a.controls.empty()) > 1)
    throw UsageError("give one of --cage, --handles, --control-points");
  check_output(a.output, OutputKind::Png);
  auto data = vtkBaryDataIO::Read(a.input);
  const std::string& controls = !a.handles.empty() ? a.handles : !a.controls.empty() ? a.controls : a.cage;
  vtkSmartPointer<vtkPolyData> cage = controls.empty() ? nullptr : vtkBaryDataIO::ReadPolyData(controls);
  barylab::RenderOptions options = a.options;
  options.title = a.title;
  options.skeleton = !a.handles.empty();
  options.free_points = !a.controls.empty();
  auto window = barylab::WeightFieldWindow(data, cage, options);
  barylab::WritePNG(window, a.output);
  return 0;
}

struct DemoArgs
{
  std::string output_dir = "barylab-demo";
  std::string data_dir = BARYLAB_DEFAULT_DATA_DIR;
  bool render = true;
  int threads = 0;
};

/// One demo pipeline: weights, statistics, deformation, images.
json demo_case(const DemoArgs& a, const std::string& name, const std::string& cage_file,
  const std::string& posed_file, const std::string& model_file, int component /* -1: auto */,
  vtkSmartPointer<vtkDataSet>* weighted_out = nullptr)
{
  const fs::path data(a.data_dir), out(a.output_dir);
  auto cage = vtkBaryDataIO::ReadPolyData((data / cage_file).string());
  auto posedData = vtkBaryDataIO::Read((data / posed_file).string());
  auto model = vtkBaryDataIO::Read((data / model_file).string());
  WeightsParameters parameters;
  parameters.threads = a.threads;
  ProgressBar bar(true, name);
  json summary;
  auto weighted = barylab::ComputeWeights(model, cage, parameters, callbacks(bar, false), &summary);
  bar.done();
  summary["cage"]["file"] = (data / cage_file).string();
  summary["points"]["file"] = (data / model_file).string();
  summary["statistics"] = barylab::WeightStatisticsJson(weighted, "Weights", cage);
  const std::string weights_out = (out / (name + "_weights.vtp")).string();
  vtkBaryDataIO::Write(weighted, weights_out);
  summary["output"] = weights_out;
  print_summary(summary);
  if (weighted_out)
    *weighted_out = weighted;

  json deform_summary;
  auto deformed = barylab::Deform(vtkPointSet::SafeDownCast(weighted), cage,
    vtkPointSet::SafeDownCast(posedData), parameters, {}, &deform_summary);
  const std::string deformed_out = (out / (name + "_deformed.vtp")).string();
  vtkBaryDataIO::Write(deformed, deformed_out);
  summary["deformation"] = deform_summary;
  summary["deformation"]["posed_cage"] = (data / posed_file).string();
  summary["deformation"]["output"] = deformed_out;

  if (component < 0)
  { // the control point with the strongest influence on the model
    vtkDataArray* w = weighted->GetPointData()->GetArray("Weights");
    double best = -1.0;
    for (int k = 0; k < w->GetNumberOfComponents(); ++k)
    {
      double r[2];
      w->GetRange(r, k);
      if (r[1] > best)
      {
        best = r[1];
        component = k;
      }
    }
  }
  if (a.render)
  {
    barylab::RenderOptions options;
    options.component = component;
    options.title = name + ": mean value coordinate of control point " + std::to_string(component);
    const std::string field_png = (out / (name + "_weights.png")).string();
    barylab::WritePNG(barylab::WeightFieldWindow(weighted, cage, options), field_png);
    options.title.clear();
    options.width = 1200;
    options.height = 600;
    const std::string deformed_png = (out / (name + "_deformed.png")).string();
    barylab::WritePNG(barylab::DeformationWindow(weighted, cage, deformed,
                        vtkPointSet::SafeDownCast(posedData), options),
      deformed_png);
    summary["images"] = { field_png, deformed_png };
  }
  std::cerr << "barylab: " << name << ": wrote " << weights_out << ", " << deformed_out
            << (a.render ? " and two PNG images" : "") << "\n";
  return summary;
}

/// The BBW pipeline: bones of a 2D skeleton in the gingerbread man, coupled BBW on a mesh of
/// the cage's interior with the skeleton inserted, weights at the model's vertices, skinning by
/// the bundled pose, images.
json demo_bbw(const DemoArgs& a)
{
  const fs::path data(a.data_dir), out(a.output_dir);
  const std::string name = "gingerbread2d_bbw";
  auto domain = vtkBaryDataIO::Read((data / "cage2d.obj").string());
  auto handles = vtkBaryDataIO::ReadPolyData((data / "skeleton2d.tgf").string());
  auto model = vtkBaryDataIO::Read((data / "model2d.obj").string());
  WeightsParameters parameters;
  parameters.method = "bbw";
  parameters.threads = a.threads;
  ProgressBar bar(true, "bbw 2d");
  json summary;
  auto weighted = barylab::ComputeWeights(model, handles, parameters, callbacks(bar, false),
    &summary, domain);
  bar.done();
  summary["handles"]["file"] = (data / "skeleton2d.tgf").string();
  summary["domain"] = { { "file", (data / "cage2d.obj").string() } };
  summary["points"]["file"] = (data / "model2d.obj").string();
  summary["statistics"] = barylab::WeightStatisticsJson(weighted, "Weights", nullptr);
  const std::string weights_out = (out / (name + "_weights.vtp")).string();
  vtkBaryDataIO::Write(weighted, weights_out);
  summary["output"] = weights_out;
  print_summary(summary);

  const bary::Skeleton skeleton = vtkBaryConversion::ToSkeleton(handles, 2);
  const std::string pose_file = (data / "skeleton2d_pose.txt").string();
  const auto pose = vtkBaryDataIO::ReadPose(pose_file, skeleton.handle_count(), &skeleton);
  json skin_summary;
  auto deformed = barylab::Skin(vtkPointSet::SafeDownCast(weighted), pose, parameters, {}, &skin_summary);
  const std::string deformed_out = (out / (name + "_deformed.vtp")).string();
  vtkBaryDataIO::Write(deformed, deformed_out);
  summary["deformation"] = skin_summary;
  summary["deformation"]["pose"] = pose_file;
  summary["deformation"]["output"] = deformed_out;
  if (a.render)
  {
    barylab::RenderOptions options;
    options.skeleton = true;
    options.component = 3; // the right arm
    options.title = name + ": BBW weight of bone 3 (right arm)";
    const std::string field_png = (out / (name + "_weights.png")).string();
    barylab::WritePNG(barylab::WeightFieldWindow(weighted, handles, options), field_png);
    options.title.clear();
    options.width = 1200;
    options.height = 600;
    const std::string deformed_png = (out / (name + "_deformed.png")).string();
    barylab::WritePNG(barylab::DeformationWindow(weighted, handles, deformed,
                        barylab::PoseHandles(handles, pose), options),
      deformed_png);
    summary["images"] = { field_png, deformed_png };
  }
  std::cerr << "barylab: " << name << ": wrote " << weights_out << ", " << deformed_out
            << (a.render ? " and two PNG images" : "") << "\n";
  return summary;
}

/// Largest distance between two points of @p points (all pairs: cages are small).
double point_set_diameter(vtkDataSet* points)
{
  double diameter = 0.0;
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
    for (vtkIdType j = i + 1; j < points->GetNumberOfPoints(); ++j)
    {
      double p[3], q[3];
      points->GetPoint(i, p);
      points->GetPoint(j, q);
      diameter = std::max(diameter, std::sqrt(vtkMath::Distance2BetweenPoints(p, q)));
    }
  return diameter;
}

/// Local barycentric coordinates (Zhang et al. 2014) of the gingerbread man: LBC weights of the
/// model's vertices (ADMM on a mesh of the cage's interior, default size), their
/// locality against the mean value coordinates of the same points (@p mvc_weighted, from the
/// gingerbread2d case: P(t), Q(k), mean support, as `barylab stats --locality`), the sparse
/// weights (threshold 1e-3/n, row sums) and the cage deformation with them, checked against the
/// deformation with the dense weights, images.
json demo_lbc(const DemoArgs& a, vtkDataSet* mvc_weighted)
{
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path data(a.data_dir), out(a.output_dir);
  const std::string name = "gingerbread2d_lbc";
  auto cage = vtkBaryDataIO::ReadPolyData((data / "cage2d.obj").string());
  auto posedData = vtkBaryDataIO::Read((data / "cage2d_posed.obj").string());
  auto model = vtkBaryDataIO::Read((data / "model2d.obj").string());
  vtkPointSet* posed = vtkPointSet::SafeDownCast(posedData);
  WeightsParameters parameters;
  parameters.method = "lbc";
  parameters.threads = a.threads;
  ProgressBar bar(true, "lbc 2d");
  json summary;
  auto weighted = barylab::ComputeWeights(model, cage, parameters, callbacks(bar, false), &summary);
  bar.done();
  summary["cage"]["file"] = (data / "cage2d.obj").string();
  summary["points"]["file"] = (data / "model2d.obj").string();
  summary["statistics"] = barylab::WeightStatisticsJson(weighted, "Weights", cage);
  const std::string weights_out = (out / (name + "_weights.vtp")).string();
  vtkBaryDataIO::Write(weighted, weights_out);
  summary["output"] = weights_out;
  print_summary(summary);

  // locality, LBC against MVC at the same points (the paper's §5 statistics)
  json inputs = json::array();
  const std::vector<std::pair<std::string, vtkDataSet*>> compared = { { "mvc", mvc_weighted },
    { "lbc", weighted } };
  for (const auto& [label, dataset] : compared)
  {
    json s = barylab::LocalityStatisticsJson(dataset, "Weights");
    s["label"] = label;
    inputs.push_back(s);
  }
  if (inputs[0]["t"] != inputs[1]["t"])
    throw bary::Error(bary::ErrorCode::Internal, "the MVC and LBC statistics sampled P(t) at different t");
  const std::string p_csv = (out / "gingerbread2d_locality_P.csv").string();
  const std::string q_csv = (out / "gingerbread2d_locality_Q.csv").string();
  write_locality_csv(p_csv, inputs, "t", "P", { "mvc", "lbc" });
  write_locality_csv(q_csv, inputs, "k", "Q", { "mvc", "lbc" });
  json& locality = summary["locality"];
  locality["mvc"] = inputs[0];
  locality["lbc"] = inputs[1];
  locality["mean_support"] = { { "mvc", inputs[0]["mean_support"] },
    { "lbc", inputs[1]["mean_support"] } };
  locality["csv"] = { p_csv, q_csv };
  std::cerr << "barylab: " << name << ": mean support (weights > "
            << inputs[1]["threshold"].get<double>() << ") LBC "
            << inputs[1]["mean_support"].get<double>() << ", MVC "
            << inputs[0]["mean_support"].get<double>() << " of " << inputs[1]["controls"]
            << " controls\n";

  // sparse weights: only those above 1e-3/n, rows renormalised to sum 1
  barylab::ReduceParameters reduce;
  json sparse_summary;
  auto sparse = barylab::ReduceWeights(weighted, cage, reduce, {}, &sparse_summary);
  const std::string sparse_out = (out / (name + "_sparse.vtp")).string();
  vtkBaryDataIO::Write(sparse, sparse_out);
  sparse_summary["output"] = sparse_out;
  summary["sparse"] = sparse_summary;

  // deformation with the sparse weights (compact arrays, O(K) per point) and with the dense ones
  json sparse_deform, dense_deform;
  auto deformed = barylab::Deform(vtkPointSet::SafeDownCast(sparse), cage, posed, parameters, {},
    &sparse_deform);
  auto deformed_dense = barylab::Deform(vtkPointSet::SafeDownCast(weighted), cage, posed,
    parameters, {}, &dense_deform);
  if (sparse_deform["weights_computed"].get<bool>() || dense_deform["weights_computed"].get<bool>())
    throw bary::Error(bary::ErrorCode::Internal,
      "the deformation recomputed the weights instead of using the given ones");
  double max_difference = 0.0;
  for (vtkIdType i = 0; i < deformed->GetNumberOfPoints(); ++i)
  {
    double p[3], q[3];
    deformed->GetPoint(i, p);
    deformed_dense->GetPoint(i, q);
    max_difference = std::max(max_difference, std::sqrt(vtkMath::Distance2BetweenPoints(p, q)));
  }
  // Per point, d = w_sparse - w_dense sums to ~0 and its positive part is at most the dropped
  // mass (kept weights are > 0 and scaled by one factor), so the difference of the deformed
  // points, sum_i d_i v_i, is at most max_dropped x the posed cage's diameter, plus the partition
  // errors times the cage's size.
  const double diameter = point_set_diameter(posed);
  double extent = 0.0;
  for (vtkIdType i = 0; i < posed->GetNumberOfPoints(); ++i)
  {
    double p[3];
    posed->GetPoint(i, p);
    extent = std::max(extent, std::sqrt(vtkMath::Dot(p, p)));
  }
  const double partition = summary["statistics"]["partition_of_unity"]["max_error"].get<double>() +
    sparse_summary["partition_error"].get<double>();
  const std::string deformed_out = (out / (name + "_deformed.vtp")).string();
  vtkBaryDataIO::Write(deformed, deformed_out);
  json& deformation = summary["deformation"];
  deformation["posed_cage"] = (data / "cage2d_posed.obj").string();
  deformation["output"] = deformed_out;
  deformation["sparse"] = sparse_deform;
  deformation["dense"] = dense_deform;
  deformation["max_difference"] = max_difference;
  deformation["posed_cage_diameter"] = diameter;
  deformation["difference_bound"] =
    sparse_summary["max_dropped"].get<double>() * diameter + partition * (diameter + extent);
  std::cerr << "barylab: " << name << ": sparse weights K = " << sparse_summary["K"] << ", "
            << 100.0 * sparse_summary["memory_fraction"].get<double>()
            << "% of the dense array; deformation off the dense one by " << max_difference
            << " (bound " << deformation["difference_bound"].get<double>() << ")\n";

  if (a.render)
  {
    barylab::RenderOptions options;
    options.component = 14; // the left hand, as gingerbread2d_weights.png
    options.influence_level = true;
    options.title = name + ": local barycentric coordinate of control point 14; blue: w = 1e-3/" +
      std::to_string(cage->GetNumberOfPoints());
    const std::string field_png = (out / (name + "_weights.png")).string();
    barylab::WritePNG(barylab::WeightFieldWindow(weighted, cage, options), field_png);
    // the sparse deformation, coloured by the dense weight like the rest pose
    vtkSmartPointer<vtkPointSet> shown;
    shown.TakeReference(deformed->NewInstance());
    shown->ShallowCopy(deformed);
    shown->GetPointData()->AddArray(weighted->GetPointData()->GetArray("Weights"));
    options.influence_level = false;
    options.title.clear();
    options.width = 1200;
    options.height = 600;
    const std::string deformed_png = (out / (name + "_deformed.png")).string();
    barylab::WritePNG(barylab::DeformationWindow(weighted, cage, shown, posed, options), deformed_png);
    summary["images"] = { field_png, deformed_png };
  }
  summary["case_seconds"] =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cerr << "barylab: " << name << ": wrote " << weights_out << ", " << sparse_out << ", "
            << deformed_out << ", " << p_csv << ", " << q_csv
            << (a.render ? " and two PNG images" : "") << "\n";
  return summary;
}

/// The organ workflow of celestial coordinates: S-celestial weights of the bundled heart w.r.t.
/// its free control points (active ones around it plus fixed hull points), once; then the
/// scripted heartbeat (data/heartbeat/frame_NN.obj) as a ParaView time series.
json demo_heart(const DemoArgs& a)
{
  const fs::path data(a.data_dir), out(a.output_dir);
  auto controls = vtkBaryDataIO::ReadPolyData((data / "heart_controls.obj").string());
  auto model = vtkBaryDataIO::Read((data / "heart.off").string());
  std::vector<std::string> frame_files;
  for (const auto& entry : fs::directory_iterator(data / "heartbeat"))
    if (entry.path().extension() == ".obj")
      frame_files.push_back(entry.path().string());
  std::sort(frame_files.begin(), frame_files.end());
  std::vector<vtkSmartPointer<vtkPointSet>> frames;
  for (const auto& f : frame_files)
    frames.push_back(vtkPointSet::SafeDownCast(vtkBaryDataIO::Read(f)));
  WeightsParameters parameters;
  parameters.method = "scc";
  parameters.threads = a.threads;
  ProgressBar bar(true, "heart scc");
  json summary;
  auto weighted = barylab::ComputeWeights(model, controls, parameters, callbacks(bar, false), &summary);
  bar.done();
  summary["cage"]["file"] = (data / "heart_controls.obj").string();
  summary["points"]["file"] = (data / "heart.off").string();
  summary["statistics"] = barylab::WeightStatisticsJson(weighted, "Weights", controls);
  print_summary(summary);
  json animation;
  const std::string pvd = barylab::WriteAnimation(vtkPointSet::SafeDownCast(weighted), controls,
    frames, parameters, (out / "heartbeat").string(), "heartbeat", 1.0, &animation);
  summary["animation"] = animation;
  if (a.render && !frames.empty())
  {
    const std::size_t systole = frames.size() / 2;
    auto deformed = barylab::Deform(vtkPointSet::SafeDownCast(weighted), controls, frames[systole], parameters);
    barylab::RenderOptions options;
    options.free_points = true;
    options.component = 7; // a control of the ventricle ring
    options.width = 1200;
    options.height = 600;
    const std::string png = (out / "heart3d_systole.png").string();
    barylab::WritePNG(barylab::DeformationWindow(weighted, controls, deformed, frames[systole], options), png);
    summary["images"] = { png };
  }
  std::cerr << "barylab: heart3d: wrote " << frames.size() << " heartbeat frames and " << pvd
            << (a.render ? " and one PNG image" : "") << "\n";
  return summary;
}

int run_demo(const DemoArgs& a)
{
  if (a.render && !barylab::HasDisplay())
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "the demo renders PNG images and needs an X display (DISPLAY is not set): run it under "
      "Xvfb (xvfb-run -a barylab demo), or pass --no-render");
  fs::create_directories(a.output_dir);
  json summary;
  summary["demo"] = "mean value coordinates (cage deformation), bounded biharmonic weights "
                    "(skeleton skinning), local barycentric coordinates (locality against MVC, "
                    "sparse weights, cage deformation) and S-celestial coordinates (a heartbeat) "
                    "on bundled data";
  vtkSmartPointer<vtkDataSet> mvc2d;
  summary["cases"]["2d"] = demo_case(a, "gingerbread2d", "cage2d.obj", "cage2d_posed.obj",
    "model2d.obj", 14, &mvc2d);
  summary["cases"]["3d"] = demo_case(a, "kidney3d", "cage3d.obj", "cage3d_posed.obj",
    "model3d.off", -1);
  summary["cases"]["bbw2d"] = demo_bbw(a);
  summary["cases"]["lbc2d"] = demo_lbc(a, mvc2d);
  summary["cases"]["heart3d"] = demo_heart(a);
  const std::string path = (fs::path(a.output_dir) / "summary.json").string();
  barylab::WriteJson(summary, path);
  std::cerr << "barylab: demo finished; summary in " << path << "\n";
  return 0;
}

} // namespace

int main(int argc, char** argv)
{
  CLI::App app{ "BaryLab: generalized barycentric coordinates and cage deformation.\n"
                "Weights are written as a point-data array 'Weights' with one component per "
                "control point (component i = cage point i, in the cage file's order).",
    "barylab" };
  app.require_subcommand(1);
  app.set_version_flag("--version", "barylab 0.1.0");

  barylab::cli::Subcommands subcommands(app);
  barylab::cli::AddWeightsCommand(subcommands);
  barylab::cli::AddDeformCommand(subcommands);
  barylab::cli::AddAnimateCommand(subcommands);

  StatsArgs sa;
  auto* stats = app.add_subcommand("stats", "property statistics of a weights file");
  stats->add_option("--input,-i", sa.inputs,
    "file with a weights point-data array (several with --locality: --input A --input B)")
    ->required();
  stats->add_option("--cage,-c", sa.cage, "the cage, for the reproduction error");
  stats->add_option("--array", sa.array, "weights array name")->default_val(sa.array);
  stats->add_option("--threshold", sa.threshold,
    "a weight is significant above this (default 1e-3 / #controls)");
  stats->add_option("--cage-dimension", sa.cage_dimension, "0 automatic, 2, 3")
    ->check(CLI::IsMember({ 0, 2, 3 }));
  stats->add_flag("--json", sa.json_out, "print JSON");
  stats->add_flag("--locality", sa.locality,
    "locality statistics (Zhang et al. 2014, Eq. 19-21): P(t), Q(k), mean/max support");
  stats->add_option("--csv", sa.csv_prefix,
    "--locality: write PREFIX_P.csv and PREFIX_Q.csv (one column per input)");
  stats->add_option("--json-output", sa.json_file, "--locality: write the JSON to this file");
  stats->add_flag("--no-measure", sa.no_measure,
    "--locality: count every point the same (default: lumped area/volume on a domain mesh)");

  ReduceArgs rda;
  auto* reduce = app.add_subcommand("reduce",
    "sparse weights: drop weights <= threshold, store <array>Indices/<array>Values (deform reads them)");
  reduce->add_option("--input,-i", rda.input, "file with a dense weights point-data array")
    ->required();
  reduce->add_option("--cage,-c", rda.cage,
    "cage / control points (point i = component i): reproduction error, needed for affine");
  reduce->add_option("--output,-o", rda.output, "output file (.vtp, .vtu, .vtk)")->required();
  reduce->add_option("--threshold", rda.parameters.threshold,
    "drop weights <= T (default 1e-3 / #controls)");
  reduce->add_option("--renormalize", rda.parameters.renormalize,
       "rowsum: rows sum to one; affine: also reproduce the points (needs --cage); none")
    ->default_val(rda.parameters.renormalize)
    ->check(CLI::IsMember({ "rowsum", "affine", "none" }));
  reduce->add_option("--array", rda.parameters.weights_name, "weights array name")
    ->default_val(rda.parameters.weights_name);
  reduce->add_flag("--keep-dense", rda.parameters.keep_dense, "keep the dense array too");
  reduce->add_flag("--json", rda.json_out, "print the summary as JSON");

  FieldsArgs fa;
  auto* fields = app.add_subcommand("fields",
    "gradient norms |grad w_i| of all weights and level sets of one (VTK's gradient and contour "
    "filters)");
  fields->add_option("--input,-i", fa.input, "weights at the vertices of a mesh (.vtp/.vtu/.vtk)")
    ->required();
  fields->add_option("--output,-o", fa.output,
    "copy of the input with <array>GradientNorm (one component per weight)");
  fields->add_option("--level-sets", fa.level_sets, "level sets of --control (lines / surfaces)");
  fields->add_option("--control", fa.control, "weights component of the level sets")
    ->default_val(0);
  fields->add_option("--level", fa.levels, "level value (repeatable; default 1e-3 / #controls)");
  fields->add_option("--array", fa.array, "weights array name")->default_val(fa.array);
  fields->add_flag("--json", fa.json_out, "print the summary as JSON");

  MeshArgs mea;
  auto* mesh = app.add_subcommand("mesh", "triangulate / tetrahedralize the interior of a cage");
  mesh->add_option("--cage,-c", mea.cage, "cage: closed triangle surface (3D) or polygon (2D)")
    ->required();
  mesh->add_option("--points,-p", mea.points, "points to make mesh vertices (those inside)");
  mesh->add_option("--output,-o", mea.output, "domain mesh (.vtu, or .vtk)")->required();
  mesh->add_option("--cells", mea.parameters.target_cells, "approximate number of cells")
    ->default_val(mea.parameters.target_cells)
    ->check(CLI::Range(1, 50000000));
  mesh->add_option("--max-volume,--max-area", mea.parameters.max_cell_size,
       "maximum tetrahedron volume / triangle area (overrides --cells)")
    ->default_val(0.0)
    ->check(CLI::NonNegativeNumber);
  mesh->add_option("--min-angle", mea.parameters.min_angle, "2D: minimum angle, degrees")
    ->default_val(mea.parameters.min_angle)
    ->check(CLI::Range(0.0, 20.7));
  mesh->add_option("--radius-edge-ratio", mea.parameters.radius_edge_ratio,
       "3D: TetGen quality bound (0 = no quality refinement)")
    ->default_val(mea.parameters.radius_edge_ratio)
    ->check(CLI::Range(0.0, 100.0));
  mesh->add_flag("--preserve-boundary", mea.parameters.preserve_boundary,
    "3D: no extra vertices on the cage faces");
  mesh->add_option("--cage-dimension", mea.parameters.cage_dimension, "0 automatic, 2, 3")
    ->check(CLI::IsMember({ 0, 2, 3 }));
  mesh->add_option("--json", mea.json_path, "write a JSON summary");
  mesh->add_flag("--quiet,-q", mea.quiet, "no progress bar or summary");

  RenderArgs ra;
  auto* render = app.add_subcommand("render", "render one weight field to a PNG (needs X/Xvfb)");
  render->add_option("--input,-i", ra.input, "file with a weights point-data array")->required();
  render->add_option("--cage,-c", ra.cage, "the cage (drawn as wireframe)");
  render->add_option("--handles", ra.handles, "BBW skeleton handles (bones and points) to draw");
  render->add_option("--control-points", ra.controls, "free control points (tcc|scc) to draw");
  render->add_option("--output,-o", ra.output, "PNG file")->required();
  render->add_option("--control", ra.options.component,
       "control point / handle whose weight is shown")
    ->default_val(0);
  render->add_option("--size", ra.options.width, "image width")->default_val(900);
  render->add_option("--title", ra.title, "title text");
  render->add_option("--array", ra.options.weights_name, "weights array name")->default_val("Weights");
  render->add_option("--level", ra.options.levels,
    "draw the level set w = VALUE as a thick blue line (repeatable)");
  render->add_flag("--influence-level", ra.options.influence_level,
    "draw the influence level w = 1e-3 / #controls (where a weight stops being significant)");
  render->add_option("--isolines", ra.options.isolines,
       "isolines evenly spaced over the weight's positive range (0: none)")
    ->default_val(ra.options.isolines)
    ->check(CLI::Range(0, 100));

  DemoArgs ma;
  auto* demo = app.add_subcommand("demo", "the main job: 2D and 3D pipelines on bundled data");
  demo->add_option("--output-dir", ma.output_dir, "where results go")->default_val(ma.output_dir);
  demo->add_option("--data-dir", ma.data_dir, "bundled data folder")->default_val(ma.data_dir);
  demo->add_option("--threads", ma.threads, "threads (0 = all cores)")->default_val(0);
  bool no_render = false;
  demo->add_flag("--no-render", no_render, "skip the PNG images (no X display needed)");

  try
  {
    app.parse(argc, argv);
  }
  catch (const CLI::ParseError& e)
  {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }

  try
  {
    if (*stats)
      return run_stats(sa);
    if (*reduce)
      return run_reduce(rda);
    if (*fields)
      return run_fields(fa);
    if (*mesh)
      return run_mesh(mea);
    if (*render)
    {
      ra.options.height = ra.options.width * 7 / 9;
      return run_render(ra);
    }
    if (*demo)
    {
      ma.render = !no_render;
      return run_demo(ma);
    }
    return subcommands.Run();
  }
  catch (const UsageError& e)
  {
    std::cerr << "barylab: usage error: " << e.what() << "\nRun with --help for more information.\n";
    return 2;
  }
  catch (const bary::Error& e)
  {
    std::cerr << "barylab: error: " << e.what() << "\n";
    return 1;
  }
  catch (const std::exception& e)
  {
    std::cerr << "barylab: error: " << e.what() << "\n";
    return 1;
  }
  return 1;
}
