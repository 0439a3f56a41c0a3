// The surface family's subcommands (weighted averages on surfaces, Panozzo et al. 2013):
//   barylab embed    the Euclidean embedding of a surface (§3.5)
//   barylab average  weighted averages of anchors (§3.3), or --inverse their weights (§3.4, §4.4),
//                    --anchor-uv a decal's texture coordinates (§4.2)
//   barylab curve    a cubic B-spline on the surface (§4.1)
//   barylab remesh   semiregular quad remeshing from a coarse layout (§4.1, Fig. 7)
//   barylab transfer point data from a source to a target surface through corresponding
//                    anchors, with a morph (§4.3)
// One file for the family (its commands share the embedding and output handling).

#include "barylabCli.h"
#include "barylabSurfacePipeline.h"

#include "vtkBaryConversion.h"
#include "vtkBaryDataIO.h"

#include "core/common/error.h"
#include "core/surface/surface_curves.h"

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
namespace
{

struct EmbedArgs
{
  bary::EmbeddingOptions options;
  std::string mesh, output, json_path, landmark_method = "decimation";
  bool quiet = false;
};

int run_embed(const EmbedArgs& a)
{
  check_output(a.output, OutputKind::Text, { a.mesh });
  if (!a.json_path.empty())
    check_output(a.json_path, OutputKind::Json, { a.mesh, a.output });
  bary::EmbeddingOptions options = a.options;
  options.landmark_method = a.landmark_method == "decimation" ? bary::LandmarkMethod::Decimation
                                                               : bary::LandmarkMethod::FarthestPoint;
  try
  {
    bary::validate_embedding_options(options);
  }
  catch (const bary::Error& e)
  {
    throw UsageError(e.what());
  }
  auto surface = ReadSurface(a.mesh);
  ProgressBar bar(!a.quiet, "embedding");
  json summary;
  auto embedded = ComputeEmbedding(surface, options, callbacks(bar, a.quiet), &summary);
  bar.done();
  WriteEmbedding(embedded, a.output);
  summary["mesh"] = a.mesh;
  summary["output"] = a.output;
  if (!a.json_path.empty())
    WriteJson(summary, a.json_path);
  if (!a.quiet)
  {
    const json& q = summary["quality"];
    const json& st = summary["stress"];
    std::cerr << "barylab: embedding in R^" << summary["dimension"] << " of " << summary["vertices"]
              << " vertices from " << summary["landmarks"] << " landmarks ("
              << summary["landmark_method"].get<std::string>() << ")\n"
              << "stress (14) per pair       " << st["classical_mds"].get<double>()
              << " (classical MDS) -> " << st["final"].get<double>() << " after "
              << st["smacof_iterations"] << " SMACOF iterations"
              << (st["smacof_converged"].get<bool>() ? "" : " (iteration cap reached)") << "\n"
              << "distance error vs geodesic mean " << q["mean_relative_error"].get<double>()
              << ", median " << q["median_relative_error"].get<double>() << ", max "
              << q["max_relative_error"].get<double>() << " (relative, " << q["pairs"]
              << " pairs)\n"
              << "seconds                    " << summary["seconds"]["total"].get<double>() << "\n";
  }
  return 0;
}

} // namespace

void AddEmbedCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<EmbedArgs>("embed",
    "weighted averages: the Euclidean embedding of a surface (landmarks, geodesics, SMACOF MDS, "
    "least-squares upsampling)",
    run_embed);
  command->add_option("--mesh,-m", a->mesh, "triangle surface (one connected manifold piece)")
    ->required();
  command->add_option("--output,-o", a->output,
    "embedding: text (one line per mesh vertex, D numbers) or .vtp/.vtu/.vtk (the surface with "
    "an 'Embedding' array)")
    ->required();
  command->add_option("--dimension,-d", a->options.dimension, "embedding dimension D [2, 64]")
    ->default_val(a->options.dimension);
  command->add_option("--landmarks,-l", a->options.landmarks,
    "number of landmarks [D + 2, 100000] (all vertices when the mesh has fewer)")
    ->default_val(a->options.landmarks);
  command->add_option("--landmark-method", a->landmark_method,
    "decimation: the vertices left by normal-preserving edge collapses (the paper's); "
    "farthest-point: farthest-point samples")
    ->default_val(a->landmark_method)
    ->check(CLI::IsMember({ "decimation", "farthest-point" }));
  command->add_option("--stress-tolerance", a->options.stress_tolerance,
    "SMACOF stops when an iteration lowers the stress by less than this fraction [1e-14, 0.1]")
    ->default_val(a->options.stress_tolerance);
  command->add_option("--max-iterations", a->options.max_iterations,
    "SMACOF iteration cap [0, 100000] (0: classical MDS only)")
    ->default_val(a->options.max_iterations);
  command->add_option("--heat-time-factor", a->options.heat_time_factor,
    "heat-method time step t = factor x (mean edge length)^2, (0, 1e6]")
    ->default_val(a->options.heat_time_factor);
  command->add_option("--quality-sources", a->options.quality_sources,
    "sources of the distance-error report [0, 1000] (0: skip)")
    ->default_val(a->options.quality_sources);
  command->add_option("--threads", a->options.threads, "OpenMP threads (0: all cores)")
    ->default_val(a->options.threads);
  command->add_option("--json", a->json_path,
    "write a JSON summary (landmarks, stress, quality, seconds per stage)");
  command->add_flag("--quiet,-q", a->quiet, "no progress bar or summary (errors still)");
}

} // namespace cli
} // namespace barylab

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

namespace barylab
{
namespace cli
{
namespace
{

struct CurveArgs
{
  std::string mesh, embedding, save_embedding, controls, output, json_path;
  int samples = 16, threads = 0;
  bool closed = false, quiet = false;
  double surface_tolerance = bary::kDefaultSurfaceTolerance;
};

int run_curve(const CurveArgs& a)
{
  try
  {
    bary::bspline_weights(4, a.samples, false); // the range of --samples, from core
    bary::validate_surface_tolerance(a.surface_tolerance);
    bary::validate_forward_options([&] {
      bary::ForwardOptions o;
      o.threads = a.threads;
      return o;
    }());
  }
  catch (const bary::Error& e)
  {
    throw UsageError(e.what());
  }
  check_surface_outputs(a.output, a.json_path, a.save_embedding, { a.mesh, a.embedding, a.controls });
  json summary;
  auto embedded = embedded_surface(a.mesh, a.embedding, a.save_embedding, a.quiet, summary);
  auto controls = ReadSurfacePoints(a.controls);
  json c;
  auto curve = SurfaceCurve(embedded, controls, a.samples, a.closed, a.surface_tolerance, a.threads, {}, &c);
  if (vtkBaryDataIO::Extension(a.output) == ".txt")
    WritePointsText(curve, a.output);
  else
    vtkBaryDataIO::Write(curve, a.output);
  summary["curve"] = c;
  summary["controls"] = a.controls;
  summary["output"] = a.output;
  if (!a.json_path.empty())
    WriteJson(summary, a.json_path);
  if (!a.quiet)
    std::cerr << "barylab: B-spline on the surface: " << c["samples"] << " samples of "
              << c["control_points"] << " control points, " << c["failures"] << " failed\n";
  return 0;
}

} // namespace

void AddCurveCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<CurveArgs>("curve",
    "weighted averages: a cubic B-spline on a surface from control points on it", run_curve);
  command->add_option("--mesh,-m", a->mesh, "triangle surface (one connected manifold piece)")
    ->required();
  command->add_option("--embedding,-e", a->embedding,
    "its embedding (barylab embed); computed with the defaults when absent");
  command->add_option("--save-embedding", a->save_embedding,
    "write the embedding computed for want of --embedding");
  command->add_option("--controls,-c", a->controls,
    "control points on the surface, in curve order: a data file's points or text x y z a line")
    ->required();
  command->add_option("--output,-o", a->output,
    "the curve: .vtp/.vtu/.vtk (polylines, FaceId, Barycentric, Valid) or .txt (x y z a line)")
    ->required();
  command->add_option("--samples", a->samples, "samples per segment of the uniform cubic B-spline")
    ->default_val(a->samples);
  command->add_flag("--closed", a->closed, "a closed (periodic) curve");
  command->add_option("--surface-tolerance", a->surface_tolerance,
    "control points farther than this x the surface's diagonal are refused")
    ->default_val(a->surface_tolerance);
  command->add_option("--threads", a->threads, "OpenMP threads (0: all cores)")->default_val(0);
  command->add_option("--json", a->json_path, "write a JSON summary");
  command->add_flag("--quiet,-q", a->quiet, "no progress bar or summary (errors still)");
}

} // namespace cli
} // namespace barylab

namespace barylab
{
namespace cli
{
namespace
{

struct RemeshArgs
{
  std::string mesh, embedding, save_embedding, coarse, output, json_path;
  bary::RemeshOptions options;
  double surface_tolerance = bary::kDefaultSurfaceTolerance;
  bool quiet = false;
};

int run_remesh(const RemeshArgs& a)
{
  try
  {
    bary::validate_remesh_options(a.options);
    bary::validate_surface_tolerance(a.surface_tolerance);
  }
  catch (const bary::Error& e)
  {
    throw UsageError(e.what());
  }
  check_surface_outputs(a.output, a.json_path, a.save_embedding, { a.mesh, a.embedding, a.coarse });
  const std::string ext = vtkBaryDataIO::Extension(a.output);
  if (ext == ".txt")
    throw UsageError("a quad mesh is written as .vtp, .vtu or .vtk");
  json summary;
  auto embedded = embedded_surface(a.mesh, a.embedding, a.save_embedding, a.quiet, summary);
  auto coarse = vtkBaryDataIO::ReadPolyData(a.coarse);
  json r;
  auto result = Remesh(embedded, coarse, a.options, a.surface_tolerance, {}, &r);
  vtkBaryDataIO::Write(result, a.output);
  summary["remesh"] = r;
  summary["coarse"] = a.coarse;
  summary["output"] = a.output;
  if (!a.json_path.empty())
    WriteJson(summary, a.json_path);
  if (!a.quiet)
    std::cerr << "barylab: remeshed " << r["coarse_quads"] << " coarse quads into " << r["quads"]
              << " (" << r["vertices"] << " vertices, " << r["failures"] << " failed)\n";
  return 0;
}

} // namespace

void AddRemeshCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<RemeshArgs>("remesh",
    "weighted averages: semiregular quad remeshing of a surface from a coarse quad layout on it",
    run_remesh);
  command->add_option("--mesh,-m", a->mesh, "triangle surface (one connected manifold piece)")
    ->required();
  command->add_option("--embedding,-e", a->embedding,
    "its embedding (barylab embed); computed with the defaults when absent");
  command->add_option("--save-embedding", a->save_embedding,
    "write the embedding computed for want of --embedding");
  command->add_option("--coarse,-c", a->coarse,
    "the coarse quad layout: a polygon file of quads whose vertices lie on the surface")
    ->required();
  command->add_option("--output,-o", a->output, "the quad mesh (.vtp, .vtu, .vtk)")->required();
  command->add_option("--levels", a->options.levels, "subdivision levels (x4 quads each) [0, " + std::to_string(bary::kMaxRemeshLevels) + "]")
    ->default_val(a->options.levels);
  command->add_option("--smooth", a->options.smoothing_steps,
    "Laplacian smoothing steps on the surface [0, 1000]")
    ->default_val(a->options.smoothing_steps);
  command->add_option("--surface-tolerance", a->surface_tolerance,
    "coarse vertices farther than this x the surface's diagonal are refused")
    ->default_val(a->surface_tolerance);
  command->add_option("--threads", a->options.threads, "OpenMP threads (0: all cores)")->default_val(0);
  command->add_option("--json", a->json_path, "write a JSON summary");
  command->add_flag("--quiet,-q", a->quiet, "no progress bar or summary (errors still)");
}

} // namespace cli
} // namespace barylab

namespace barylab
{
namespace cli
{
namespace
{

struct TransferArgs
{
  std::string source, source_embedding, source_anchors, target, target_embedding, target_anchors;
  std::string output, json_path, morph_dir;
  std::vector<std::string> arrays;
  int morph_frames = 0;
  bool quiet = false;
  bary::CorrespondenceOptions options;
  double surface_tolerance = bary::kDefaultSurfaceTolerance;
};

int run_transfer(const TransferArgs& a)
{
  try
  {
    bary::validate_inverse_options(a.options.inverse);
    bary::validate_round_trip_tolerance(a.options.round_trip_tolerance);
    bary::validate_surface_tolerance(a.surface_tolerance);
  }
  catch (const bary::Error& e)
  {
    throw UsageError(e.what());
  }
  if (a.morph_frames < 0 || a.morph_frames > 10000)
    throw UsageError("--morph takes a number of frames in [1, 10000]");
  if (a.morph_frames > 0 && a.morph_dir.empty())
    throw UsageError("--morph needs --morph-dir (where the frames and the .pvd go)");
  const std::vector<std::string> inputs = { a.source, a.source_embedding, a.source_anchors, a.target,
    a.target_embedding, a.target_anchors };
  check_output(a.output, OutputKind::Data, inputs);
  const std::string ext = vtkBaryDataIO::Extension(a.output);
  if (ext != ".vtp" && ext != ".vtu" && ext != ".vtk")
    throw bary::Error(bary::ErrorCode::Io, "cannot write '" + a.output +
        "': the transferred arrays are point data, kept only by .vtp, .vtu or .vtk");
  if (!a.json_path.empty())
    check_output(a.json_path, OutputKind::Json, inputs);
  json summary;
  json source_summary, target_summary;
  auto source = embedded_surface(a.source, a.source_embedding, "", a.quiet, source_summary);
  auto target = embedded_surface(a.target, a.target_embedding, "", a.quiet, target_summary);
  summary["source"] = source_summary;
  summary["target"] = target_summary;
  auto source_anchors = ReadSurfacePoints(a.source_anchors);
  auto target_anchors = ReadSurfacePoints(a.target_anchors);
  ProgressBar bar(!a.quiet, "transfer");
  json t;
  auto result = Transfer(target, target_anchors, source, source_anchors, a.arrays, a.options,
    a.surface_tolerance, callbacks(bar, a.quiet), &t);
  bar.done();
  vtkBaryDataIO::Write(result, a.output);
  summary["transfer"] = t;
  summary["output"] = a.output;
  if (a.morph_frames > 0)
    summary["morph"] = WriteMorph(result, a.morph_frames, a.morph_dir, "morph");
  if (!a.json_path.empty())
    WriteJson(summary, a.json_path);
  if (!a.quiet)
    std::cerr << "barylab: transfer to " << t["target_points"] << " target points through "
              << t["anchors"] << " anchors: " << t["undefined"]
              << " undefined (not weighted averages of the anchors, or no image); "
              << t["flipped_triangles"] << " flipped triangles ("
              << 100.0 * t["flipped_area_fraction"].get<double>() << "% of the area); stretch "
              << t["stretch"]["all"].get<double>() << " (best 95%: "
              << t["stretch"]["best_95_percent"].get<double>() << ")\n";
  return 0;
}

} // namespace

void AddTransferCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<TransferArgs>("transfer",
    "weighted averages: transfer point data from a source surface to a target through "
    "corresponding anchors (and morph between them)",
    run_transfer);
  command->add_option("--source", a->source, "source surface, carrying the point data")->required();
  command->add_option("--source-embedding", a->source_embedding,
    "its embedding (barylab embed); computed when absent");
  command->add_option("--source-anchors", a->source_anchors, "anchors on the source (x y z a line, or a data file)")
    ->required();
  command->add_option("--target", a->target, "target surface")->required();
  command->add_option("--target-embedding", a->target_embedding,
    "its embedding (barylab embed); computed when absent");
  command->add_option("--target-anchors", a->target_anchors,
    "anchors on the target, in the source anchors' order")
    ->required();
  command->add_option("--output,-o", a->output,
    "the target with the transferred arrays, Defined, SourcePosition, Stretch, Flipped "
    "(.vtp, .vtu, .vtk)")
    ->required();
  command->add_option("--array", a->arrays,
    "a source point array to transfer (repeat; default: all but the embedding)");
  command->add_option("--gamma", a->options.inverse.gamma, "the inverse problem's gamma")
    ->default_val(a->options.inverse.gamma);
  command->add_option("--round-trip-tolerance", a->options.round_trip_tolerance,
    "target points whose round trip lands farther than this x the mean edge length are undefined")
    ->default_val(a->options.round_trip_tolerance);
  command->add_option("--surface-tolerance", a->surface_tolerance,
    "anchors farther than this x the surface's diagonal are refused")
    ->default_val(a->surface_tolerance);
  command->add_option("--morph", a->morph_frames,
    "also write a morph from the target to its image on the source in N + 1 frames");
  command->add_option("--morph-dir", a->morph_dir, "folder for the morph's frames and morph.pvd");
  command->add_option("--json", a->json_path, "write a JSON summary");
  command->add_flag("--quiet,-q", a->quiet, "no progress bar or summary (errors still)");
}

} // namespace cli
} // namespace barylab
