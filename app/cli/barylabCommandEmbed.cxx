// barylab embed: the Euclidean embedding of a surface for weighted averages (Panozzo et al. 2013,
// §3.5), written as text (one line per mesh vertex, D numbers) or with the surface (.vtp).

#include "barylabCli.h"
#include "barylabSurfacePipeline.h"

#include "core/common/error.h"

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
