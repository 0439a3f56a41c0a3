// barylab animate: a model deformed by a sequence of moved cages / control points.

#include "barylabCli.h"

#include "vtkBaryDataIO.h"

#include "core/common/error.h"

#include "vtkDataSet.h"
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

struct AnimateArgs
{
  WeightsParameters parameters;
  std::string cage, controls, points, output_dir, prefix = "animation", json_path, user_weights;
  std::vector<std::string> frames;
  double period = 1.0;
  bool quiet = false;
  FrameTransformOptions transforms; ///< per-frame displacement fields / warped label maps
};

int run_animate(AnimateArgs a)
{
  if (a.parameters.method == bary::MethodId::BBW)
    throw UsageError("animate moves cages or control points; for skeletons use 'deform --method bbw' per pose");
  if (!a.controls.empty() && !a.cage.empty())
    throw UsageError("give --cage or --control-points, not both");
  check_bbw_inputs(a.parameters.method, a.controls.empty() ? a.cage : a.controls, "", "",
    !a.controls.empty());
  if (!a.controls.empty())
    a.cage = a.controls;
  if (!a.user_weights.empty() && a.parameters.method != bary::MethodId::TCelestial)
    throw UsageError("--user-weights is for --method tcc (Eq. 8's s_i)");
  a.parameters.user_weights = read_user_weights(a.user_weights);
  a.transforms.Check();
  if (a.transforms.Any() && ProcessCount() > 1)
    throw UsageError("--displacement-fields and --warp-image are written by a serial run");
  // Distributed: the weights are computed on the model's pieces (one solve per cage) and
  // gathered; process r deforms and writes frames r, r + K, ...; process 0 writes the .pvd.
  const int rank = ProcessRank(), K = ProcessCount();
  vtkSmartPointer<vtkPolyData> cage;
  std::vector<vtkSmartPointer<vtkPointSet>> frames(a.frames.size());
  vtkSmartPointer<vtkDataSet> model, piece;
  Collective([&]() {
    if (!a.json_path.empty())
      check_output(a.json_path, OutputKind::Json);
    cage = vtkBaryDataIO::ReadPolyData(a.cage);
    for (std::size_t f = static_cast<std::size_t>(rank); f < a.frames.size(); f += static_cast<std::size_t>(K))
    {
      auto data = vtkBaryDataIO::Read(a.frames[f]);
      vtkSmartPointer<vtkPointSet> set = vtkPointSet::SafeDownCast(data);
      if (!set || set->GetNumberOfPoints() != cage->GetNumberOfPoints())
        throw bary::Error(bary::ErrorCode::SizeMismatch,
          "frame '" + a.frames[f] + "' must hold the " + std::to_string(cage->GetNumberOfPoints()) +
            " points of '" + a.cage + "', moved (same order)");
      frames[f] = set;
    }
    model = vtkBaryDataIO::Read(a.points); // a .pvtp / .pvtu: all its pieces
    piece = SplitPiece(model);
  });
  const bool lead = rank == 0;
  ProgressBar bar(!a.quiet && lead, "weights");
  json summary;
  vtkSmartPointer<vtkDataSet> weighted;
  Collective([&]() {
    weighted = barylab::ComputeWeights(
      piece, cage, a.parameters, callbacks(bar, a.quiet || !lead), &summary);
  });
  bar.done();
  Collective([&]() { weighted = GatherPointArrays(model, weighted); });
  json animation;
  std::string pvd;
  Collective([&]() {
    pvd = barylab::WriteAnimation(vtkPointSet::SafeDownCast(weighted), cage, frames,
      a.parameters, a.output_dir, a.prefix, a.period, &animation, lead);
  });
  summary["animation"] = animation;
  if (!lead)
    return 0;
  if (a.transforms.Any())
    summary["transforms"] = WriteFrameTransforms(cage, frames, a.parameters, a.transforms,
      a.output_dir, a.prefix, a.quiet);
  if (!a.json_path.empty())
    barylab::WriteJson(summary, a.json_path);
  if (!a.quiet)
    std::cerr << "barylab: wrote " << frames.size() << " frames and " << pvd << " ("
              << animation["seconds_per_frame"].get<double>() * 1e3 << " ms per frame"
              << (K > 1 ? " on process 0, " + std::to_string(K) + " processes" : std::string())
              << ")\n";
  return 0;
}

} // namespace

void AddAnimateCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<AnimateArgs>("animate",
    "deform a model by a sequence of moved cages / control points: frames + a ParaView .pvd",
    run_animate);
  command->add_option("--cage,-c", a->cage, "rest cage");
  command->add_option("--control-points", a->controls, "tcc|scc: rest control points");
  command->add_option("--frames", a->frames, "moved cages / control points, one file per frame")
    ->required()
    ->expected(1, -1);
  command->add_option("--points,-p", a->points, "model to deform")->required();
  command->add_option("--output-dir", a->output_dir, "folder for the frames and the .pvd")
    ->required();
  command->add_option("--prefix", a->prefix, "file name prefix (a name, not a path)")
    ->default_val(a->prefix)
    ->check(CLI::Validator(
      [](std::string& prefix) -> std::string {
        if (prefix.empty() || prefix.find_first_of("/\\") != std::string::npos ||
          prefix == "." || prefix == "..")
          return "the prefix must be a file name without '/' (the frames are written inside "
                 "--output-dir)";
        return {};
      },
      "NAME", ""));
  command->add_option("--period", a->period, "time of the whole sequence (the .pvd's time steps)")
    ->default_val(1.0)
    ->check(FiniteRange(1e-300, 1e300, "> 0"));
  command->add_option("--user-weights", a->user_weights, "tcc: s_i of Eq. 8 (text or .dmat)");
  command->add_option("--json", a->json_path, "write a JSON summary");
  command->add_flag("--quiet,-q", a->quiet, "no progress bar or summary");
  add_frame_transform_options(command, a->transforms);
  add_method_options(command, a->parameters);
}

} // namespace cli
} // namespace barylab
