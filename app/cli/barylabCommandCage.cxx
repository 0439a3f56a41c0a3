// barylab cage: a coarse cage that strictly encloses a model (automatic cage generation,
// vtkBaryEnclosingCage over bary::enclosing_cage; docs/cage-generation.md).

#include "barylabCli.h"

#include "vtkBaryDataIO.h"
#include "vtkBaryEnclosingCage.h"

#include "core/common/error.h"

#include "vtkPolyData.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <iostream>
#include <limits>

using nlohmann::json;

namespace barylab
{
namespace cli
{
namespace
{

struct CageArgs
{
  std::string model, output, json_path;
  int vertices = 100;
  double margin = 0.0;
  double margin_fraction = 0.05;
  double resolution = 2.0;
  int tighten_rounds = 4;
  double clearance = 0.25;
  bool quiet = false;
};

// A JSON number, or null for NaN (an open 3D model has no volume).
json number(double x)
{
  return std::isfinite(x) ? json(x) : json(nullptr);
}

int run_cage(const CageArgs& a)
{
  check_output(a.output, OutputKind::Data, { a.model });
  if (!a.json_path.empty())
    check_output(a.json_path, OutputKind::Json, { a.model, a.output });
  auto model = vtkBaryDataIO::ReadPolyData(a.model);
  vtkNew<vtkBaryEnclosingCage> filter;
  filter->SetInputData(model);
  filter->SetNumberOfVertices(a.vertices);
  filter->SetMargin(a.margin);
  filter->SetMarginFraction(a.margin_fraction);
  filter->SetResolution(a.resolution);
  filter->SetTightenRounds(a.tighten_rounds);
  filter->SetClearance(a.clearance);
  ProgressBar bar(!a.quiet, "cage");
  RunAlgorithm(filter, callbacks(bar, a.quiet), bary::ErrorCode::InvalidArgument);
  bar.done();
  vtkPolyData* cage = filter->GetOutput();
  vtkBaryDataIO::Write(cage, a.output);
  const bool planar = cage->GetNumberOfCells() == 1 && cage->GetCellType(0) != VTK_TRIANGLE;
  json summary;
  summary["model"] = a.model;
  summary["output"] = a.output;
  summary["dimension"] = planar ? 2 : 3;
  summary["target_vertices"] = a.vertices;
  summary["vertices"] = cage->GetNumberOfPoints();
  summary["faces"] = planar ? cage->GetNumberOfPoints() : cage->GetNumberOfCells();
  summary["reached_target"] = filter->GetReachedTarget();
  summary["stop_reason"] = filter->GetStopReason();
  summary["collapses"] = filter->GetCollapses();
  summary["tighten_moves"] = filter->GetTightenMoves();
  summary["margin"] = filter->GetMarginUsed();
  summary["offset_vertices"] = filter->GetOffsetVertices();
  summary["model_measure"] = number(filter->GetModelMeasure());
  summary["cage_measure"] = number(filter->GetCageMeasure());
  summary["measure_ratio"] = number(filter->GetVolumeRatio());
  summary["max_distance"] = filter->GetMaximumDistance();
  summary["mean_distance"] = filter->GetMeanDistance();
  summary["diagonal"] = filter->GetDiagonal();
  summary["seconds"] = filter->GetSeconds();
  if (!a.json_path.empty())
    barylab::WriteJson(summary, a.json_path);
  if (!a.quiet)
  {
    std::cerr << "barylab: cage of " << cage->GetNumberOfPoints() << " vertices";
    if (!planar)
      std::cerr << ", " << cage->GetNumberOfCells() << " triangles";
    std::cerr << " in " << filter->GetSeconds() << " s; " << (planar ? "area" : "volume")
              << " ratio " << filter->GetVolumeRatio() << ", distance to the model max "
              << filter->GetMaximumDistance() << " mean " << filter->GetMeanDistance()
              << " (bounding-box diagonal " << filter->GetDiagonal() << ")\n";
  }
  return 0;
}

} // namespace

void AddCageCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<CageArgs>("cage",
    "make a coarse cage that strictly encloses a model", run_cage);
  command->add_option("--model,-m", a->model,
      "model: triangle surface (3D), or triangles / polygon in a plane z = const (2D)")
    ->required();
  command->add_option("--vertices,-n", a->vertices, "target number of cage vertices (3D >= 4, 2D >= 3)")
    ->default_val(a->vertices)
    ->check(CLI::Range(3, 10000000));
  command->add_option("--margin", a->margin,
      "offset distance of the initial surface, model units (default: --margin-fraction x the "
      "bounding-box diagonal)")
    ->check(FiniteRange(std::numeric_limits<double>::min(), 1e300, "> 0"));
  command->add_option("--margin-fraction", a->margin_fraction,
      "automatic margin as a fraction of the bounding-box diagonal")
    ->default_val(a->margin_fraction)
    ->check(FiniteRange(1e-6, 1.0));
  command->add_option("--resolution", a->resolution, "distance-grid cells per margin")
    ->default_val(a->resolution)
    ->check(FiniteRange(2.0, 64.0));
  command->add_option("--tighten-rounds", a->tighten_rounds,
      "rounds moving the cage's vertices toward the model after decimation (0: none)")
    ->default_val(a->tighten_rounds)
    ->check(CLI::Range(0, 1000));
  command->add_option("--clearance", a->clearance,
      "distance tightening leaves between a vertex and the model, in margins")
    ->default_val(a->clearance)
    ->check(FiniteRange(0.0, 1.0));
  command->add_option("--output,-o", a->output, "cage (.obj, .vtp, .vtk, .off, .stl, .ply)")
    ->required();
  command->add_option("--json", a->json_path, "write a JSON summary");
  command->add_flag("--quiet,-q", a->quiet, "no progress bar or summary");
}

} // namespace cli
} // namespace barylab
