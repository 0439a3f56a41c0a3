// The flags of a weights computation, shared by 'weights', 'deform' and 'animate'
// (barylabCli.h).

#include "barylabCli.h"

#include "vtkBaryCoordinates.h"

#include <CLI/CLI.hpp>

namespace barylab
{
namespace cli
{

void add_method_options(CLI::App* cmd, WeightsParameters& p)
{
  std::string names;
  for (int i = 0; i < vtkBaryCoordinates::NUMBER_OF_METHODS; ++i)
    names += (i ? "|" : "") + std::string(vtkBaryCoordinates::GetMethodName(i));
  cmd->add_option("--method,-m", p.method, "coordinate method: " + names)
    ->default_val(p.method);
  cmd->add_option("--boundary-tolerance", p.boundary_tolerance,
       "points closer to the cage than this fraction of its diagonal count as on the cage")
    ->default_val(p.boundary_tolerance)
    ->check(CLI::Range(0.0, 1e-3));
  cmd->add_option("--threads", p.threads, "threads (0 = all cores); results do not depend on it")
    ->default_val(0)
    ->check(CLI::Range(0, 1024));
  cmd->add_option("--cage-dimension", p.cage_dimension,
       "how to read the cage: 0 automatic (triangles: 3D; one polygon/polyline/bare points: 2D), 2, 3")
    ->default_val(0)
    ->check(CLI::IsMember({ 0, 2, 3 }));
  cmd->add_option("--weights-name", p.weights_name, "name of the weights point-data array")
    ->default_val(p.weights_name);
  auto* mesh = cmd->add_option_group("domain mesh", "mesh-based methods (harmonic, bbw, lbc)");
  mesh->add_option("--cells", p.target_cells,
       "approximate number of cells of the domain mesh (0: 3000 in 2D, 20000 in 3D)")
    ->default_val(0)
    ->check(CLI::Range(0, 50000000));
  mesh->add_option("--max-volume,--max-area", p.max_cell_size,
       "maximum tetrahedron volume / triangle area (overrides --cells)")
    ->default_val(0.0)
    ->check(CLI::NonNegativeNumber);
  mesh->add_flag("--insert-points", p.insert_points,
    "make the points mesh vertices (exact finite-element values there)");
  mesh->add_option("--outside", p.outside, "points outside the cage/domain: error|nearest|nan")
    ->default_val(p.outside)
    ->check(CLI::IsMember({ "error", "nearest", "nan" }));
  auto* celestial = cmd->add_option_group("celestial coordinates", "--method tcc|scc");
  celestial->add_option("--lambda", p.lambda,
       "scc: wrapping-sphere parameter (> 1; the coordinates do not depend on it)")
    ->default_val(p.lambda)
    ->check(CLI::Range(1.000001, 1e6));
  auto* bbw = cmd->add_option_group("bounded biharmonic weights", "--method bbw");
  bbw->add_flag("--fast", p.bbw_fast,
    "solve each handle alone, then normalize (the paper's fast mode); default: the coupled "
    "problem with partition of unity enforced");
  auto* lbc = cmd->add_option_group("local barycentric coordinates",
    "--method lbc (Zhang et al. 2014; defaults: the paper's)");
  lbc->add_option("--locality", p.lbc_locality,
       "locality function tau of the geodesic distance: squared (the paper's) | constant (plain "
       "total variation) | linear")
    ->default_val(p.lbc_locality)
    ->check(CLI::IsMember({ "squared", "constant", "linear" }));
  lbc->add_option("--relaxed-epsilon", p.lbc_relaxed_epsilon,
       "relaxed total variation epsilon (Eq. 7-8, relative to the diameter; 0: plain TV, > 0: "
       "C1 weights, less local)")
    ->default_val(p.lbc_relaxed_epsilon)
    ->check(CLI::NonNegativeNumber);
  lbc->add_option("--primal-tolerance", p.lbc_primal_tolerance,
       "ADMM primal stopping threshold per residual entry (Eq. 26)")
    ->default_val(p.lbc_primal_tolerance)
    ->check(CLI::Range(1e-15, 0.5));
  lbc->add_option("--dual-tolerance", p.lbc_dual_tolerance,
       "ADMM dual stopping threshold per residual entry (Eq. 27)")
    ->default_val(p.lbc_dual_tolerance)
    ->check(CLI::Range(1e-15, 0.5));
  lbc->add_option("--max-iterations", p.lbc_max_iterations,
       "ADMM iteration cap; reaching it is an error")
    ->default_val(p.lbc_max_iterations)
    ->check(CLI::Range(1, 1000000000));
  lbc->add_option("--distance-normalization", p.lbc_distance_normalization,
       "geodesic distances normalised by each control point's maximum (Eq. 12) or by one global "
       "maximum (the authors' code): per-control-point | global")
    ->default_val(p.lbc_distance_normalization)
    ->check(CLI::IsMember({ "per-control-point", "global" }));
  lbc->add_flag("--unconstrained-tv", p.lbc_unconstrained,
    "drop partition of unity and reproduction (the paper's unconstrained TV, §3.2): not "
    "barycentric coordinates");
}

/// BBW inputs: --cage (cage handles) or --handles with --mesh (a skeleton in a domain).
/// Celestial coordinates: --control-points (passed here as @p cage with @p controls set).
void check_bbw_inputs(const std::string& method, const std::string& cage,
  const std::string& handles, const std::string& mesh, bool controls)
{
  if (method != "bbw")
  {
    if (!handles.empty() || (!mesh.empty() && method != "lbc"))
      throw UsageError(method == "lbc" ? "--handles is for --method bbw"
                                       : "--handles and --mesh are for --method bbw (--mesh also "
                                         "for lbc)");
    const bool point_based = barylab::IsPointBasedMethod(method);
    if (point_based && !controls)
      throw UsageError("--method " + method + " takes free control points: --control-points "
                       "FILE (not --cage)");
    if (!point_based && controls)
      throw UsageError("--control-points is for --method tcc|scc; --method " + method +
        " takes --cage");
    if (cage.empty())
      throw UsageError(std::string(point_based ? "--control-points" : "--cage") +
        " is required for --method " + method);
    return;
  }
  if (controls)
    throw UsageError("--control-points is for --method tcc|scc");
  if (!cage.empty() && (!handles.empty() || !mesh.empty()))
    throw UsageError("--method bbw takes either --cage (cage handles) or --handles with --mesh "
                     "(points and bones in a domain), not both");
  if (cage.empty() && (handles.empty() || mesh.empty()))
    throw UsageError("--method bbw needs --handles HANDLES and --mesh DOMAIN (or --cage CAGE for "
                     "cage handles)");
}

} // namespace cli
} // namespace barylab
