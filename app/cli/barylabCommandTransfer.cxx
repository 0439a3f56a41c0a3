// barylab transfer: a correspondence between two surfaces from corresponding anchors
// (Panozzo et al. 2013, §4.3): the source's point data (texture coordinates, skinning weights,
// any array) transferred to the target, the map's distortion, and optionally a morph.

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
