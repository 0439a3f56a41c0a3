// Harmonic coordinates: bind time (mesh the cage's interior, factor, solve for all cage
// vertices) against mesh size, 2D and 3D, split into phases. See docs/benchmarks.md.
#include "core/coordinates/harmonic_coordinates.h"

#include <benchmark/benchmark.h>

#include <cmath>

namespace
{
bary::Cage square()
{
  bary::Cage c;
  c.V.resize(4, 2);
  c.V << 0, 0, 1, 0, 1, 1, 0, 1;
  return c;
}

/// A 2D star-shaped cage with @p n vertices (radius 1 +- 0.3), like a character cage.
bary::Cage star(int n)
{
  bary::Cage c;
  c.V.resize(n, 2);
  for (int i = 0; i < n; ++i)
  {
    const double a = 2 * M_PI * i / n, r = i % 2 ? 0.7 : 1.0;
    c.V.row(i) << r * std::cos(a), r * std::sin(a);
  }
  return c;
}

/// The cube [0,1]^3, 12 outward triangles.
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

void bind(benchmark::State& state, const bary::Cage& cage)
{
  bary::HarmonicOptions options;
  options.polygon_mesh.target_cells = static_cast<int>(state.range(0));
  options.surface_mesh.target_cells = static_cast<int>(state.range(0));
  bary::HarmonicReport report;
  for (auto _ : state)
  {
    bary::HarmonicCoordinates hc(cage, options);
    report = hc.report();
    benchmark::DoNotOptimize(hc.mesh_weights().data());
  }
  state.counters["controls"] = static_cast<double>(cage.num_controls());
  state.counters["mesh_vertices"] = static_cast<double>(report.mesh_vertices);
  state.counters["cells"] = static_cast<double>(report.mesh_cells);
  state.counters["mesh_s"] = report.mesh_seconds;
  state.counters["factor_s"] = report.factor_seconds;
  state.counters["solve_s"] = report.solve_seconds;
  state.counters["residual"] = report.max_residual;
}

void BM_Harmonic2D_Square(benchmark::State& state) { bind(state, square()); }
void BM_Harmonic2D_Star32(benchmark::State& state) { bind(state, star(32)); }
void BM_Harmonic3D_Cube(benchmark::State& state) { bind(state, cube()); }
} // namespace

BENCHMARK(BM_Harmonic2D_Square)->Arg(3000)->Arg(12000)->Arg(48000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Harmonic2D_Star32)->Arg(3000)->Arg(12000)->Arg(48000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Harmonic3D_Cube)->Arg(5000)->Arg(20000)->Arg(80000)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
