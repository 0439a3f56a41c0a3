/// @file bench_weighted_averages.cpp
/// Weighted averages on surfaces (Panozzo et al. 2013) on the authors' four meshes
/// (BARYLAB_SHARED_DIR/wa: plane, igea, 3holes, gargo): the precomputation's stages and the
/// per-query cost of the forward and inverse problems, with the paper's protocol (Table 1: random
/// points, their weights by the inverse problem, then the forward problem with those weights,
/// which must return to the points).
///
/// Anchors: n (4 or 16) farthest-point samples among the vertices within a geodesic (edge-graph)
/// radius of 12% of the mesh's diameter around the vertex nearest the bounding-box centre
/// projected to the surface; so the anchors cover a patch, as a user places them. Query points:
/// the forward problem of random convex weights (uniform on the simplex, std::mt19937_64 with a
/// fixed seed), so every query is a weighted average of the anchors by construction.
///
/// Benchmarks (per mesh m = 0..3, anchors n, threads t):
///   Precompute/m           the embedding's stages and the Phong precomputation (counters, s)
///   Forward/m/n/t          forward problems of 100,000 rows of weights, no initial guess
///   Inverse/m/n/t          inverse problems of the 100,000 points
/// Counters: items_per_second (queries per second, wall-clock), failures, round-trip median and max error
/// (relative to the mean edge length) and outliers (round trip > 1e-6 mean edge lengths).
#include "core/surface/euclidean_embedding.h"
#include "core/surface/weighted_averages.h"
#include "igl_formats.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <queue>
#include <random>

using namespace bary;

namespace
{

const char* const kMeshes[] = { "plane", "igea", "3holes", "gargo" };

struct Setup
{
  std::unique_ptr<WeightedAverages> wa;
  EmbeddingResult embedding;
  double phong_seconds = 0;
};

std::map<int, Setup>& setups()
{
  static std::map<int, Setup> s;
  return s;
}

Setup* setup(int m)
{
  auto& all = setups();
  auto it = all.find(m);
  if (it != all.end())
    return &it->second;
  const std::filesystem::path path =
    std::filesystem::path(BARYLAB_SHARED_DIR) / "wa" / (std::string(kMeshes[m]) + ".obj");
  if (!std::filesystem::exists(path))
    return nullptr;
  const auto obj = test::read_obj(path.string());
  SurfaceMesh mesh(obj.V, obj.F);
  Setup s;
  s.embedding = euclidean_embedding(mesh);
  const auto t0 = std::chrono::steady_clock::now();
  s.wa = std::make_unique<WeightedAverages>(std::move(mesh), s.embedding.E);
  s.phong_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return &(all[m] = std::move(s));
}

std::vector<SurfacePoint> patch_anchors(const SurfaceMesh& m, int n)
{
  const Eigen::RowVector3d centre = 0.5 * (m.V.colwise().minCoeff() + m.V.colwise().maxCoeff());
  Index c = 0;
  (m.V.rowwise() - centre).rowwise().squaredNorm().minCoeff(&c);
  const double diameter = (m.V.colwise().maxCoeff() - m.V.colwise().minCoeff()).norm();
  // Dijkstra from c.
  std::vector<double> d(static_cast<std::size_t>(m.vertex_count()), 1e300);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
  d[c] = 0;
  heap.emplace(0.0, static_cast<int>(c));
  while (!heap.empty())
  {
    const auto [dv, v] = heap.top();
    heap.pop();
    if (dv > d[v])
      continue;
    for (int i = m.ring_offsets[v]; i < m.ring_offsets[v + 1]; ++i)
    {
      const int u = m.ring[i];
      const double du = dv + (m.V.row(u) - m.V.row(v)).norm();
      if (du < d[u])
        heap.emplace(d[u] = du, u);
    }
  }
  std::vector<int> patch;
  for (Index v = 0; v < m.vertex_count(); ++v)
    if (d[v] <= 0.12 * diameter)
      patch.push_back(static_cast<int>(v));
  // Farthest-point samples within the patch (Euclidean distance), starting from its farthest
  // vertex from c.
  std::vector<double> best(patch.size(), 1e300);
  std::vector<int> chosen;
  std::size_t next = 0;
  for (std::size_t i = 0; i < patch.size(); ++i)
    if (d[patch[i]] > d[patch[next]])
      next = i;
  while (static_cast<int>(chosen.size()) < n)
  {
    chosen.push_back(patch[next]);
    for (std::size_t i = 0; i < patch.size(); ++i)
      best[i] = std::min(best[i], (m.V.row(patch[i]) - m.V.row(patch[next])).norm());
    next = static_cast<std::size_t>(std::max_element(best.begin(), best.end()) - best.begin());
  }
  std::vector<SurfacePoint> anchors;
  for (const int v : chosen)
  {
    SurfacePoint p;
    p.face = m.vertex_faces[m.face_offsets[v]];
    for (int k = 0; k < 3; ++k)
      p.barycentric(k) = m.F(p.face, k) == v ? 1.0 : 0.0;
    anchors.push_back(p);
  }
  return anchors;
}

DenseWeights random_convex(Index rows, Index n, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::exponential_distribution<double> e(1.0);
  DenseWeights W(rows, n);
  for (Index r = 0; r < rows; ++r)
  {
    for (Index i = 0; i < n; ++i)
      W(r, i) = e(rng);
    W.row(r) /= W.row(r).sum();
  }
  return W;
}

constexpr Index kQueries = 100000;

void Precompute(benchmark::State& state)
{
  const int m = static_cast<int>(state.range(0));
  Setup* s = setup(m);
  if (!s)
  {
    state.SkipWithError("no shared data (BARYLAB_SHARED_DIR/wa)");
    return;
  }
  for (auto _ : state)
    benchmark::DoNotOptimize(s->phong_seconds);
  double total = 0;
  for (const auto& [stage, seconds] : s->embedding.seconds)
  {
    state.counters[stage + "_s"] = seconds;
    total += seconds;
  }
  state.counters["phong_s"] = s->phong_seconds;
  state.counters["total_s"] = total + s->phong_seconds;
  state.counters["vertices"] = static_cast<double>(s->wa->mesh().vertex_count());
  state.counters["smacof_iterations"] = s->embedding.smacof_iterations;
  state.counters["distance_error_mean"] = s->embedding.quality.mean_relative_error;
  state.counters["distance_error_max"] = s->embedding.quality.max_relative_error;
  state.SetLabel(kMeshes[m]);
}

void Queries(benchmark::State& state, bool inverse)
{
  const int m = static_cast<int>(state.range(0));
  const int n = static_cast<int>(state.range(1));
  const int threads = static_cast<int>(state.range(2));
  const Index queries = state.range(3) > 0 ? state.range(3) : kQueries;
  Setup* s = setup(m);
  if (!s)
  {
    state.SkipWithError("no shared data (BARYLAB_SHARED_DIR/wa)");
    return;
  }
  const WeightedAverages& wa = *s->wa;
  const auto anchors = patch_anchors(wa.mesh(), n);
  const DenseWeights W0 = random_convex(queries, n, 20131 + static_cast<std::uint64_t>(m * 100 + n));
  ForwardOptions fo;
  fo.threads = threads;
  const ForwardResult first = wa.forward(anchors, W0, fo);
  std::vector<SurfacePoint> points;
  for (std::size_t q = 0; q < first.points.size(); ++q)
    if (first.valid[q])
      points.push_back(first.points[q]);
  InverseOptions io;
  io.threads = threads;
  DenseWeights W = wa.inverse(anchors, points, io);
  ForwardResult again;
  for (auto _ : state)
  {
    if (inverse)
      W = wa.inverse(anchors, points, io);
    else
      again = wa.forward(anchors, W, fo);
    benchmark::ClobberMemory();
  }
  if (inverse)
    again = wa.forward(anchors, W, fo);
  const RoundTrip rt = wa.round_trip(anchors, points, W, 1e-6, fo);
  const double h = wa.mesh().mean_edge_length;
  state.SetItemsProcessed(state.iterations() * static_cast<Index>(points.size()));
  state.counters["failures_first"] = static_cast<double>(first.failures);
  state.counters["failures"] = static_cast<double>(rt.failures);
  state.counters["outliers"] = static_cast<double>(rt.not_returned);
  state.counters["rt_median_h"] = rt.median_error / h;
  state.counters["rt_max_h"] = rt.max_error / h;
  state.SetLabel(std::string(kMeshes[m]) + (inverse ? " inverse" : " forward"));
}

void Forward(benchmark::State& state) { Queries(state, false); }
void Inverse(benchmark::State& state) { Queries(state, true); }

void QueryArgs(benchmark::internal::Benchmark* b)
{
  for (int m = 0; m < 4; ++m)
    for (const int n : { 4, 16 })
      for (const int t : { 1, 2 })
        b->Args({ m, n, t, 0 });
  b->Args({ 0, 4, 1, 2000 }); // the smoke run: the plane, 2,000 queries
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

} // namespace

BENCHMARK(Precompute)->DenseRange(0, 3)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(Forward)->Apply(QueryArgs);
BENCHMARK(Inverse)->Apply(QueryArgs);

BENCHMARK_MAIN();
