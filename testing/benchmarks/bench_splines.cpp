// C1 spline deformations (Rodrigues et al. 2014): time per DECLeS edit against grid size and
// delta_max, with and without the cached exact elimination, and the exact elimination's share;
// deformation throughput (point location once, then evaluation) for 10^6 points.
//
// Grids: [-1, 1] x [-0.5, 0.5] cut into 2 n x n squares, diagonals alternating (interior vertex
// degrees 4 and 8), 4 n^2 triangles, degree 5. An edit translates the control point nearest
// (0.2 h, 0) (the edge corner next to the centre vertex on its horizontal edge; with the last
// argument 1, the centre vertex itself) by a small
// vector; "Uncached" clears the elimination cache before each edit (the first edit of a
// drag), "Cached" does not (the following ones). See docs/benchmarks.md.
#include "core/spline/decles.h"
#include "core/spline/triangular_spline.h"

#include <benchmark/benchmark.h>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <random>

namespace
{
using bary::Index;

std::shared_ptr<bary::SplineNet> make_net(int n)
{
  const int nx = 2 * n, ny = n;
  const double h = 1.0 / n;
  Eigen::MatrixXd V((nx + 1) * (ny + 1), 2);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      V.row(j * (nx + 1) + i) << -1.0 + h * i, -0.5 + h * j;
  Eigen::MatrixXi T(2 * nx * ny, 3);
  int t = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
    {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
      if ((i + j) % 2 == 0)
      {
        T.row(t++) << a, b, c;
        T.row(t++) << a, c, d;
      }
      else
      {
        T.row(t++) << a, b, d;
        T.row(t++) << b, c, d;
      }
    }
  return std::make_shared<bary::SplineNet>(V, T, 5);
}

// Edit/<n>/<delta_max>/<cached>/<anchor: 0 edge point, 1 vertex>
void Edit(benchmark::State& state)
{
  const int n = static_cast<int>(state.range(0));
  const auto net = make_net(n);
  bary::SplineEditor editor(bary::TriangularSpline::identity(net));
  const bool cached = state.range(2) != 0;
  // The centre vertex, or the edge corner next to it on the horizontal edge (h = 1 / n).
  const Eigen::Vector2d where = state.range(3) ? Eigen::Vector2d(0.0, 0.0) : Eigen::Vector2d(0.2 / n, 0.0);
  bary::SplineEdit e;
  e.anchors = { editor.nearest_point(where) };
  e.delta_max = static_cast<int>(state.range(1));
  double sign = 1, exact = 0, total = 0;
  bary::SplineEditReport r;
  for (auto _ : state)
  {
    if (!cached)
      editor.clear_cache();
    e.by = Eigen::Vector2d(1e-3, 5e-4) * sign;
    sign = -sign;
    r = editor.apply(e);
    exact += r.exact_seconds;
    total += r.seconds;
  }
  state.counters["triangles"] = static_cast<double>(net->num_triangles());
  state.counters["derived"] = static_cast<double>(r.sets.derived.size());
  state.counters["conditions"] = static_cast<double>(r.sets.constraints.size());
  state.counters["exact_share"] = total > 0 ? exact / total : 0;
  state.SetLabel(std::string(bary::to_string(net->type(e.anchors[0]))));
}

// Deform/<threads>: 10^6 random points in the domain of a 1024-triangle spline (after a few
// edits): locate once (counter locate_s), then evaluate per iteration.
void Deform(benchmark::State& state)
{
  const int threads = static_cast<int>(state.range(0));
  omp_set_num_threads(threads);
  const auto net = make_net(16);
  bary::SplineEditor editor(bary::TriangularSpline::identity(net));
  for (int k = 0; k < 10; ++k)
  {
    bary::SplineEdit e;
    e.near = { Eigen::Vector2d(-0.8 + 0.17 * k, 0.3 * std::sin(k)) };
    e.by = Eigen::Vector2d(0.02, -0.01);
    e.delta_max = 3;
    editor.apply(e);
  }
  const Index np = 1000000;
  bary::Points P(np, 2);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> ux(-0.999, 0.999), uy(-0.499, 0.499);
  for (Index p = 0; p < np; ++p)
    P.row(p) << ux(rng), uy(rng);
  const auto t0 = std::chrono::steady_clock::now();
  const auto where = editor.spline().locate(P);
  const double locate_s =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (auto _ : state)
  {
    Eigen::MatrixXd Q = editor.spline().evaluate(where);
    benchmark::DoNotOptimize(Q.data());
  }
  state.counters["locate_s"] = locate_s;
  state.counters["points_per_s"] =
    benchmark::Counter(static_cast<double>(np), benchmark::Counter::kIsIterationInvariantRate);
}

} // namespace

BENCHMARK(Edit)
  ->ArgsProduct({ { 8, 16, 32, 64 }, { 0, 2, 4, 8 }, { 0, 1 }, { 0 } })
  ->ArgsProduct({ { 16, 64 }, { 0, 4 }, { 0, 1 }, { 1 } })
  ->Unit(benchmark::kMicrosecond);
BENCHMARK(Deform)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
