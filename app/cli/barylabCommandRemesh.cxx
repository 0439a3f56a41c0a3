// barylab remesh: semiregular remeshing of a surface from a coarse quad layout on it, by
// weighted averages (Panozzo et al. 2013, §4.1, Fig. 7).

#include "barylabCli.h"
#include "barylabSurfacePipeline.h"

#include "vtkBaryDataIO.h"

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
  command->add_option("--levels", a->options.levels, "subdivision levels (x4 quads each) [0, 8]")
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
