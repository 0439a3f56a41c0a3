// barylab mesh: a triangle / tetrahedron mesh of the interior of a cage.

#include "barylabCli.h"

#include "vtkBaryDataIO.h"

#include "core/common/error.h"
#include "core/meshing/domain_mesh.h"

#include "vtkDataSet.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <sstream>

using nlohmann::json;

namespace barylab
{
namespace cli
{
namespace
{

struct MeshArgs
{
  barylab::MeshParameters parameters;
  std::string cage, points, output, json_path;
  bool quiet = false;
};

int run_mesh(const MeshArgs& a)
{
  check_output(a.output, OutputKind::Data, { a.cage, a.points });
  if (!a.json_path.empty())
    check_output(a.json_path, OutputKind::Json, { a.cage, a.points });
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

} // namespace

namespace
{
std::string RadiusEdgeRange()
{
  std::ostringstream range;
  range << "[" << bary::kMinRadiusEdgeRatio << ", " << bary::kMaxRadiusEdgeRatio << "]";
  return range.str();
}
} // namespace

void AddMeshCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<MeshArgs>("mesh",
    "triangulate / tetrahedralize the interior of a cage", run_mesh);
  command->add_option("--cage,-c", a->cage, "cage: closed triangle surface (3D) or polygon (2D)")
    ->required();
  command->add_option("--points,-p", a->points, "points to make mesh vertices (those inside)");
  command->add_option("--output,-o", a->output, "domain mesh (.vtu, or .vtk)")->required();
  command->add_option("--cells", a->parameters.target_cells, "approximate number of cells")
    ->default_val(a->parameters.target_cells)
    ->check(CLI::Range(1, 50000000));
  command->add_option("--max-volume,--max-area", a->parameters.max_cell_size,
       "maximum tetrahedron volume / triangle area (overrides --cells)")
    ->default_val(0.0)
    ->check(FiniteRange(0.0, 1e300, ">= 0"));
  command->add_option("--min-angle", a->parameters.min_angle, "2D: minimum angle, degrees")
    ->default_val(a->parameters.min_angle)
    ->check(FiniteRange(0.0, bary::kMaxMinAngleDegrees));
  command->add_option("--radius-edge-ratio", a->parameters.radius_edge_ratio,
       "3D: TetGen quality bound (0 = no quality refinement)")
    ->default_val(a->parameters.radius_edge_ratio)
    ->check(CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) ||
          !(value == 0.0 ||
            (value >= bary::kMinRadiusEdgeRatio && value <= bary::kMaxRadiusEdgeRatio)))
          return "'" + text + "' is not 0 or a number in " + RadiusEdgeRange();
        return {};
      },
      "0 or " + RadiusEdgeRange(), ""));
  command->add_flag("--preserve-boundary", a->parameters.preserve_boundary,
    "3D: no extra vertices on the cage faces");
  command->add_option("--cage-dimension", a->parameters.cage_dimension, "0 automatic, 2, 3")
    ->check(CLI::IsMember({ 0, 2, 3 }));
  command->add_option("--json", a->json_path, "write a JSON summary");
  command->add_flag("--quiet,-q", a->quiet, "no progress bar or summary");
}

} // namespace cli
} // namespace barylab
