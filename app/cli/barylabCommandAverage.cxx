// barylab average: weighted averages of anchor points on a surface (the forward problem of
// Panozzo et al. 2013, §3.3), or with --inverse the weights of points w.r.t. the anchors (§3.4)
// with the round trip of §4.4.
//
//   barylab average --mesh M [--embedding E.txt] --anchors A --weights W --output OUT
//   barylab average --inverse --mesh M [--embedding E.txt] --anchors A --points Q --output W.txt

#include "barylabCli.h"
#include "barylabSurfacePipeline.h"

#include "vtkBaryConversion.h"
#include "vtkBaryDataIO.h"

#include "core/common/error.h"

#include "vtkDataArray.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"

#include <CLI/CLI.hpp>

#include <iostream>

using nlohmann::json;

namespace barylab
{
namespace cli
{
void check_surface_outputs(const std::string& output, const std::string& json_path,
  const std::string& save, const std::vector<std::string>& inputs)
{
  check_output(output, OutputKind::Text, inputs);
  if (!json_path.empty())
    check_output(json_path, OutputKind::Json, inputs);
  if (!save.empty())
    check_output(save, OutputKind::Text, inputs);
}

vtkSmartPointer<vtkPolyData> embedded_surface(const std::string& mesh,
  const std::string& embedding, const std::string& save, bool quiet, json& summary)
{
  auto surface = ReadSurface(mesh);
  summary["mesh"] = mesh;
  if (!embedding.empty())
  {
    summary["embedding"] = { { "file", embedding } };
    return AttachEmbedding(surface, embedding);
  }
  ProgressBar bar(!quiet, "embedding");
  json e;
  auto embedded = ComputeEmbedding(surface, bary::EmbeddingOptions{}, callbacks(bar, quiet), &e);
  bar.done();
  summary["embedding"] = e;
  summary["embedding"]["file"] = save.empty() ? "(computed)" : save;
  if (!save.empty())
    WriteEmbedding(embedded, save);
  else if (!quiet)
    std::cerr << "barylab: note: the embedding was computed (" << e["seconds"]["total"].get<double>()
              << " s); keep it with --save-embedding or barylab embed, and pass --embedding\n";
  return embedded;
}

namespace
{

struct AverageArgs
{
  std::string mesh, embedding, save_embedding, anchors, weights, points, output, json_path, anchor_uv;
  bool inverse = false, brute_force = false, quiet = false;
  bary::ForwardOptions forward;
  bary::InverseOptions inverse_options;
  double surface_tolerance = bary::kDefaultSurfaceTolerance;
  double round_trip_tolerance = bary::kDefaultRoundTripTolerance;
};

int run_average(const AverageArgs& a)
{
  if (a.inverse && !a.weights.empty())
    throw UsageError("--inverse computes weights: give --points, not --weights");
  if (a.inverse && a.points.empty())
    throw UsageError("--inverse needs --points (the points whose weights are computed)");
  if (!a.inverse && a.weights.empty())
    throw UsageError("give --weights (one row of weights per query), or --inverse with --points");
  if (!a.inverse && !a.points.empty())
    throw UsageError("--points is for --inverse; the forward problem takes --weights");
  if (!a.anchor_uv.empty() && (!a.inverse || vtkBaryDataIO::Extension(a.output) == ".txt"))
    throw UsageError("--anchor-uv is for --inverse with a .vtp/.vtu/.vtk output (the points "
                     "carry the TCoords array)");
  bary::InverseOptions inverse_options = a.inverse_options;
  inverse_options.threads = a.forward.threads;
  try
  {
    bary::validate_forward_options(a.forward);
    bary::validate_inverse_options(inverse_options);
    bary::validate_surface_tolerance(a.surface_tolerance);
    bary::validate_round_trip_tolerance(a.round_trip_tolerance);
  }
  catch (const bary::Error& e)
  {
    throw UsageError(e.what());
  }
  check_surface_outputs(a.output, a.json_path, a.save_embedding,
    { a.mesh, a.embedding, a.anchors, a.weights, a.points, a.anchor_uv });

  json summary;
  auto embedded = embedded_surface(a.mesh, a.embedding, a.save_embedding, a.quiet, summary);
  auto anchors = ReadSurfacePoints(a.anchors);
  summary["anchors"] = { { "file", a.anchors }, { "count", anchors->GetNumberOfPoints() } };

  const std::string ext = vtkBaryDataIO::Extension(a.output);
  if (!a.inverse)
  {
    const Eigen::MatrixXd W = vtkBaryDataIO::ReadMatrix(a.weights);
    if (W.cols() != anchors->GetNumberOfPoints())
      throw bary::Error(bary::ErrorCode::SizeMismatch, "'" + a.weights + "' has " +
          std::to_string(W.cols()) + " weights a row but there are " +
          std::to_string(anchors->GetNumberOfPoints()) + " anchors (one column per anchor)");
    bary::ForwardOptions options = a.forward;
    options.search = a.brute_force ? bary::ForwardOptions::Search::BruteForce
                                   : bary::ForwardOptions::Search::Local;
    ProgressBar bar(!a.quiet, "averages");
    json f;
    auto result = WeightedAverage(embedded, anchors, W, options, a.surface_tolerance,
      callbacks(bar, a.quiet), &f);
    bar.done();
    if (ext == ".txt")
      WritePointsText(result, a.output);
    else
      vtkBaryDataIO::Write(result, a.output);
    summary["forward"] = f;
    summary["weights"] = a.weights;
    summary["output"] = a.output;
    if (!a.json_path.empty())
      WriteJson(summary, a.json_path);
    if (!a.quiet)
      std::cerr << "barylab: " << f["queries"] << " weighted averages of " << f["anchors"]
                << " anchors: " << f["failures"] << " failed (no Phong projection found), "
                << f["microseconds_per_query"].get<double>() << " us per query\n";
    return 0;
  }

  auto points = ReadSurfacePoints(a.points);
  ProgressBar bar(!a.quiet, "weights");
  json inv;
  Eigen::MatrixXd uv;
  if (!a.anchor_uv.empty())
  {
    uv = vtkBaryDataIO::ReadMatrix(a.anchor_uv);
    if (uv.cols() != 2 || uv.rows() != anchors->GetNumberOfPoints())
      throw bary::Error(bary::ErrorCode::SizeMismatch, "'" + a.anchor_uv + "' has " +
          std::to_string(uv.rows()) + " lines of " + std::to_string(uv.cols()) + " numbers; " +
          std::to_string(anchors->GetNumberOfPoints()) + " lines 'u v' are needed, one per anchor");
  }
  auto result = SurfaceWeights(points, embedded, anchors, inverse_options, a.surface_tolerance,
    a.round_trip_tolerance, callbacks(bar, a.quiet), &inv, a.anchor_uv.empty() ? nullptr : &uv);
  bar.done();
  if (ext == ".txt")
    vtkBaryDataIO::WriteMatrix(
      vtkBaryConversion::ArrayToMatrix(result->GetPointData()->GetArray("Weights")), a.output);
  else
    vtkBaryDataIO::Write(result, a.output);
  summary["inverse"] = inv;
  summary["points"] = a.points;
  summary["output"] = a.output;
  if (!a.json_path.empty())
    WriteJson(summary, a.json_path);
  if (!a.quiet)
  {
    const json& rt = inv["round_trip"];
    std::cerr << "barylab: weights of " << inv["points"] << " points w.r.t. " << inv["anchors"]
              << " anchors, " << inv["microseconds_per_query"].get<double>() << " us per point\n"
              << "barylab: round trip (forward of the weights): median error "
              << rt["median_error"].get<double>() << ", max " << rt["max_error"].get<double>()
              << "; " << rt["not_returned"] << " point(s) do not return (their weights are "
              << "meaningless: not a weighted average of these anchors)\n";
  }
  return 0;
}

} // namespace

void AddAverageCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<AverageArgs>("average",
    "weighted averages of anchor points on a surface, or (--inverse) the weights of points",
    run_average);
  command->add_option("--mesh,-m", a->mesh, "triangle surface (one connected manifold piece)")
    ->required();
  command->add_option("--embedding,-e", a->embedding,
    "its embedding (barylab embed: text, one line per mesh vertex; or .vtp with 'Embedding'); "
    "computed with the defaults when absent");
  command->add_option("--save-embedding", a->save_embedding,
    "write the embedding computed for want of --embedding (text or .vtp)");
  command->add_option("--anchors,-a", a->anchors,
    "anchor points on the surface: a data file (its points) or text, x y z a line")
    ->required();
  command->add_option("--weights,-w", a->weights,
    "forward: a text matrix, one row of weights per query (one column per anchor, summing to 1)");
  command->add_flag("--inverse", a->inverse,
    "compute the weights of --points w.r.t. the anchors (the inverse problem)");
  command->add_option("--points,-p", a->points,
    "--inverse: points on the surface (a data file's points, or text x y z a line)");
  command->add_option("--output,-o", a->output,
    "forward: .vtp/.vtu/.vtk (points with FaceId, Barycentric, Valid) or .txt (x y z a line, nan "
    "where a query failed); --inverse: .txt (one row of weights per point) or .vtp/.vtu/.vtk "
    "(the points with Weights, FaceId, Barycentric, RoundTripError, Defined)")
    ->required();
  command->add_option("--anchor-uv", a->anchor_uv,
    "--inverse: the anchors' texture coordinates (text, 'u v' a line, one per anchor): the "
    "output gets TCoords = sum w_i uv_i, a local parametrisation / decal (NaN where not Defined)");
  command->add_flag("--brute-force", a->brute_force,
    "forward: project onto every triangle and keep the closest (validation; slow)");
  command->add_flag("--warm-start", a->forward.warm_start,
    "forward: start each query from the previous result (rows in path order, e.g. a curve)");
  command->add_option("--max-triangles", a->forward.max_triangles,
    "forward: triangles a query may try before it is reported failed (0: all)")
    ->default_val(a->forward.max_triangles);
  command->add_option("--gamma", a->inverse_options.gamma,
    "--inverse: weight of the anchors' distance off the tangent plane (the paper's gamma)")
    ->default_val(a->inverse_options.gamma);
  command->add_option("--round-trip-tolerance", a->round_trip_tolerance,
    "--inverse: a point whose round trip lands farther than this x the mean edge length is "
    "marked undefined")
    ->default_val(a->round_trip_tolerance);
  command->add_option("--surface-tolerance", a->surface_tolerance,
    "anchors and points farther than this x the surface's diagonal are refused as off the surface")
    ->default_val(a->surface_tolerance);
  command->add_option("--threads", a->forward.threads, "OpenMP threads (0: all cores)")
    ->default_val(a->forward.threads);
  command->add_option("--json", a->json_path,
    "write a JSON summary (counts, failures, time per query, round trip)");
  command->add_flag("--quiet,-q", a->quiet, "no progress bar or summary (errors still)");
}

} // namespace cli
} // namespace barylab
