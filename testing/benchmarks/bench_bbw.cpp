// Bounded biharmonic weights: bind time per handle against mesh size (2D: the bundled
// gingerbread man with its 8-bone skeleton; 3D: a cube with a 3-bone chain and 2 point handles),
// fast and coupled modes, with active-set iteration counts; libigl's hand (7,234 vertices, 20
// bones) on 1 and 2 threads when ../shared/data is present; and pose time per frame (linear
// blend skinning) against the number of points and handles. See docs/benchmarks.md.
#include "core/coordinates/bbw.h"
#include "core/meshing/domain_mesh.h"
#include "core/deformation/linear_blend_skinning.h"
#include "core/deformation/skeleton.h"
#include "core/detail/simd.h"
#include "core/solvers/box_constrained_qp.h"
#include "core/solvers/sparse_cholesky.h"

#include "igl_formats.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <cstdlib>
#include <numeric>
#include <random>
#include <sstream>

namespace
{
/// The bundled gingerbread polygon (data/cage2d.obj: `v x y 0` lines).
bary::Cage gingerbread()
{
  std::ifstream in(std::string(BARYLAB_DATA_DIR) + "/cage2d.obj");
  std::vector<std::array<double, 2>> v;
  std::string tag;
  double x, y, z;
  while (in >> tag >> x >> y >> z)
    if (tag == "v")
      v.push_back({ x, y });
  bary::Cage c;
  c.V.resize(static_cast<Eigen::Index>(v.size()), 2);
  for (std::size_t i = 0; i < v.size(); ++i)
    c.V.row(static_cast<Eigen::Index>(i)) << v[i][0], v[i][1];
  return c;
}

/// data/skeleton2d.tgf (bones only).
bary::Skeleton skeleton2d()
{
  const bary::test::TgfSkeleton t = bary::test::read_tgf(std::string(BARYLAB_DATA_DIR) + "/skeleton2d.tgf");
  bary::Skeleton s;
  s.C = t.C.leftCols(2);
  s.BE = t.E;
  return s;
}

bary::Cage cube()
{
  bary::Cage c;
  c.V.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    c.V.row(i) << 2.0 * (i & 1) - 1, 2.0 * (i >> 1 & 1) - 1, 2.0 * (i >> 2 & 1) - 1;
  c.F.resize(12, 3);
  c.F << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1,
    3, 5, 3, 7, 5;
  return c;
}

/// A chain of 3 bones through the cube and 2 point handles (5 handles).
bary::Skeleton skeleton3d()
{
  bary::Skeleton s;
  s.C.resize(6, 3);
  s.C << -0.7, -0.6, 0, -0.2, 0, 0.1, 0.3, 0.2, -0.1, 0.7, 0.6, 0.2, 0.5, -0.6, 0.5, -0.5, 0.6, -0.5;
  s.P.resize(2);
  s.P << 4, 5;
  s.BE.resize(3, 2);
  s.BE << 0, 1, 1, 2, 2, 3;
  return s;
}

struct Bound
{
  bary::DomainMesh mesh;
  bary::BBWHandles handles;
};

/// Meshes the domain with the skeleton's samples inserted about one edge length apart.
Bound mesh_with_skeleton(const bary::Cage& domain, const bary::Skeleton& s, int cells)
{
  Bound b;
  if (domain.dimension() == 2)
  {
    double area = 0;
    for (Eigen::Index i = 0; i < domain.V.rows(); ++i)
    {
      const Eigen::Index j = (i + 1) % domain.V.rows();
      area += domain.V(i, 0) * domain.V(j, 1) - domain.V(j, 0) * domain.V(i, 1);
    }
    const double h = std::sqrt(4.0 * std::abs(area) / 2 / cells / std::sqrt(3.0));
    bary::PolygonMeshOptions o;
    o.target_cells = cells;
    o.steiner_points = bary::skeleton_samples(s, h);
    b.mesh = bary::mesh_polygon(domain, o);
  }
  else
  {
    const double h = std::cbrt(6.0 * std::sqrt(2.0) * 8.0 / cells);
    bary::SurfaceMeshOptions o;
    o.target_cells = cells;
    o.steiner_points = bary::skeleton_samples(s, h);
    b.mesh = bary::mesh_closed_surface(domain, o);
  }
  b.handles = bary::handles_from_skeleton(b.mesh.V, s.C, s.P, s.BE);
  return b;
}

void report(benchmark::State& state, const bary::BBWResult& r, Eigen::Index vertices, double seconds)
{
  long long iterations = 0, factorizations = 0;
  for (std::size_t j = 0; j < r.iterations.size(); ++j)
  {
    iterations += r.iterations[j];
    factorizations += r.factorizations[j];
  }
  const double handles = static_cast<double>(r.W.cols());
  state.counters["vertices"] = static_cast<double>(vertices);
  state.counters["handles"] = handles;
  state.counters["s_per_handle"] = seconds / handles;
  state.counters["fast_iterations"] = static_cast<double>(iterations);
  state.counters["fast_factorizations"] = static_cast<double>(factorizations);
  state.counters["outer"] = r.outer_iterations;
  state.counters["coupled_iterations"] = r.coupled_iterations;
  state.counters["max_kkt"] = r.max_kkt_residual;
  if (!r.iterations.empty() && r.mode == bary::BBWMode::Coupled) // BBWOptions::compare_with_fast
  {
    state.counters["E_mean"] = r.fast_difference_mean;
    state.counters["E_max"] = r.fast_difference_max;
  }
}

void bind(benchmark::State& state, const bary::Cage& domain, const bary::Skeleton& s,
  bary::BBWMode mode)
{
  const Bound b = mesh_with_skeleton(domain, s, static_cast<int>(state.range(0)));
  bary::BBWOptions options;
  options.mode = mode;
  bary::BBWResult r;
  double seconds = 0;
  for (auto _ : state)
  {
    r = bary::bounded_biharmonic_weights(b.mesh.V, b.mesh.T, b.handles, options);
    seconds = r.seconds;
    benchmark::DoNotOptimize(r.W.data());
  }
  report(state, r, b.mesh.V.rows(), seconds);
  state.counters["cells"] = static_cast<double>(b.mesh.T.rows());
}

void BBW2DFast(benchmark::State& state) { bind(state, gingerbread(), skeleton2d(), bary::BBWMode::Fast); }
void BBW2DCoupled(benchmark::State& state) { bind(state, gingerbread(), skeleton2d(), bary::BBWMode::Coupled); }
void BBW3DFast(benchmark::State& state) { bind(state, cube(), skeleton3d(), bary::BBWMode::Fast); }
void BBW3DCoupled(benchmark::State& state) { bind(state, cube(), skeleton3d(), bary::BBWMode::Coupled); }

BENCHMARK(BBW2DFast)->Arg(1000)->Arg(3000)->Arg(10000)->Arg(30000)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BBW2DCoupled)->Arg(1000)->Arg(3000)->Arg(10000)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BBW3DFast)->Arg(5000)->Arg(20000)->Arg(80000)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BBW3DCoupled)->Arg(5000)->Arg(20000)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

/// libigl's tutorial hand (7,234 vertices, 20 bones), fast mode, range(0) threads.
void BBWHandFast(benchmark::State& state)
{
  const std::string dir = std::string(BARYLAB_SHARED_DIR) + "/igl";
  if (!std::filesystem::exists(dir + "/hand.mesh"))
  {
    state.SkipWithError("shared data not found (../shared/data/igl/hand.mesh)");
    return;
  }
  const auto mesh = bary::test::read_medit_mesh(dir + "/hand.mesh");
  const auto tgf = bary::test::read_tgf(dir + "/hand.tgf");
  const bary::BBWHandles h = bary::handles_from_skeleton(mesh.V, tgf.C, Eigen::VectorXi(), tgf.E);
  bary::BBWOptions options;
  options.mode = bary::BBWMode::Fast;
  options.threads = static_cast<int>(state.range(0));
  bary::BBWResult r;
  for (auto _ : state)
  {
    r = bary::bounded_biharmonic_weights(mesh.V, mesh.T, h, options);
    benchmark::DoNotOptimize(r.W.data());
  }
  report(state, r, mesh.V.rows(), r.seconds);
}
BENCHMARK(BBWHandFast)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

/// One free block of the fast mode, factored again and again (symbolic analysis and numeric
/// factorization, as the active-set solver does for a fresh factorization): handle 0's final
/// free set on libigl's hand (its weight strictly between the bounds), ordered by the
/// restriction of one AMD ordering of Q, Supernodal backend. range(0) = 0: the 256-bit (AVX2)
/// kernels, 1: the 512-bit ones where the CPU has AVX-512 (skipped elsewhere). Counters: the
/// block's size, the factor's entries and flops, GFlop/s of the whole factorization.
void BBWHandBlock(benchmark::State& state)
{
  const std::string dir = std::string(BARYLAB_SHARED_DIR) + "/igl/";
  if (!std::filesystem::exists(dir + "hand.mesh"))
  {
    state.SkipWithError("shared data not found (../shared/data/igl/hand.mesh)");
    return;
  }
  const bool wide = state.range(0) == 1;
  const bool before = bary::detail::avx512_enabled(); // restored after (BARYLAB_SIMD=avx2 stays)
  if (bary::detail::set_avx512_enabled(wide) != wide ||
    bary::detail::simd_level() != bary::detail::SimdLevel::AVX2)
  {
    bary::detail::set_avx512_enabled(before);
    state.SkipWithError("this CPU lacks the instruction set asked for");
    return;
  }
  const auto mesh = bary::test::read_medit_mesh(dir + "hand.mesh");
  const auto tgf = bary::test::read_tgf(dir + "hand.tgf");
  const bary::BBWHandles h = bary::handles_from_skeleton(mesh.V, tgf.C, Eigen::VectorXi(), tgf.E);
  const bary::BBWBoundaryConditions bc = bary::bbw_boundary_conditions(h, mesh.V.rows());
  const bary::BBWOptions defaults;
  const bary::BoundedBiharmonicWeights bbw(mesh.V, mesh.T, defaults);
  const Eigen::SparseMatrix<double>& Q = bbw.energy_matrix();
  const bary::Index n = Q.rows();
  Eigen::VectorXd l = Eigen::VectorXd::Zero(n), u = Eigen::VectorXd::Ones(n);
  for (bary::Index k = 0; k < bc.vertices.size(); ++k)
    l(bc.vertices(k)) = u(bc.vertices(k)) = bc.values(k, 0);
  bary::BoxQPOptions box;
  box.tolerance = defaults.tolerance;
  const bary::BoxQPResult r = bary::BoxConstrainedQP(Q).solve(Eigen::VectorXd::Zero(n), l, u, box);
  const Eigen::VectorXi amd = bary::fill_reducing_ordering(Q);
  std::vector<int> rank(static_cast<std::size_t>(n));
  for (bary::Index k = 0; k < n; ++k)
    rank[static_cast<std::size_t>(amd(k))] = static_cast<int>(k);
  std::vector<int> free;
  for (bary::Index i = 0; i < n; ++i)
    if (l(i) < u(i) && r.x(i) > 0.0 && r.x(i) < 1.0)
      free.push_back(static_cast<int>(i));
  const Eigen::VectorXi rows = Eigen::Map<const Eigen::VectorXi>(free.data(), static_cast<Eigen::Index>(free.size()));
  bary::SparseCholeskySettings settings;
  settings.trusted = true;
  settings.ordering = Eigen::VectorXi::LinSpaced(rows.size(), 0, static_cast<int>(rows.size()) - 1);
  std::sort(settings.ordering.data(), settings.ordering.data() + rows.size(),
    [&](int a, int b) { return rank[static_cast<std::size_t>(free[static_cast<std::size_t>(a)])] < rank[static_cast<std::size_t>(free[static_cast<std::size_t>(b)])]; });
  bary::SparseCholesky solver(bary::SparseCholesky::Backend::Supernodal);
  for (auto _ : state)
  {
    solver.compute_principal(Q, rows, settings);
    benchmark::DoNotOptimize(solver.min_pivot());
  }
  bary::detail::set_avx512_enabled(before);
  state.counters["block"] = static_cast<double>(rows.size());
  state.counters["entries"] = solver.factor_entries();
  state.counters["flops"] = solver.factor_flops();
  state.counters["GFlop/s"] = benchmark::Counter(
    solver.factor_flops() * 1e-9, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BBWHandBlock)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

/// The page's bind-time table (docs/bounded-biharmonic-weights.md#speed): libigl's decimated
/// knight (1,822 vertices, 7 bones) and hand (7,234 vertices, 20 bones) with the current
/// defaults (BBWOptions{}: Voronoi lumping; range(1) = 1 barycentric, to tell the lumping from
/// the machine's load), range(0) = 0 fast / 1 coupled, one thread, process CPU time.
void bind_igl(benchmark::State& state, const std::string& name, double radius)
{
  const std::string dir = std::string(BARYLAB_SHARED_DIR) + "/igl/";
  if (!std::filesystem::exists(dir + name + ".mesh"))
  {
    state.SkipWithError("shared data not found (../shared/data/igl/)");
    return;
  }
  const auto mesh = bary::test::read_medit_mesh(dir + name + ".mesh");
  const auto tgf = bary::test::read_tgf(dir + name + ".tgf");
  const bary::BBWHandles h = radius > 0
    ? bary::handles_from_skeleton(mesh.V, tgf.C, Eigen::VectorXi(), tgf.E, radius)
    : bary::handles_from_skeleton(mesh.V, tgf.C, Eigen::VectorXi(), tgf.E);
  bary::BBWOptions options;
  options.mode = state.range(0) == 0 ? bary::BBWMode::Fast : bary::BBWMode::Coupled;
  options.threads = 1;
  if (state.range(1) == 1)
    options.mass_lumping = bary::BBWMassLumping::Barycentric;
  bary::BBWResult r;
  for (auto _ : state)
  {
    r = bary::bounded_biharmonic_weights(mesh.V, mesh.T, h, options);
    benchmark::DoNotOptimize(r.W.data());
  }
  report(state, r, mesh.V.rows(), r.seconds);
}
/// The knight's bones sampled as the BBW oracle test does (radius sqrt(1e-7)).
void BBWKnight(benchmark::State& state) { bind_igl(state, "decimated-knight", std::sqrt(1e-7)); }
void BBWHand(benchmark::State& state) { bind_igl(state, "hand", 0.0); }
BENCHMARK(BBWKnight)->ArgsProduct({ { 0, 1 }, { 0, 1 } })->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->Iterations(1);
BENCHMARK(BBWHand)->ArgsProduct({ { 0, 1 }, { 0, 1 } })->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->Iterations(1);

/// Pose time: linear blend skinning of range(0) points by range(1) handles, dense weights, or
/// sparse weights with range(2) stored entries per point (range(2) = 0: dense). The points are
/// uniform in the unit cube, the weights uniform in [0, 1) (on range(2) distinct handles per
/// point when sparse, chosen uniformly) and normalised per point, the transforms random affine
/// maps; the same generator as the libigl driver in docs/benchmarks.md ("Skinning"), so both
/// pose the same data. One thread unless BARYLAB_BENCH_THREADS says otherwise.
void Skinning(benchmark::State& state)
{
  const auto np = static_cast<Eigen::Index>(state.range(0));
  const auto m = static_cast<Eigen::Index>(state.range(1));
  const auto k = static_cast<Eigen::Index>(state.range(2));
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  bary::Points X(np, 3);
  bary::DenseWeights W = bary::DenseWeights::Zero(np, m);
  std::vector<int> handles(static_cast<std::size_t>(m));
  for (Eigen::Index p = 0; p < np; ++p)
  {
    for (int c = 0; c < 3; ++c)
      X(p, c) = u(rng);
    if (k == 0)
      for (Eigen::Index j = 0; j < m; ++j)
        W(p, j) = u(rng);
    else
    {
      std::iota(handles.begin(), handles.end(), 0);
      for (Eigen::Index i = 0; i < k; ++i) // the first k of a random permutation
      {
        const auto r = i + static_cast<Eigen::Index>(u(rng) * static_cast<double>(m - i));
        std::swap(handles[static_cast<std::size_t>(i)], handles[static_cast<std::size_t>(r)]);
        W(p, handles[static_cast<std::size_t>(i)]) = u(rng);
      }
    }
    W.row(p) /= W.row(p).sum();
  }
  bary::AffineTransforms T(static_cast<std::size_t>(m));
  for (auto& t : T)
    t = Eigen::MatrixXd::NullaryExpr(3, 4, [&] { return u(rng) - 0.5; }) +
      Eigen::MatrixXd::Identity(3, 4);
  const char* env = std::getenv("BARYLAB_BENCH_THREADS");
  const int threads = env ? std::atoi(env) : 1;
  if (k == 0)
    for (auto _ : state)
      benchmark::DoNotOptimize(bary::linear_blend_skinning(X, W, T, threads).data());
  else
  {
    const bary::SparseWeights S = W.sparseView();
    for (auto _ : state)
      benchmark::DoNotOptimize(bary::linear_blend_skinning(X, S, T, threads).data());
  }
  state.counters["points"] = static_cast<double>(np);
  state.counters["handles"] = static_cast<double>(m);
  state.counters["per_point"] = static_cast<double>(k == 0 ? m : k);
  state.counters["threads"] = threads;
  state.SetItemsProcessed(state.iterations() * np);
}
BENCHMARK(Skinning)
  ->ArgsProduct({ { 7234, 100000, 1000000 }, { 20 }, { 0, 4 } })
  ->Args({ 100000, 8, 0 })
  ->Unit(benchmark::kMillisecond)
  ->UseRealTime();
} // namespace

BENCHMARK_MAIN();
