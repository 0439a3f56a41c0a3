// barylab demo: the 2D and 3D pipelines on the bundled data (MVC, BBW, LBC, celestial
// coordinates), weights, deformations, statistics and images in one folder.

#include "barylabCli.h"

#include "barylabRender.h"
#include "barylabSplinePipeline.h"
#include "barylabSurfacePipeline.h"

#include "vtkBaryConversion.h"
#include "vtkBaryDataIO.h"
#include "vtkBaryDisplacementField.h"
#include "vtkBaryEnclosingCage.h"
#include "vtkBaryImageIO.h"
#include "vtkBaryImageWarp.h"
#include "vtkBaryLabelMapSurface.h"
#include "vtkBaryWeightMethod.h"
#include "vtkUnstructuredGrid.h"

#include "core/common/error.h"
#include "core/imaging/displacement_field.h"

#include "vtkCellLocator.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkRendererCollection.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>

namespace fs = std::filesystem;
using nlohmann::json;

namespace barylab
{
namespace cli
{
namespace
{

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
  parameters.method = bary::MethodId::BBW;
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
  parameters.method = bary::MethodId::LBC;
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
  parameters.method = bary::MethodId::SCelestial;
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

/// Weighted averages on a surface (Panozzo et al. 2013): the bundled bumpy torus's embedding,
/// the averages of its 9 anchors for the bundled rows of weights, the weights of every vertex
/// (the inverse problem) with the round trip, and the weight field of the centre anchor.
json demo_surface(const DemoArgs& a)
{
  const fs::path data(a.data_dir), out(a.output_dir);
  auto surface = barylab::ReadSurface((data / "wa_torus.obj").string());
  json summary;
  bary::EmbeddingOptions embedding;
  embedding.threads = a.threads;
  ProgressBar bar(true, "torus embedding");
  auto embedded = barylab::ComputeEmbedding(surface, embedding, callbacks(bar, false), &summary["embedding"]);
  bar.done();
  const std::string embedding_out = (out / "torus_embedding.txt").string();
  barylab::WriteEmbedding(embedded, embedding_out);
  summary["embedding"]["output"] = embedding_out;

  auto anchors = barylab::ReadSurfacePoints((data / "wa_anchors.txt").string());
  const Eigen::MatrixXd W = vtkBaryDataIO::ReadMatrix((data / "wa_weights.txt").string());
  bary::ForwardOptions forward;
  forward.threads = a.threads;
  auto averages = barylab::WeightedAverage(embedded, anchors, W, forward,
    bary::kDefaultSurfaceTolerance, {}, &summary["forward"]);
  const std::string averages_out = (out / "torus_averages.vtp").string();
  vtkBaryDataIO::Write(averages, averages_out);
  summary["forward"]["output"] = averages_out;

  bary::InverseOptions inverse;
  inverse.threads = a.threads;
  auto weighted = barylab::SurfaceWeights(embedded, embedded, anchors, inverse,
    bary::kDefaultSurfaceTolerance, bary::kDefaultRoundTripTolerance, {}, &summary["inverse"]);
  const std::string weights_out = (out / "torus_weights.vtp").string();
  vtkBaryDataIO::Write(weighted, weights_out);
  summary["inverse"]["output"] = weights_out;
  // A closed cubic B-spline on the torus around the anchors (§4.1).
  auto controls = barylab::ReadSurfacePoints((data / "wa_curve_controls.txt").string());
  auto curve = barylab::SurfaceCurve(embedded, controls, 24, true, bary::kDefaultSurfaceTolerance,
    a.threads, {}, &summary["curve"]);
  const std::string curve_out = (out / "torus_curve.vtp").string();
  vtkBaryDataIO::Write(curve, curve_out);
  summary["curve"]["output"] = curve_out;
  // Semiregular remeshing from the bundled coarse quad layout (§4.1, Fig. 7).
  auto coarse = vtkBaryDataIO::ReadPolyData((data / "wa_quads.obj").string());
  bary::RemeshOptions remesh;
  remesh.threads = a.threads;
  auto quads = barylab::Remesh(embedded, coarse, remesh, bary::kDefaultSurfaceTolerance, {},
    &summary["remesh"]);
  const std::string quads_out = (out / "torus_quads.vtp").string();
  vtkBaryDataIO::Write(quads, quads_out);
  summary["remesh"]["output"] = quads_out;
  std::cerr << "barylab: torus: embedding " << summary["embedding"]["seconds"]["total"].get<double>()
            << " s; " << summary["forward"]["queries"] << " averages ("
            << summary["forward"]["failures"] << " failed); weights of "
            << summary["inverse"]["points"] << " vertices, "
            << summary["inverse"]["round_trip"]["not_returned"]
            << " outside what the 9 anchors reach (round trip)\n";
  if (a.render)
  {
    barylab::RenderOptions options;
    options.component = 4; // the centre anchor
    const std::string png = (out / "torus_weights.png").string();
    auto window = barylab::SurfaceWeightsWindow(vtkPolyData::SafeDownCast(weighted), anchors, curve, options);
    barylab::WritePNG(window, png);
    summary["images"] = { png };
  }
  return summary;
}

/// C1 spline deformations (Rodrigues et al. 2014): the bundled organism matched to its picture
/// (barylab::OrganismSplineExample).
json demo_spline(const DemoArgs& a)
{
  const fs::path data(a.data_dir), out(a.output_dir);
  json summary;
  const barylab::OrganismSpline example = barylab::OrganismSplineExample(a.data_dir, &summary);
  const std::string spline_out = (out / "organism_spline.vtu").string();
  const std::string model_out = (out / "organism_deformed.vtp").string();
  vtkBaryDataIO::Write(example.grid, spline_out);
  vtkBaryDataIO::Write(example.deformed, model_out);
  summary["outputs"] = { spline_out, model_out };
  std::cerr << "barylab: organism: spline fitted to " << summary["fit"]["landmarks"]
            << " landmarks (max error " << summary["fit"]["max_error"].get<double>()
            << "), " << summary["edits"].size() << " DECLeS edits; C1 residual "
            << summary["c1_condition_residual"].get<double>() << ", min Jacobian "
            << summary["min_jacobian"].get<double>() << "\n";
  if (a.render)
  {
    barylab::RenderOptions options;
    options.title = "fitted to the picture, then edited";
    const std::string png = (out / "organism_spline.png").string();
    barylab::WritePNG(barylab::SplineDeformationWindow(example.rest_grid, example.grid,
                        example.model, example.deformed, example.picture, options),
      png);
    summary["images"] = { png };
  }
  return summary;
}

/// C1 spline deformations in 2D: the gingerbread man's picture warped by DECLeS edits of a
/// spline over his cage polygon (barylab::GingerbreadSplineExample).
json demo_spline_picture(const DemoArgs& a)
{
  const fs::path out(a.output_dir);
  json summary;
  const barylab::GingerbreadSpline example = barylab::GingerbreadSplineExample(a.data_dir, &summary);
  const std::string spline_out = (out / "gingerbread2d_spline.vtu").string();
  vtkBaryDataIO::Write(example.grid, spline_out);
  summary["outputs"] = { spline_out };
  std::cerr << "barylab: gingerbread picture: spline of degree 5 on " << summary["triangles"]
            << " triangles, " << summary["edits"].size() << " DECLeS edits; C1 residual "
            << summary["c1_condition_residual"].get<double>() << ", min Jacobian "
            << summary["min_jacobian"].get<double>() << "\n";
  if (a.render)
  {
    barylab::RenderOptions options;
    options.title = "left hand raised, right hand and head turned";
    const std::string png = (out / "gingerbread2d_spline.png").string();
    barylab::WritePNG(barylab::SplinePictureWindow(example.rest_grid, example.grid, example.picture,
                        example.bounds, options),
      png);
    summary["images"] = { png };
  }
  return summary;
}

/// The largest distance from a point of @p points to the surface @p surface (its points and
/// triangles, by VTK's cell locator).
double max_distance_to_surface(vtkPointSet* points, vtkPolyData* surface)
{
  vtkNew<vtkCellLocator> locator;
  locator->SetDataSet(surface);
  locator->BuildLocator();
  double worst = 0.0;
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
  {
    double x[3], closest[3], d2 = 0.0;
    vtkIdType cell = -1;
    int sub = 0;
    points->GetPoint(i, x);
    locator->FindClosestPoint(x, closest, cell, sub, d2);
    worst = std::max(worst, std::sqrt(d2));
  }
  return worst;
}

/// The organ workflow (issue 15) on the bundled label map: the organ (label 1) as a closed
/// surface in LPS, an automatic cage around it, the cage moved by the bundled 3D Slicer
/// landmarks (T-celestial coordinates of the cage's vertices w.r.t. the landmarks: a breathing
/// motion), the organ deformed by mean value coordinates of that cage, the deformation written as
/// a displacement field with its inverse (grid transforms ITK and 3D Slicer load), and the label
/// map warped by it. The summary checks the pieces against each other: the field at the
/// organ's points against the direct deformation, and the warped label's surface against the
/// deformed surface.
json demo_organ(const DemoArgs& a)
{
  const fs::path data(a.data_dir), out(a.output_dir);
  const auto t0 = std::chrono::steady_clock::now();
  json summary;
  const std::string label_file = (data / "organ_label.nii.gz").string();
  vtkSmartPointer<vtkImageData> labels = vtkBaryImageIO::Read(label_file);

  // 1. segmentation: the organ's surface
  vtkNew<vtkBaryLabelMapSurface> segment;
  segment->SetInputData(labels);
  segment->SetLabel(1);
  barylab::RunAlgorithm(segment, {}, bary::ErrorCode::InvalidArgument);
  vtkSmartPointer<vtkPolyData> organ = segment->GetOutput();
  const std::string organ_out = (out / "organ_surface.vtp").string();
  vtkBaryDataIO::Write(organ, organ_out);
  summary["segmentation"] = { { "image", label_file }, { "label", 1 },
    { "voxels", segment->GetNumberOfLabelVoxels() }, { "label_volume", segment->GetLabelVolume() },
    { "enclosed_volume", segment->GetEnclosedVolume() }, { "triangles", organ->GetNumberOfCells() },
    { "space", "LPS" }, { "output", organ_out } };

  // 2. the cage, made automatically
  vtkNew<vtkBaryEnclosingCage> cager;
  cager->SetInputData(organ);
  cager->SetNumberOfVertices(60);
  barylab::RunAlgorithm(cager, {}, bary::ErrorCode::InvalidArgument);
  vtkSmartPointer<vtkPolyData> cage = cager->GetOutput();
  const std::string cage_out = (out / "organ_cage.obj").string();
  vtkBaryDataIO::Write(cage, cage_out);
  summary["cage"] = { { "vertices", cage->GetNumberOfPoints() }, { "faces", cage->GetNumberOfCells() },
    { "volume_ratio", cager->GetVolumeRatio() }, { "max_distance", cager->GetMaximumDistance() },
    { "mean_distance", cager->GetMeanDistance() }, { "seconds", cager->GetSeconds() },
    { "output", cage_out } };

  // 3. the cage moved by the landmarks (3D Slicer markups)
  const std::string landmarks_file = (data / "organ_landmarks.mrk.json").string();
  const std::string moved_file = (data / "organ_landmarks_moved.mrk.json").string();
  auto landmarks = vtkBaryDataIO::ReadPolyData(landmarks_file);
  auto moved = vtkBaryDataIO::Read(moved_file);
  WeightsParameters tcc;
  tcc.method = bary::MethodId::TCelestial;
  tcc.threads = a.threads;
  auto posed = barylab::Deform(cage, landmarks, vtkPointSet::SafeDownCast(moved), tcc);
  vtkNew<vtkPolyData> posed_cage;
  posed_cage->SetPoints(posed->GetPoints());
  posed_cage->SetPolys(cage->GetPolys());
  const std::string posed_out = (out / "organ_cage_moved.obj").string();
  vtkBaryDataIO::Write(posed_cage, posed_out);
  summary["landmarks"] = { { "rest", landmarks_file }, { "moved", moved_file },
    { "count", landmarks->GetNumberOfPoints() }, { "cage_moved", posed_out } };

  // 4. the organ deformed by mean value coordinates of the cage
  WeightsParameters mvc;
  mvc.threads = a.threads;
  ProgressBar bar(true, "organ mvc");
  auto weighted = barylab::ComputeWeights(organ, cage, mvc, callbacks(bar, false));
  bar.done();
  auto deformed = barylab::Deform(vtkPointSet::SafeDownCast(weighted), cage, posed_cage, mvc);
  const std::string deformed_out = (out / "organ_deformed.vtp").string();
  vtkBaryDataIO::Write(deformed, deformed_out);
  summary["deformation"] = { { "method", "mvc" }, { "output", deformed_out } };

  // 5. the deformation as a displacement field on the label map's grid, with its inverse
  vtkNew<vtkBaryDisplacementField> field;
  field->GetWeightMethod()->SetSettings(mvc);
  field->SetRestCageData(cage);
  field->SetDeformedCageData(posed_cage);
  field->SetReferenceImageData(labels);
  field->ComputeInverseOn();
  barylab::RunAlgorithm(field, {}, bary::ErrorCode::InvalidArgument);
  const std::string field_out = (out / "organ_field.mha").string();
  const std::string inverse_out = (out / "organ_field_inverse.mha").string();
  vtkBaryImageIO::Write(field->GetOutput(0), field_out);
  vtkBaryImageIO::Write(field->GetOutput(1), inverse_out);
  // the field at the organ's points against the direct deformation
  const bary::DisplacementField u = vtkBaryDisplacementField::ToField(field->GetOutput(0));
  const bary::Points rest_points = vtkBaryConversion::PointsToMatrix(organ, 3);
  const bary::Points moved_points = bary::transform_points(u, rest_points, a.threads);
  double field_error = 0.0;
  for (vtkIdType i = 0; i < deformed->GetNumberOfPoints(); ++i)
  {
    double x[3];
    deformed->GetPoint(i, x);
    field_error = std::max(field_error,
      std::sqrt(std::pow(moved_points(i, 0) - x[0], 2) + std::pow(moved_points(i, 1) - x[1], 2) +
        std::pow(moved_points(i, 2) - x[2], 2)));
  }
  summary["field"] = { { "output", field_out }, { "inverse", inverse_out }, { "space", "LPS" },
    { "jacobian_minimum", field->GetJacobianMinimum() },
    { "folded_voxels", field->GetNumberOfFoldedVoxels() },
    { "inverse_max_residual", field->GetInverseMaximumResidual() },
    { "inverse_not_converged", field->GetInverseNotConverged() },
    { "inverse_not_converged_at_border", field->GetInverseNotConvergedAtBorder() },
    { "max_difference_at_organ_points", field_error } };

  // 6. the label map warped into the deformed space (nearest neighbour: labels kept)
  vtkNew<vtkBaryImageWarp> warp;
  warp->SetInputData(labels);
  warp->SetFieldData(field->GetOutput(1));
  warp->SetInterpolationToNearest();
  warp->SetNumberOfThreads(a.threads);
  barylab::RunAlgorithm(warp, {}, bary::ErrorCode::InvalidArgument);
  vtkSmartPointer<vtkImageData> warped = warp->GetOutput();
  const std::string warped_out = (out / "organ_label_warped.nii.gz").string();
  vtkBaryImageIO::Write(warped, warped_out);
  // the warped label's surface against the deformed surface (both from the same smoothing)
  vtkNew<vtkBaryLabelMapSurface> resegment;
  resegment->SetInputData(warped);
  resegment->SetLabel(1);
  barylab::RunAlgorithm(resegment, {}, bary::ErrorCode::InvalidArgument);
  const double surface_distance =
    max_distance_to_surface(vtkPointSet::SafeDownCast(deformed), resegment->GetOutput());
  const double* spacing = labels->GetSpacing();
  summary["warp"] = { { "output", warped_out }, { "interpolation", "nearest" },
    { "outside_voxels", warp->GetNumberOfOutsideVoxels() },
    { "label_volume_before", segment->GetLabelVolume() },
    { "label_volume_after", resegment->GetLabelVolume() },
    { "max_distance_deformed_to_warped_surface", surface_distance },
    { "voxel_diagonal", std::sqrt(spacing[0] * spacing[0] + spacing[1] * spacing[1] + spacing[2] * spacing[2]) } };
  summary["case_seconds"] =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cerr << "barylab: organ: surface of " << organ->GetNumberOfCells() << " triangles, cage of "
            << cage->GetNumberOfPoints() << " vertices (volume ratio " << cager->GetVolumeRatio()
            << "), field " << field_out << " (at the organ's points within " << field_error
            << " mm of the deformation), warped labels " << warped_out << " (surface within "
            << surface_distance << " mm of the deformed one)\n";
  if (a.render)
  {
    barylab::RenderOptions options;
    options.width = 1200;
    options.height = 600;
    options.component = 0;
    const std::string deformed_png = (out / "organ_deformed.png").string();
    barylab::WritePNG(barylab::DeformationWindow(weighted, cage, deformed, posed_cage, options), deformed_png);
    double b[6], center[3];
    organ->GetBounds(b);
    for (int k = 0; k < 3; ++k)
      center[k] = 0.5 * (b[2 * k] + b[2 * k + 1]);
    const std::string slice_png = (out / "organ_label_warped.png").string();
    barylab::WritePNG(barylab::LabelSliceWindow(labels, warped, organ,
                        vtkPolyData::SafeDownCast(deformed), center, options),
      slice_png);
    summary["images"] = { deformed_png, slice_png };
  }
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
                    "sparse weights, cage deformation), S-celestial coordinates (a heartbeat) and "
                    "weighted averages on a surface (a bumpy torus) and a C1 spline deformation "
                    "(an organism matched to its picture), and the organ workflow (a label map segmented, "
                    "an automatic cage, landmarks from 3D Slicer, a displacement field and the "
                    "warped label map) on bundled data";
  vtkSmartPointer<vtkDataSet> mvc2d;
  summary["cases"]["2d"] = demo_case(a, "gingerbread2d", "cage2d.obj", "cage2d_posed.obj",
    "model2d.obj", 14, &mvc2d);
  summary["cases"]["3d"] = demo_case(a, "kidney3d", "cage3d.obj", "cage3d_posed.obj",
    "model3d.off", -1);
  summary["cases"]["bbw2d"] = demo_bbw(a);
  summary["cases"]["lbc2d"] = demo_lbc(a, mvc2d);
  summary["cases"]["heart3d"] = demo_heart(a);
  summary["cases"]["torus_averages"] = demo_surface(a);
  summary["cases"]["spline2d"] = demo_spline_picture(a);
  summary["cases"]["organism_spline"] = demo_spline(a);
  summary["cases"]["organ"] = demo_organ(a);
  const std::string path = (fs::path(a.output_dir) / "summary.json").string();
  barylab::WriteJson(summary, path);
  std::cerr << "barylab: demo finished; summary in " << path << "\n";
  return 0;
}

} // namespace

void AddDemoCommand(Subcommands& subcommands)
{
  auto a = std::make_shared<DemoArgs>();
  auto no_render = std::make_shared<bool>(false);
  CLI::App* command = subcommands.Add("demo", "the main job: 2D and 3D pipelines on bundled data",
    [a, no_render] {
      a->render = !*no_render;
      return run_demo(*a);
    });
  command->add_option("--output-dir", a->output_dir, "where results go")
    ->default_val(a->output_dir);
  command->add_option("--data-dir", a->data_dir, "bundled data folder")->default_val(a->data_dir);
  command->add_option("--threads", a->threads, "threads (0 = all cores)")->default_val(0);
  command->add_flag("--no-render", *no_render, "skip the PNG images (no X display needed)");
}

} // namespace cli
} // namespace barylab
