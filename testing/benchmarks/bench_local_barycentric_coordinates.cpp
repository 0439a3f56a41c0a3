// Local barycentric coordinates: the LBC authors' four reference runs (their triangulations,
// control vertices and weights, ../shared/data/lbc) solved again on one thread, with the
// objective of both weight sets evaluated by BaryLab; 2D iteration counts against mesh size;
// 3D cages meshed with TetGen at a few sizes, next to BBW and harmonic coordinates on the same
// meshes; the paper's Table 2 analog (LBCTable2: LBC next to BBW fast and coupled, the cage as
// handles, on the authors' four triangulations, the bundled 2D and 3D cages and three simple 3D
// cages). See docs/benchmarks.md and docs/local-barycentric-coordinates.md for the results and
// how they were taken.
#include "core/coordinates/bbw.h"
#include "core/meshing/domain_mesh.h"
#include "core/coordinates/harmonic_coordinates.h"
#include "core/coordinates/local_barycentric_coordinates.h"
#include "core/analysis/locality_statistics.h"

#include "cage_catalogue.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <ctime>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using bary::Index;

double cpu_seconds()
{
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

// --- the reference runs ------------------------------------------------------------------------

struct Reference
{
  bary::DomainMesh mesh;
  bary::DenseWeights W;
  bool ok = false;
  std::string error;
};

Reference load_reference(const std::string& name)
{
  Reference ref;
  bary::test::LBCReferenceRun run;
  if (!bary::test::read_lbc_reference(name, run))
  {
    ref.error = "the LBC authors' reference run '" + name + "' not found in " +
      std::string(BARYLAB_SHARED_DIR) + "/lbc";
    return ref;
  }
  ref.mesh = bary::domain_mesh_from_simplices(run.cage, run.V, run.T, run.control, 1e-9);
  ref.W = std::move(run.W);
  ref.ok = true;
  return ref;
}

const char* kReferences[] = { "Gil_Gecko", "LBClogo", "cactus", "woody" };
// The reference solver's iterations and single-thread times (../shared/data/README.md).
const int kReferenceIterations[] = { 2580, 230, 2190, 1960 };
const double kReferenceSeconds[] = { 12.7, 0.16, 7.9, 7.3 };

/// Arguments: the cage (index into kReferences) and the tolerances: 0 = the paper's rule
/// (defaults), 1 = the authors' code's defaults (1e-7 primal, 1e-6 dual: what the reference ran).
void LBCReference(benchmark::State& state)
{
  const int which = static_cast<int>(state.range(0));
  const Reference ref = load_reference(kReferences[which]);
  if (!ref.ok)
  {
    state.SkipWithError(ref.error.c_str());
    return;
  }
  bary::LBCOptions o;
  o.threads = 1;
  o.distance_normalization = bary::DistanceNormalization::Global; // as the authors' code
  // 0: the paper's rule, 1: the authors' tolerances (paper's rule), 2: the default (converged)
  if (state.range(1) != 2)
    o.stopping = bary::LBCStopping::Paper;
  if (state.range(1) == 1)
  {
    o.primal_tolerance = 1e-7;
    o.dual_tolerance = 1e-6;
  }
  bary::LBCResult r;
  double cpu = 0.0, reference_objective = 0.0;
  for (auto _ : state)
  {
    const double c0 = cpu_seconds();
    const bary::LocalBarycentricCoordinates lbc(ref.mesh, o);
    r = lbc.compute();
    cpu = cpu_seconds() - c0;
    state.PauseTiming();
    reference_objective = lbc.objective(ref.W);
    state.ResumeTiming();
  }
  const bary::DenseWeights diff = r.W - ref.W;
  const bary::LocalityStatistics s = bary::locality_statistics(r.W),
                                 sr = bary::locality_statistics(ref.W);
  state.counters["n"] = static_cast<double>(ref.mesh.control_vertex.size());
  state.counters["V"] = static_cast<double>(ref.mesh.V.rows());
  state.counters["iterations"] = r.iterations;
  state.counters["ref_iterations"] = kReferenceIterations[which];
  state.counters["cpu_s"] = cpu;
  state.counters["ref_cpu_s"] = kReferenceSeconds[which];
  state.counters["speedup"] = kReferenceSeconds[which] / cpu;
  state.counters["geodesic_s"] = r.geodesic_seconds;
  state.counters["factor_s"] = r.factor_seconds;
  state.counters["admm_s"] = r.admm_seconds;
  state.counters["polish_s"] = r.polish_seconds;
  state.counters["objective"] = r.objective;
  state.counters["ref_objective"] = reference_objective;
  state.counters["objective_rel"] = (r.objective - reference_objective) / reference_objective;
  state.counters["max_dW"] = diff.cwiseAbs().maxCoeff();
  state.counters["mean_dW"] = diff.cwiseAbs().mean();
  state.counters["partition_err"] = r.partition_error;
  state.counters["repro_err"] = r.reproduction_error;
  state.counters["min_w"] = r.min_weight;
  state.counters["ref_min_w"] = ref.W.minCoeff();
  state.counters["support_mean"] = s.mean_support;
  state.counters["support_max"] = s.max_support;
  state.counters["ref_support_mean"] = sr.mean_support;
  state.counters["ref_support_max"] = sr.max_support;
  state.SetLabel(std::string(kReferences[which]) +
    (state.range(1) == 2 ? " converged (default)"
        : state.range(1)  ? " authors' tolerances"
                          : " paper's rule"));
}
BENCHMARK(LBCReference)
  ->ArgsProduct({ { 0, 1, 2, 3 }, { 0, 1, 2 } })
  ->Unit(benchmark::kMillisecond)
  ->Iterations(1);

// --- 2D: iterations against mesh size ---------------------------------------------------------

/// A 7-tip star (14 control points), arguments: target cells, scaling (0 lumped, 1 paper).
void LBC2DMeshSize(benchmark::State& state)
{
  bary::Cage cage;
  cage.V.resize(14, 2);
  for (int i = 0; i < 14; ++i)
  {
    const double a = M_PI * i / 7 + 0.5 * M_PI, rr = i % 2 == 0 ? 1.0 : 0.55;
    cage.V.row(i) << rr * std::cos(a), rr * std::sin(a);
  }
  bary::PolygonMeshOptions po;
  po.target_cells = static_cast<int>(state.range(0));
  const bary::DomainMesh mesh = bary::mesh_polygon(cage, po);
  bary::LBCOptions o;
  o.threads = 1;
  o.require_convergence = false;
  o.stopping = bary::LBCStopping::Paper; // the table in the docs is the paper's rule
  if (state.range(1) == 1)
    o.scaling = bary::ConstraintScaling::Paper;
  bary::LBCResult r;
  for (auto _ : state)
    r = bary::local_barycentric_coordinates(mesh, o);
  state.counters["V"] = static_cast<double>(mesh.V.rows());
  state.counters["iterations"] = r.iterations;
  state.counters["converged"] = r.converged;
  state.counters["objective"] = r.objective;
  state.counters["admm_s"] = r.admm_seconds;
  state.counters["ms_per_iteration"] = 1e3 * r.admm_seconds / std::max(1, r.iterations);
  state.counters["support_mean"] = bary::locality_statistics(r.W).mean_support;
  state.SetLabel(state.range(1) ? "paper scaling" : "lumped scaling");
}
BENCHMARK(LBC2DMeshSize)
  ->ArgsProduct({ { 1000, 3000, 10000 }, { 0, 1 } })
  ->Unit(benchmark::kMillisecond)
  ->Iterations(1);

// --- 3D cages next to BBW and harmonic coordinates ---------------------------------------------

bary::Cage cube()
{
  bary::Cage c;
  c.V.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    c.V.row(i) << (i & 1), (i >> 1 & 1), (i >> 2 & 1);
  c.F.resize(12, 3);
  c.F << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1,
    3, 5, 3, 7, 5;
  return c;
}

bary::Cage octahedron()
{
  bary::Cage c;
  c.V.resize(6, 3);
  c.V << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  c.F.resize(8, 3);
  c.F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  return c;
}

/// Icosahedron subdivided once (42 vertices, 80 faces), radii perturbed by +-10% (fixed seed).
bary::Cage icosphere42()
{
  const double p = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = { { -1, p, 0 }, { 1, p, 0 }, { -1, -p, 0 }, { 1, -p, 0 },
    { 0, -1, p }, { 0, 1, p }, { 0, -1, -p }, { 0, 1, -p }, { p, 0, -1 }, { p, 0, 1 },
    { -p, 0, -1 }, { -p, 0, 1 } };
  std::vector<Eigen::Vector3i> f = { { 0, 11, 5 }, { 0, 5, 1 }, { 0, 1, 7 }, { 0, 7, 10 },
    { 0, 10, 11 }, { 1, 5, 9 }, { 5, 11, 4 }, { 11, 10, 2 }, { 10, 7, 6 }, { 7, 1, 8 },
    { 3, 9, 4 }, { 3, 4, 2 }, { 3, 2, 6 }, { 3, 6, 8 }, { 3, 8, 9 }, { 4, 9, 5 }, { 2, 4, 11 },
    { 6, 2, 10 }, { 8, 6, 7 }, { 9, 8, 1 } };
  for (auto& x : v)
    x.normalize();
  std::map<std::pair<int, int>, int> mid;
  auto midpoint = [&](int a, int b) {
    const std::pair<int, int> key(std::min(a, b), std::max(a, b));
    auto it = mid.find(key);
    if (it != mid.end())
      return it->second;
    v.push_back((v[static_cast<std::size_t>(a)] + v[static_cast<std::size_t>(b)]).normalized());
    return mid[key] = static_cast<int>(v.size()) - 1;
  };
  std::vector<Eigen::Vector3i> g;
  for (const auto& t : f)
  {
    const int a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
    g.push_back({ t[0], a, c });
    g.push_back({ t[1], b, a });
    g.push_back({ t[2], c, b });
    g.push_back({ a, b, c });
  }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  bary::Cage c;
  c.V.resize(static_cast<Index>(v.size()), 3);
  for (std::size_t k = 0; k < v.size(); ++k)
    c.V.row(static_cast<Index>(k)) = (1.0 + 0.1 * u(rng)) * v[k].transpose();
  c.F.resize(static_cast<Index>(g.size()), 3);
  for (std::size_t k = 0; k < g.size(); ++k)
    c.F.row(static_cast<Index>(k)) = g[k].transpose();
  return c;
}

/// Arguments: cage (0 cube, 1 octahedron, 2 icosphere with 42 vertices), target tetrahedra,
/// rule (0: the paper's, 1: its tolerances 100 times tighter, 2: the default, converged).
void LBC3D(benchmark::State& state)
{
  const int which = static_cast<int>(state.range(0));
  const bary::Cage cage = which == 0 ? cube() : which == 1 ? octahedron() : icosphere42();
  bary::SurfaceMeshOptions so;
  so.target_cells = static_cast<int>(state.range(1));
  const bary::DomainMesh mesh = bary::mesh_closed_surface(cage, so);
  bary::LBCOptions o;
  o.threads = 1;
  o.require_convergence = false;
  if (state.range(2) != 2)
    o.stopping = bary::LBCStopping::Paper;
  if (state.range(2) == 1)
  {
    o.primal_tolerance = 1e-8;
    o.dual_tolerance = 1e-7;
  }
  bary::LBCResult r;
  double cpu = 0.0;
  for (auto _ : state)
  {
    const double c0 = cpu_seconds();
    r = bary::local_barycentric_coordinates(mesh, o);
    cpu = cpu_seconds() - c0;
  }
  // BBW (fast mode, one thread) and harmonic coordinates on the same mesh
  bary::BBWHandles handles;
  handles.extra_handles = cage.num_controls();
  handles.fixed_vertices = Eigen::Map<const Eigen::VectorXi>(
    mesh.boundary_vertices.data(), static_cast<Index>(mesh.boundary_vertices.size()));
  handles.fixed_values = bary::DenseWeights(Eigen::MatrixXd(mesh.boundary_weights));
  bary::BBWOptions bo;
  bo.threads = 1;
  double c0 = cpu_seconds();
  const bary::BBWResult bbw = bary::bounded_biharmonic_weights(mesh.V, mesh.T, handles, bo);
  const double bbw_cpu = cpu_seconds() - c0;
  c0 = cpu_seconds();
  const bary::HarmonicCoordinates hc(cage, mesh);
  const double hc_cpu = cpu_seconds() - c0;
  const Eigen::VectorXd measure = bary::vertex_measures(mesh.V, mesh.T);
  const bary::LocalityStatistics sl = bary::locality_statistics(r.W, -1, measure),
                                 sb = bary::locality_statistics(bbw.W, -1, measure),
                                 sh = bary::locality_statistics(hc.mesh_weights(), -1, measure);
  state.counters["n"] = static_cast<double>(cage.num_controls());
  state.counters["V"] = static_cast<double>(mesh.V.rows());
  state.counters["T"] = static_cast<double>(mesh.T.rows());
  state.counters["iterations"] = r.iterations;
  state.counters["converged"] = r.converged;
  state.counters["cpu_s"] = cpu;
  state.counters["geodesic_s"] = r.geodesic_seconds;
  state.counters["admm_s"] = r.admm_seconds;
  state.counters["partition_err"] = r.partition_error;
  state.counters["objective"] = r.objective;
  state.counters["support_lbc"] = sl.mean_support;
  state.counters["support_lbc_max"] = sl.max_support;
  state.counters["support_bbw"] = sb.mean_support;
  state.counters["support_harmonic"] = sh.mean_support;
  state.counters["bbw_cpu_s"] = bbw_cpu;
  state.counters["harmonic_cpu_s"] = hc_cpu;
  state.SetLabel(std::string(which == 0 ? "cube" : which == 1 ? "octahedron" : "icosphere42") +
    (state.range(2) == 2 ? ", converged (default)"
        : state.range(2)  ? ", tolerances / 100"
                          : ", paper's rule"));
}
BENCHMARK(LBC3D)
  ->ArgsProduct({ { 0, 1, 2 }, { 1000, 5000, 20000 }, { 0 } })
  ->ArgsProduct({ { 0, 1, 2 }, { 1000, 5000 }, { 1 } })
  ->ArgsProduct({ { 0, 1, 2 }, { 1000, 5000 }, { 2 } })
  ->Unit(benchmark::kMillisecond)
  ->Iterations(1);

// --- the paper's Table 2 analog: LBC next to BBW on the same meshes ----------------------------

/// data/cage2d.obj (`v x y 0` lines, the polygon in order) or data/cage3d.obj (`v`, `f` lines).
bary::Cage bundled_cage(bool three_d)
{
  std::ifstream in(std::string(BARYLAB_DATA_DIR) + (three_d ? "/cage3d.obj" : "/cage2d.obj"));
  std::vector<Eigen::RowVector3d> v;
  std::vector<Eigen::RowVector3i> f;
  std::string line;
  while (std::getline(in, line))
  {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v")
    {
      double x, y, z;
      s >> x >> y >> z;
      v.emplace_back(x, y, z);
    }
    else if (tag == "f")
    {
      int a, b, c;
      s >> a >> b >> c;
      f.emplace_back(a - 1, b - 1, c - 1);
    }
  }
  bary::Cage c;
  c.V.resize(static_cast<Index>(v.size()), three_d ? 3 : 2);
  for (std::size_t k = 0; k < v.size(); ++k)
    c.V.row(static_cast<Index>(k)) = v[k].head(three_d ? 3 : 2);
  if (three_d)
  {
    c.F.resize(static_cast<Index>(f.size()), 3);
    for (std::size_t k = 0; k < f.size(); ++k)
      c.F.row(static_cast<Index>(k)) = f[k];
  }
  return c;
}

// Cases: 0-3 the authors' cages on their reference triangulations, 4 the bundled gingerbread
// cage meshed by BaryLab (3,000 target triangles, as the authors' GUI default), 5 cube,
// 6 octahedron, 7 icosphere42, 8 the bundled kidney cage (5,000 target tetrahedra each),
// 9-12 the authors' four cages meshed by BaryLab at about the paper's Table 2 sizes |V|.
const char* kTable2Names[] = { "Gil_Gecko", "LBClogo", "cactus", "woody", "gingerbread",
  "cube", "octahedron", "icosphere42", "kidney", "Gil_Gecko (paper's |V|)",
  "LBClogo (paper's |V|)", "cactus (paper's |V|)", "woody (paper's |V|)" };
// Target triangles for cases 9-12, chosen so that |V| is close to the paper's 11,554 / 4,479 /
// 12,862 / 6,069.
const int kTable2PaperCells[] = { 14750, 5700, 16400, 7750 };

/// An authors' cage: the `v` lines of ../shared/data/lbc/cages/<name>-control-edgeset.obj, in
/// order (their polygon).
bool authors_cage(const std::string& name, bary::Cage& c)
{
  std::ifstream in(std::string(BARYLAB_SHARED_DIR) + "/lbc/cages/" + name + "-control-edgeset.obj");
  if (!in)
    return false;
  std::vector<Eigen::RowVector2d> v;
  std::string line;
  while (std::getline(in, line))
  {
    std::istringstream s(line);
    std::string tag;
    double x, y;
    if (s >> tag && tag == "v" && s >> x >> y)
      v.emplace_back(x, y);
  }
  c.V.resize(static_cast<Index>(v.size()), 2);
  for (std::size_t k = 0; k < v.size(); ++k)
    c.V.row(static_cast<Index>(k)) = v[k];
  return !v.empty();
}

struct Table2Case
{
  bary::DomainMesh mesh;
  int n = 0;
  bool ok = false;
  std::string error;
};

const Table2Case& table2_case(int which)
{
  static std::map<int, Table2Case> cache;
  auto it = cache.find(which);
  if (it != cache.end())
    return it->second;
  Table2Case& c = cache[which];
  if (which < 4)
  {
    Reference ref = load_reference(kReferences[which]);
    c.ok = ref.ok;
    c.error = ref.error;
    c.mesh = std::move(ref.mesh);
  }
  else if (which >= 9)
  {
    bary::Cage cage;
    if (!authors_cage(kReferences[which - 9], cage))
    {
      c.error = std::string("shared data not found in ") + BARYLAB_SHARED_DIR + "/lbc/cages";
      return c;
    }
    bary::PolygonMeshOptions po;
    po.target_cells = kTable2PaperCells[which - 9];
    c.mesh = bary::mesh_polygon(cage, po);
    c.ok = true;
  }
  else if (which == 4)
  {
    bary::PolygonMeshOptions po;
    po.target_cells = 3000;
    c.mesh = bary::mesh_polygon(bundled_cage(false), po);
    c.ok = true;
  }
  else
  {
    const bary::Cage cage = which == 5 ? cube()
      : which == 6                     ? octahedron()
      : which == 7                     ? icosphere42()
                                       : bundled_cage(true);
    bary::SurfaceMeshOptions so;
    so.target_cells = 5000;
    c.mesh = bary::mesh_closed_surface(cage, so);
    c.ok = true;
  }
  c.n = static_cast<int>(c.mesh.control_vertex.size());
  return c;
}

/// Arguments: the case (kTable2Names), tolerances (0: the paper's rule, with BBW fast and
/// coupled on the same mesh; 1: 1e-7 / 1e-6, LBC only; 2: the default converged rule, LBC only). One
/// thread, CPU time (std::clock).
void LBCTable2(benchmark::State& state)
{
  const int which = static_cast<int>(state.range(0));
  const bool tight = state.range(1) == 1;
  const Table2Case& c = table2_case(which);
  if (!c.ok)
  {
    state.SkipWithError(c.error.c_str());
    return;
  }
  const bary::DomainMesh& mesh = c.mesh;
  bary::LBCOptions o;
  o.threads = 1;
  o.require_convergence = false;
  if (which < 4)
    o.distance_normalization = bary::DistanceNormalization::Global; // as LBCReference
  // (BaryLab's default, per-control-point normalisation for the meshes made here)
  if (state.range(1) != 2)
    o.stopping = bary::LBCStopping::Paper; // 2: the default, converged
  if (tight)
  {
    o.primal_tolerance = 1e-7;
    o.dual_tolerance = 1e-6;
  }
  bary::LBCResult r;
  double cpu = 0.0;
  for (auto _ : state)
  {
    const double c0 = cpu_seconds();
    r = bary::local_barycentric_coordinates(mesh, o);
    cpu = cpu_seconds() - c0;
  }
  const Eigen::VectorXd measure = bary::vertex_measures(mesh.V, mesh.T);
  state.counters["n"] = c.n;
  state.counters["vertices"] = static_cast<double>(mesh.V.rows());
  state.counters["cells"] = static_cast<double>(mesh.T.rows());
  state.counters["lbc_iterations"] = r.iterations;
  state.counters["lbc_converged"] = r.converged;
  state.counters["lbc_cpu_seconds"] = cpu;
  state.counters["lbc_objective"] = r.objective;
  state.counters["lbc_partition_err"] = r.partition_error;
  state.counters["lbc_min_w"] = r.min_weight;
  const bary::LocalityStatistics sl = bary::locality_statistics(r.W, -1, measure);
  state.counters["lbc_support_mean"] = sl.mean_support;
  state.counters["lbc_support_max"] = sl.max_support;
  std::string label = std::string(kTable2Names[which]) +
    (tight ? ", LBC at 1e-7 / 1e-6" : state.range(1) == 2 ? ", converged (default)" : ", paper's rule");
  if (state.range(1) == 0)
  {
    // BBW with the cage as handles: the cage's hat values fixed on the boundary
    bary::BBWHandles handles;
    handles.extra_handles = c.n;
    handles.fixed_vertices = Eigen::Map<const Eigen::VectorXi>(
      mesh.boundary_vertices.data(), static_cast<Index>(mesh.boundary_vertices.size()));
    handles.fixed_values = bary::DenseWeights(Eigen::MatrixXd(mesh.boundary_weights));
    bary::BBWOptions bo;
    bo.threads = 1;
    bo.require_convergence = false;
    double c0 = cpu_seconds();
    const bary::BBWResult fast = bary::bounded_biharmonic_weights(mesh.V, mesh.T, handles, bo);
    state.counters["bbw_fast_cpu_seconds"] = cpu_seconds() - c0;
    state.counters["bbw_fast_converged"] = fast.converged;
    state.counters["bbw_fast_support_mean"] =
      bary::locality_statistics(fast.W, -1, measure).mean_support;
    // the coupled mode (partition of unity enforced; it starts from the fast weights and
    // includes their computation): at most 15 s CPU on these meshes
    bo.mode = bary::BBWMode::Coupled;
    c0 = cpu_seconds();
    const bary::BBWResult coupled = bary::bounded_biharmonic_weights(mesh.V, mesh.T, handles, bo);
    state.counters["bbw_coupled_cpu_seconds"] = cpu_seconds() - c0;
    state.counters["bbw_coupled_converged"] = coupled.converged;
    state.counters["bbw_coupled_outer_iterations"] = coupled.outer_iterations;
    state.counters["bbw_coupled_support_mean"] =
      bary::locality_statistics(coupled.W, -1, measure).mean_support;
  }
  state.SetLabel(label);
}
BENCHMARK(LBCTable2)
  ->ArgsProduct({ { 0, 1, 2, 3, 4, 9, 10, 11, 12, 5, 6, 7, 8 }, { 0 } })
  ->ArgsProduct({ { 5, 6, 7, 8 }, { 1 } })
  ->ArgsProduct({ { 0, 1, 2, 3, 4, 5, 6, 7, 8 }, { 2 } })
  ->Unit(benchmark::kMillisecond)
  ->Iterations(1);

// --- stopping rules: a convergence study ------------------------------------------------------

// Cases: 0-3 the authors' cages on their triangulations (Global normalisation), 4 the bundled
// kidney cage at 600 target tetrahedra, 5 at 3,000, 6 cube (1,000), 7 icosphere42 (1,000),
// 8 icosphere42 (5,000).
const char* kStudyNames[] = { "Gil_Gecko", "LBClogo", "cactus", "woody", "kidney/600",
  "kidney/3000", "cube/1000", "icosphere42/1000", "icosphere42/5000" };

const Table2Case& study_case(int which)
{
  static std::map<int, Table2Case> cache;
  auto it = cache.find(which);
  if (it != cache.end())
    return it->second;
  Table2Case& c = cache[which];
  if (which < 4)
  {
    Reference ref = load_reference(kReferences[which]);
    c.ok = ref.ok;
    c.error = ref.error;
    c.mesh = std::move(ref.mesh);
  }
  else
  {
    const bary::Cage cage = which <= 5 ? bundled_cage(true) : which == 6 ? cube() : icosphere42();
    bary::SurfaceMeshOptions so;
    so.target_cells = which == 4 ? 600 : which == 5 ? 3000 : which == 8 ? 5000 : 1000;
    c.mesh = bary::mesh_closed_surface(cage, so);
    c.ok = true;
  }
  c.n = static_cast<int>(c.mesh.control_vertex.size());
  return c;
}

/// The rules compared: each is evaluated on the residual and support histories of one long run
/// (the iterates do not depend on the rule, so a rule's stop is the first check where it holds),
/// then the run is repeated up to that iteration to get its weights.
struct StudyRule
{
  std::string name;
  std::function<bool(std::size_t check)> holds; // at check index c (iteration (c+1) interval)
};

/// Argument: the case (kStudyNames). Ground truth: tolerances 1e-10 / 1e-9 (at most
/// BARYLAB_LBC_TRUTH_ITERATIONS iterations, default 60,000). Prints one row per rule:
/// iterations, CPU seconds, max |W - W_truth|, mean / max support against the truth's.
void LBCStoppingStudy(benchmark::State& state)
{
  const int which = static_cast<int>(state.range(0));
  const Table2Case& c = study_case(which);
  if (!c.ok)
  {
    state.SkipWithError(c.error.c_str());
    return;
  }
  bary::LBCOptions o;
  o.threads = 1;
  o.require_convergence = false;
  if (which < 4)
    o.distance_normalization = bary::DistanceNormalization::Global;
  bary::LBCOptions truth_o = o;
  truth_o.stopping = bary::LBCStopping::Paper;
  truth_o.primal_tolerance = 1e-10;
  truth_o.dual_tolerance = 1e-9;
  const char* cap = std::getenv("BARYLAB_LBC_TRUTH_ITERATIONS");
  truth_o.max_iterations = cap ? std::atoi(cap) : 60000;
  bary::LBCResult truth;
  double truth_cpu = 0.0;
  for (auto _ : state)
  {
    const double c0 = cpu_seconds();
    truth = bary::local_barycentric_coordinates(c.mesh, truth_o);
    truth_cpu = cpu_seconds() - c0;
  }
  const Eigen::VectorXd measure = bary::vertex_measures(c.mesh.V, c.mesh.T);
  const bary::LocalityStatistics st = bary::locality_statistics(truth.W, -1, measure);
  const double np = truth.primal_threshold / truth_o.primal_tolerance;
  const double nd = truth.dual_threshold / truth_o.dual_tolerance;
  const auto& hp = truth.primal_history;
  const auto& hd = truth.dual_history;
  const auto& hs = truth.support_history;
  std::vector<StudyRule> rules;
  for (double f : { 1.0, 0.1, 0.01 })
    rules.push_back({ f == 1.0 ? "paper (N 1e-6, N 1e-5)" : "paper x " + std::to_string(f),
      [=, &hp, &hd](std::size_t k) { return hp[k] <= f * np * 1e-6 && hd[k] <= f * nd * 1e-5; } });
  for (double e : { 1e-5, 3e-6, 1e-6 })
    rules.push_back({ "sqrt(N) " + std::to_string(e),
      [=, &hp, &hd](std::size_t k) { return hp[k] <= std::sqrt(np) * e && hd[k] <= std::sqrt(nd) * 10 * e; } });
  for (double d : { 0.02, 0.01, 0.005 })
    rules.push_back({ "paper + support within " + std::to_string(d),
      [=, &hp, &hd, &hs](std::size_t k) {
        if (!(hp[k] <= np * 1e-6 && hd[k] <= nd * 1e-5) || k < 1)
          return false;
        const double now = hs[k], then = hs[(k + 1) / 2 - 1];
        return std::abs(now - then) <= d * now;
      } });
  // BARYLAB_LBC_SHORT_STUDY: the paper's rule and the converged rule only
  if (std::getenv("BARYLAB_LBC_SHORT_STUDY"))
    rules.resize(1);
  rules.push_back({ "converged (BaryLab)", {} });
  std::printf("\n%s: n %d, |V| %d, |T| %d; truth %d iterations (converged %d), %.1f s, support "
              "%.2f / %.0f\n",
    kStudyNames[which], c.n, static_cast<int>(c.mesh.V.rows()), static_cast<int>(c.mesh.T.rows()),
    truth.iterations, truth.converged ? 1 : 0, truth_cpu, st.mean_support, st.max_support);
  std::printf("history (iteration primal/sqrtN dual/sqrtN support):");
  for (std::size_t k = 0; k < hp.size(); k = k < 8 ? k + 1 : k * 5 / 4)
    std::printf(" [%zu %.2e %.2e %.2f]", (k + 1) * static_cast<std::size_t>(o.check_interval),
      hp[k] / std::sqrt(np), hd[k] / std::sqrt(nd), hs[k]);
  std::printf("\n");
  for (const StudyRule& rule : rules)
  {
    bary::LBCOptions ro = o;
    if (rule.holds)
    {
      std::size_t k = 0;
      while (k < hp.size() && !rule.holds(k))
        ++k;
      if (k == hp.size())
      {
        std::printf("  %-34s not reached in the truth's run\n", rule.name.c_str());
        continue;
      }
      ro.max_iterations = static_cast<int>(k + 1) * o.check_interval;
      ro.primal_tolerance = 1e-15;
      ro.dual_tolerance = 1e-15;
    }
    else
      ro.stopping = bary::LBCStopping::Converged;
    if (rule.holds)
      ro.stopping = bary::LBCStopping::Paper; // capped at the rule's stop
    const double c0 = cpu_seconds();
    const bary::LBCResult r = bary::local_barycentric_coordinates(c.mesh, ro);
    const double cpu = cpu_seconds() - c0;
    const bary::LocalityStatistics s = bary::locality_statistics(r.W, -1, measure);
    std::printf("  %-34s %6d iterations %8.2f s  max err %.2e  support %.2f / %.0f  (truth %.2f / "
                "%.0f)  objective %+.3e rel\n",
      rule.name.c_str(), r.iterations, cpu, (r.W - truth.W).cwiseAbs().maxCoeff(),
      s.mean_support, s.max_support, st.mean_support, st.max_support,
      (r.objective - truth.objective) / truth.objective);
    std::fflush(stdout);
  }
}
BENCHMARK(LBCStoppingStudy)
  ->DenseRange(0, 8)
  ->Unit(benchmark::kMillisecond)
  ->Iterations(1);

/// Penalty sweep of the converged rule on a study case (kStudyNames): BARYLAB_LBC_SWEEP holds
/// settings "scaled_penalty:constraint_balance:relaxation" separated by spaces (default: the
/// defaults). Prints per setting: iterations, CPU, support, objective and max |W - W_first|.
void LBCPenaltySweep(benchmark::State& state)
{
  const int which = static_cast<int>(state.range(0));
  const Table2Case& c = study_case(which);
  if (!c.ok)
  {
    state.SkipWithError(c.error.c_str());
    return;
  }
  for (auto _ : state)
  {
  }
  bary::LBCOptions o;
  o.threads = 1;
  o.require_convergence = false;
  o.stopping = bary::LBCStopping::Converged;
  if (which < 4)
    o.distance_normalization = bary::DistanceNormalization::Global;
  const char* cap = std::getenv("BARYLAB_LBC_SWEEP_ITERATIONS");
  o.max_iterations = cap ? std::atoi(cap) : 20000;
  const char* list = std::getenv("BARYLAB_LBC_SWEEP");
  std::istringstream in(list ? list : "0.3:7:1.65");
  std::string item;
  const Eigen::VectorXd measure = bary::vertex_measures(c.mesh.V, c.mesh.T);
  bary::DenseWeights first;
  // BARYLAB_LBC_SWEEP_TRUTH: a file with a tight solve's weights (written there by a
  // 1e-10 / 1e-9 solve with the first setting when it does not exist); max|dW| is against it.
  double truth_objective = 0.0;
  if (const char* truth_file = std::getenv("BARYLAB_LBC_SWEEP_TRUTH"))
  {
    first.resize(c.mesh.V.rows(), c.n);
    std::FILE* f = std::fopen(truth_file, "rb");
    if (f && std::fread(first.data(), sizeof(double), static_cast<std::size_t>(first.size()), f) ==
          static_cast<std::size_t>(first.size()))
      std::fclose(f);
    else
    {
      if (f)
        std::fclose(f);
      bary::LBCOptions to = o;
      std::istringstream in0(list ? list : "0.3:7:1.65");
      std::string item0;
      in0 >> item0;
      int adaptive0 = 1;
      std::sscanf(item0.c_str(), "%lf:%lf:%lf:%d", &to.scaled_penalty, &to.constraint_balance,
        &to.relaxation, &adaptive0);
      to.adaptive_penalty = adaptive0 != 0;
      to.stopping = bary::LBCStopping::Converged; // with residual balancing
      to.primal_tolerance = 1e-10;
      to.dual_tolerance = 1e-9;
      to.max_iterations = 60000;
      const bary::LBCResult t = bary::local_barycentric_coordinates(c.mesh, to);
      first = t.W;
      std::printf("truth: %d iterations, converged %d\n", t.iterations, t.converged ? 1 : 0);
      f = std::fopen(truth_file, "wb");
      if (f)
      {
        std::fwrite(first.data(), sizeof(double), static_cast<std::size_t>(first.size()), f);
        std::fclose(f);
      }
    }
    const bary::LocalBarycentricCoordinates lbc(c.mesh, o);
    truth_objective = lbc.objective(first);
    const bary::LocalityStatistics ts = bary::locality_statistics(first, -1, measure);
    std::printf("truth objective %.9e support %.2f / %.0f\n", truth_objective, ts.mean_support,
      ts.max_support);
  }
  std::printf("\n%s: n %d, |V| %d\n", kStudyNames[which], c.n, static_cast<int>(c.mesh.V.rows()));
  while (in >> item)
  {
    bary::LBCOptions ro = o;
    int adaptive = 1;
    std::sscanf(item.c_str(), "%lf:%lf:%lf:%d", &ro.scaled_penalty, &ro.constraint_balance,
      &ro.relaxation, &adaptive);
    ro.adaptive_penalty = adaptive != 0;
    const double c0 = cpu_seconds();
    const bary::LBCResult r = bary::local_barycentric_coordinates(c.mesh, ro);
    const double cpu = cpu_seconds() - c0;
    const bary::LocalityStatistics s = bary::locality_statistics(r.W, -1, measure);
    if (first.size() == 0)
      first = r.W;
    std::printf("  mu %.4g beta %.4g alpha %.3g adaptive %d (%d updates, x%.3g): %6d iterations (converged %d) %7.2f s support "
                "%.2f / %.0f objective %.6e (%+.1e rel) max|dW| %.2e\n",
      ro.scaled_penalty, ro.constraint_balance, ro.relaxation, adaptive, r.penalty_updates,
      r.penalty_factor, r.iterations, r.converged ? 1 : 0,
      cpu, s.mean_support, s.max_support, r.objective,
      truth_objective > 0 ? (r.objective - truth_objective) / truth_objective : 0.0,
      (r.W - first).cwiseAbs().maxCoeff());
    std::fflush(stdout);
  }
}
BENCHMARK(LBCPenaltySweep)->DenseRange(0, 8)->Unit(benchmark::kMillisecond)->Iterations(1);

/// BBW (fast and coupled, one thread) and harmonic coordinates on a study case's mesh, for the
/// locality comparison with the converged LBC of LBCStoppingStudy on the same mesh. The cage's
/// hat values are fixed on the boundary, clamped to [0, 1] (the mesher's barycentric boundary
/// weights can be -1e-16, which BBW's bounds refuse).
void LBCStudyMeshOthers(benchmark::State& state)
{
  const int which = static_cast<int>(state.range(0));
  const Table2Case& c = study_case(which);
  if (!c.ok)
  {
    state.SkipWithError(c.error.c_str());
    return;
  }
  const bary::DomainMesh& mesh = c.mesh;
  bary::BBWHandles handles;
  handles.extra_handles = c.n;
  handles.fixed_vertices = Eigen::Map<const Eigen::VectorXi>(
    mesh.boundary_vertices.data(), static_cast<Index>(mesh.boundary_vertices.size()));
  handles.fixed_values =
    bary::DenseWeights(Eigen::MatrixXd(mesh.boundary_weights).cwiseMax(0.0).cwiseMin(1.0));
  bary::BBWOptions bo;
  bo.threads = 1;
  bo.require_convergence = false;
  bary::BBWResult fast, coupled;
  double fast_cpu = 0.0;
  for (auto _ : state)
  {
    const double c0 = cpu_seconds();
    fast = bary::bounded_biharmonic_weights(mesh.V, mesh.T, handles, bo);
    fast_cpu = cpu_seconds() - c0;
  }
  bo.mode = bary::BBWMode::Coupled;
  double c0 = cpu_seconds();
  coupled = bary::bounded_biharmonic_weights(mesh.V, mesh.T, handles, bo);
  const double coupled_cpu = cpu_seconds() - c0;
  const Eigen::VectorXd measure = bary::vertex_measures(mesh.V, mesh.T);
  const bary::LocalityStatistics sf = bary::locality_statistics(fast.W, -1, measure),
                                 sc = bary::locality_statistics(coupled.W, -1, measure);
  state.counters["n"] = c.n;
  state.counters["V"] = static_cast<double>(mesh.V.rows());
  state.counters["bbw_fast_support"] = sf.mean_support;
  state.counters["bbw_fast_support_max"] = sf.max_support;
  state.counters["bbw_fast_cpu_s"] = fast_cpu;
  state.counters["bbw_fast_converged"] = fast.converged;
  state.counters["bbw_coupled_support"] = sc.mean_support;
  state.counters["bbw_coupled_support_max"] = sc.max_support;
  state.counters["bbw_coupled_cpu_s"] = coupled_cpu;
  state.counters["bbw_coupled_converged"] = coupled.converged;
  state.SetLabel(kStudyNames[which]);
}
BENCHMARK(LBCStudyMeshOthers)->DenseRange(4, 8)->Unit(benchmark::kMillisecond)->Iterations(1);

} // namespace

BENCHMARK_MAIN();
