/// @file bench_celestial_coordinates.cpp
/// Throughput (points/s) of T- and S-Celestial coordinates, bary::CelestialCoordinates::compute,
/// against the number of control points and of query points, with and without warm starts.
///
/// Controls (3D): the 8 corners of the cube [-1, 1]^3 plus #C - 8 points uniform in
/// [-0.9, 0.9]^3, so the convex hull is the cube (6 square facets); #C = 8, 30, 100, 200.
/// Points: #P = 1e3, 1e4, 1e5 uniform in [-0.95, 0.95]^3 (all strictly inside), and 1e6 for
/// #C = 30 only. Both from std::mt19937_64 with fixed seeds (the standard fixes its output).
/// A 2D case (30 controls: the square's corners + 26 random, 1e5 points) is included for
/// comparison.
///
/// Variants: scheme T or S; warm (the default: Hilbert order, warm starts inside chunks of 256
/// points) or cold (every point from the paper's initial guess); threads = 2 (override with
/// the environment variable BARYLAB_BENCH_THREADS).
///
/// Timed: one compute() call (classification, ordering, Newton, weights, allocation of the
/// #P x #C result); "/reuse" (10^6 points): compute(X, result) into the previous call's result,
/// reusing its storage (an animation's frames). Not timed: the constructor (hull; its time is the counter setup_ms).
/// Counters: items_per_second = points/s; it_per_point = Newton iterations per point
/// (total_iterations / #P, including failed warm attempts); warm_frac = points started warm;
/// and, from the last timed result, checked after the loop: pou_err = max |sum_i w_i - 1|,
/// repro_err = max |sum_i w_i v_i - p| / diameter, max_residual. A benchmark is skipped with an
/// error if a point is not Inside or did not converge, or if an error exceeds 1e-10.
///
/// Edits (the viewer's incremental update, FreePointsMode::EditedWeights): one control point
/// added (at a random interior position) to 30 controls, 1e4 and 1e5 points; timed: the
/// compute() for the 31 controls started from the solution for the 30 (compute_from,
/// "from_solution") against the same compute() started as usual ("recompute"). Removing a
/// control is the same computation with one control fewer.
///
/// How it was run and what it measured: docs/celestial-coordinates.md.

#include "core/coordinates/celestial_coordinates.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace
{

using bary::Index;

constexpr std::uint64_t kSeed = 20240601;
constexpr double kMaxError = 1e-10;

int bench_threads()
{
  const char* env = std::getenv("BARYLAB_BENCH_THREADS");
  return env ? std::max(1, std::atoi(env)) : 2;
}

/// Uniform in [0, 1) from the top 53 bits: identical on every platform.
double uniform01(std::mt19937_64& gen)
{
  return static_cast<double>(gen() >> 11) * 0x1.0p-53;
}

bary::Points make_controls(int dim, Index n)
{
  std::mt19937_64 gen(kSeed + static_cast<std::uint64_t>(n * 10 + dim));
  const Index corners = Index(1) << dim;
  bary::Points V(n, dim);
  for (Index c = 0; c < corners; ++c)
    for (int k = 0; k < dim; ++k)
      V(c, k) = (c >> k) & 1 ? 1.0 : -1.0;
  for (Index i = corners; i < n; ++i)
    for (int k = 0; k < dim; ++k)
      V(i, k) = 0.9 * (2.0 * uniform01(gen) - 1.0);
  return V;
}

const bary::Points& points(int dim, Index n)
{
  static std::map<std::pair<int, Index>, bary::Points> cache;
  auto it = cache.find({ dim, n });
  if (it != cache.end())
    return it->second;
  std::mt19937_64 gen(kSeed + 1 + static_cast<std::uint64_t>(dim));
  bary::Points X(n, dim);
  for (Index p = 0; p < n; ++p)
    for (int k = 0; k < dim; ++k)
      X(p, k) = 0.95 * (2.0 * uniform01(gen) - 1.0);
  return cache.emplace(std::make_pair(dim, n), std::move(X)).first->second;
}

void bm_celestial(
  benchmark::State& state, bary::CelestialScheme scheme, int dim, Index nc, Index np, bool warm,
  bool reuse)
{
  const bary::Points V = make_controls(dim, nc);
  const bary::Points& X = points(dim, np);
  bary::CelestialOptions options;
  options.scheme = scheme;
  options.warm_start = warm;
  options.threads = bench_threads();
  const auto t0 = std::chrono::steady_clock::now();
  const bary::CelestialCoordinates cc(V, options);
  const double setup_ms =
    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  bary::CelestialResult result;
  if (reuse)
    cc.compute(X, result); // untimed: the storage the timed calls reuse
  for (auto _ : state)
  {
    if (reuse)
      cc.compute(X, result);
    else
      result = cc.compute(X);
    benchmark::DoNotOptimize(result.W.data());
    benchmark::ClobberMemory();
  }

  // accuracy of the last result (untimed)
  const double diam = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  double pou = 0.0, repro = 0.0;
  for (Index p = 0; p < np; ++p)
  {
    const double e_pou = std::abs(result.W.row(p).sum() - 1.0);
    const double e_rep = (result.W.row(p) * V - X.row(p)).norm() / diam;
    pou = (e_pou > pou || std::isnan(e_pou)) ? e_pou : pou;
    repro = (e_rep > repro || std::isnan(e_rep)) ? e_rep : repro;
  }
  if (result.inside != np || !result.not_converged.empty())
    state.SkipWithError("not every point was Inside and converged");
  else if (!(pou <= kMaxError && repro <= kMaxError))
    state.SkipWithError("partition of unity or reproduction error above 1e-10");

  state.SetItemsProcessed(state.iterations() * np);
  state.counters["controls"] = static_cast<double>(nc);
  state.counters["points"] = static_cast<double>(np);
  state.counters["threads"] = options.threads;
  state.counters["it_per_point"] = static_cast<double>(result.total_iterations) / np;
  state.counters["warm_frac"] = static_cast<double>(result.warm_starts) / np;
  state.counters["max_residual"] = result.residual.maxCoeff();
  state.counters["pou_err"] = pou;
  state.counters["repro_err"] = repro;
  state.counters["setup_ms"] = setup_ms;
  state.counters["hull_facets"] = static_cast<double>(cc.num_hull_facets());
}

void bm_edit(benchmark::State& state, bary::CelestialScheme scheme, Index np, bool from_solution)
{
  const int dim = 3;
  const bary::Points V = make_controls(dim, 30);
  const bary::Points& X = points(dim, np);
  bary::CelestialOptions options;
  options.scheme = scheme;
  options.threads = bench_threads();
  const bary::CelestialResult before = bary::CelestialCoordinates(V, options).compute(X);
  bary::Points edited(V.rows() + 1, dim);
  edited << V, bary::Points::Constant(1, dim, 0.0);
  edited.row(V.rows()) << 0.31, -0.42, 0.17;
  const bary::CelestialCoordinates cc(edited, options);
  bary::CelestialResult result;
  for (auto _ : state)
  {
    result = from_solution ? cc.compute_from(X, before.solution) : cc.compute(X);
    benchmark::DoNotOptimize(result.W.data());
    benchmark::ClobberMemory();
  }
  if (result.inside != np || !result.not_converged.empty())
    state.SkipWithError("not every point was Inside and converged");
  state.SetItemsProcessed(state.iterations() * np);
  state.counters["it_per_point"] = static_cast<double>(result.total_iterations) / np;
  state.counters["warm_frac"] = static_cast<double>(result.warm_starts) / np;
  state.counters["cold_restarts"] = static_cast<double>(result.cold_restarts);
}

void register_all()
{
  for (Index np : { 10000, 100000 })
    for (bary::CelestialScheme scheme : { bary::CelestialScheme::S, bary::CelestialScheme::T })
      for (bool from_solution : { true, false })
      {
        const std::string name = std::string(scheme == bary::CelestialScheme::S ? "SCC" : "TCC") +
          "_3d_edit/controls:30+1/points:" + std::to_string(np) +
          (from_solution ? "/from_solution" : "/recompute");
        benchmark::RegisterBenchmark(name.c_str(), bm_edit, scheme, np, from_solution)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->MeasureProcessCPUTime();
      }

  using bary::CelestialScheme;
  struct Case
  {
    int dim;
    Index nc, np;
  };
  std::vector<Case> cases;
  for (Index nc : { 8, 30, 100, 200 })
    for (Index np : { 1000, 10000, 100000 })
      cases.push_back({ 3, nc, np });
  cases.push_back({ 3, 30, 1000000 });
  cases.push_back({ 2, 30, 100000 });
  for (const Case& c : cases)
    for (CelestialScheme scheme : { CelestialScheme::S, CelestialScheme::T })
      for (bool warm : { true, false })
      {
        const std::string name = std::string(scheme == CelestialScheme::S ? "SCC" : "TCC") + "_" +
          std::to_string(c.dim) + "d/controls:" + std::to_string(c.nc) +
          "/points:" + std::to_string(c.np) + (warm ? "/warm" : "/cold");
        benchmark::RegisterBenchmark(
          name.c_str(), bm_celestial, scheme, c.dim, c.nc, c.np, warm, false)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->MeasureProcessCPUTime();
        if (c.np == 1000000 && warm)
          benchmark::RegisterBenchmark(
            (name + "/reuse").c_str(), bm_celestial, scheme, c.dim, c.nc, c.np, warm, true)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->MeasureProcessCPUTime();
      }
}

} // namespace

int main(int argc, char** argv)
{
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
