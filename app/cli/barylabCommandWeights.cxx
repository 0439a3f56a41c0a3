// barylab weights: coordinates of points w.r.t. a cage, control points or skeleton handles.

#include "barylabCli.h"

#include "barylabDistributed.h"
#include "vtkBaryDataIO.h"

#include "core/common/error.h"

#include "vtkDataSet.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#include <CLI/CLI.hpp>

#include <iostream>

using nlohmann::json;

namespace barylab
{
namespace cli
{
namespace
{

struct WeightsArgs
{
  WeightsParameters parameters;
  std::string cage, controls, handles, mesh, points, output, json_path, user_weights;
  std::string shape_preservation;
  bool quiet = false;
};

int run_weights(WeightsArgs a)
{
  if (!a.controls.empty() && !a.cage.empty())
    throw UsageError("give --cage or --control-points, not both");
  check_bbw_inputs(a.parameters.method, a.controls.empty() ? a.cage : a.controls, a.handles,
    a.mesh, !a.controls.empty());
  if (!a.user_weights.empty() && a.parameters.method != bary::MethodId::TCelestial)
    throw UsageError("--user-weights is for --method tcc (Eq. 8's s_i)");
  if (!a.shape_preservation.empty() &&
    (a.parameters.method != bary::MethodId::BBW || a.mesh.empty()))
    throw UsageError("--shape-preservation is for --method bbw with a domain mesh (--mesh)");
  if (!a.controls.empty())
    a.cage = a.controls;
  a.parameters.user_weights = read_user_weights(a.user_weights);
  // Mesh-based methods with a cage and no points: the weights at the vertices of the domain
  // mesh (made here as the method makes it, or --mesh for lbc), written as that mesh.
  const bary::MethodInfo& method = bary::method_info(a.parameters.method);
  const bool mesh_based = method.domain_mesh && a.handles.empty();
  if (a.points.empty() && a.mesh.empty() && !mesh_based)
    throw UsageError("--points is required (the points to compute weights at)");
  if (Distributed() && a.points.empty())
    throw UsageError("a distributed run (mpirun) splits the points of --points over the "
                     "processes: give --points");
  const std::vector<std::string> inputs = { a.cage, a.controls, a.handles, a.mesh, a.points };
  const bool skeleton = !a.handles.empty();
  vtkSmartPointer<vtkPolyData> cage;
  vtkSmartPointer<vtkDataSet> domain, points;
  Collective([&]() { // every process reads the whole cage and domain, and its piece of the points
    check_output(a.output, OutputKind::Data, inputs);
    if (!a.json_path.empty())
      check_output(a.json_path, OutputKind::Json, inputs);
    cage = vtkBaryDataIO::ReadPolyData(skeleton ? a.handles : a.cage);
    domain = a.mesh.empty() ? nullptr : vtkBaryDataIO::Read(a.mesh);
    if (domain)
      domain = with_shape_preservation(domain, a.shape_preservation, a.mesh);
    if (!a.points.empty())
      points = ReadPiece(a.points);
  });
  if (!points && domain)
    points = domain;
  else if (!points)
  {
    // the mesher's defaults are the methods' (deterministic: the same mesh again inside)
    barylab::MeshParameters mp;
    mp.cage_dimension = a.parameters.cage_dimension;
    const int dim = barylab::CageDimension(cage, a.parameters.cage_dimension);
    mp.target_cells = a.parameters.target_cells > 0 ? a.parameters.target_cells
                                                    : bary::default_target_cells(dim);
    mp.max_cell_size = a.parameters.max_cell_size;
    points = barylab::MeshCage(cage, nullptr, mp);
    domain = points; // used as is by the method: no second meshing
  }
  // The result is a copy of the points with the weights added: a format that cannot hold them
  // fails now, not after the solve.
  Collective([&]() { CheckWritableData(points, a.output); });
  const bool lead = ProcessRank() == 0;
  ProgressBar bar(!a.quiet && lead, "weights");
  json summary;
  vtkSmartPointer<vtkDataSet> result;
  Collective([&]() {
    result = barylab::ComputeWeights(
      points, cage, a.parameters, callbacks(bar, a.quiet || !lead), &summary, domain);
  });
  bar.done();
  summary[skeleton ? "handles" : "cage"]["file"] = skeleton ? a.handles : a.cage;
  if (!a.user_weights.empty())
    summary["user_weights"] = a.user_weights;
  if (domain)
    summary["domain"] = { { "file", a.mesh.empty() ? "(meshed)" : a.mesh } };
  summary["points"]["file"] =
    !a.points.empty() ? a.points : !a.mesh.empty() ? a.mesh : "(the domain mesh's vertices)";
  summary["output"] = a.output;
  Collective([&]() {
    // a distributed run's figures are over the points each process owns, then combined
    vtkSmartPointer<vtkDataSet> owned = OwnedPoints(result);
    if (Distributed())
      summary["points"].update(PointCounts(owned, a.parameters.weights_name));
    summary["statistics"] = barylab::WeightStatisticsJson(owned, a.parameters.weights_name,
      skeleton ? nullptr : cage.Get(), -1.0, a.parameters.cage_dimension);
  });
  summary = CombineSummaries(summary);
  WriteData(result, a.output);
  if (!lead)
    return 0;
  if (!a.json_path.empty())
    barylab::WriteJson(summary, a.json_path);
  if (!a.quiet)
  {
    print_summary(summary);
    if (summary["points"]["outside"].get<long long>() > 0 && a.parameters.method == bary::MethodId::MeanValue)
      std::cerr << "barylab: note: " << summary["points"]["outside"]
                << " point(s) lie outside the cage; mean value coordinates are defined there "
                   "but may be negative\n";
    if (summary["points"]["outside"].get<long long>() > 0 && a.parameters.method == bary::MethodId::Green)
      std::cerr << "barylab: note: " << summary["points"]["outside"]
                << " point(s) lie outside the cage; Green coordinates continue there through "
                   "each point's nearest cage face (the paper's extension)\n";
  }
  return 0;
}

} // namespace

void AddWeightsCommand(Subcommands& subcommands)
{
  const auto [command, a] = subcommands.Add<WeightsArgs>("weights",
    "compute coordinates of points w.r.t. a cage", run_weights);
  command->add_option("--cage,-c", a->cage, "cage: closed triangle surface (3D) or polygon (2D)");
  command->add_option("--control-points", a->controls,
    "tcc|scc: free control points (any point file; cells ignored; 2D if planar)");
  command->add_option("--user-weights", a->user_weights,
    "tcc: s_i of Eq. 8, one number per control point (text or .dmat)");
  command->add_option("--handles", a->handles,
    "bbw: skeleton (.tgf, or .vtp points + lines), or mixed handles (.vtp: points, bones, cage "
    "faces, regions; cell array HandleType)");
  command->add_option("--shape-preservation", a->shape_preservation,
    "bbw: shape-preservation brush rho >= 0 per --mesh vertex (Eq. 7): a file of one number per "
    "vertex, or the name of a point array of the mesh");
  command->add_option("--mesh", a->mesh,
    "bbw with --handles: domain: tet/triangle mesh (.vtu, .mesh) or a closed surface / polygon "
    "to mesh; harmonic, lbc, bbw with --cage: a tet/triangle mesh of the cage's interior, used as "
    "is (its boundary vertices include the cage's)");
  command->add_option("--points,-p", a->points,
    "points/mesh to evaluate at (default: the --mesh itself; without --mesh, for harmonic, lbc, "
    "bbw with --cage: the domain mesh made of the cage, written with its weights)");
  command->add_option("--output,-o", a->output, "output file (.vtp/.vtu/.vtk keep the weights)")
    ->required();
  command->add_option("--json", a->json_path, "write a JSON summary (counts, timings, statistics)");
  command->add_flag("--quiet,-q", a->quiet, "no progress bar, summary or warnings (errors still)");
  add_method_options(command, a->parameters);
}

} // namespace cli
} // namespace barylab
