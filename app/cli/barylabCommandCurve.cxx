// barylab curve: a cubic B-spline on a surface whose control points lie on it, as weighted
// averages (Panozzo et al. 2013, §4.1): one forward problem per sample, each from the previous.

#include "barylabCli.h"
#include "barylabSurfacePipeline.h"

#include "vtkBaryDataIO.h"

#include "core/common/error.h"
#include "core/surface/surface_curves.h"

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
