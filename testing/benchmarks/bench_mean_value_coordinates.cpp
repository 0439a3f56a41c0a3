/// @file bench_mean_value_coordinates.cpp
/// Throughput (points/s) of 3D mean value coordinates: BaryLab's batch evaluator
/// bary::MeanValueCoordinates::evaluate(const Points&) against VTK's
/// vtkMeanValueCoordinatesInterpolator::ComputeInterpolationWeights, on the same cages and the
/// same query points, in one run.
///
/// Cages (all convex, centred at the origin, faces oriented outward):
///   cube_12f      8 vertices,    12 triangles
///   ico_320f    162 vertices,   320 triangles (icosphere, 2 subdivisions)
///   ico_1280f   642 vertices, 1,280 triangles (icosphere, 3 subdivisions)
/// Points: 20,000 (or $BARYLAB_BENCH_POINTS) deterministic pseudo-random points strictly inside
/// each cage (uniform in [-0.9, 0.9]^3 for the cube, uniform in the ball of radius 0.9 for the
/// icospheres, whose inscribed radius is > 0.98), generated from std::mt19937_64 (whose output
/// the standard fixes).
///
/// Variants, per cage:
///   vtk_1t        VTK, one thread (a plain loop over the points; VTK's function is per point)
///   vtk_smp_2t    VTK, 2 threads through vtkSMPTools (VTK's own threading; backend printed)
///   vtk_omp_2t    VTK, 2 threads through an OpenMP loop (the same scheduling BaryLab uses)
///   barylab_1t    BaryLab, MeanValueOptions::threads = 1
///   barylab_2t    BaryLab, MeanValueOptions::threads = 2
///   barylab_1t_portable  BaryLab, 1 thread, the batch kernel's portable path (SSE2 on x86-64;
///                 what a CPU without AVX2 and FMA runs), chosen with detail::set_simd_level
///
/// Fairness: VTK writes into an output buffer allocated once before the timed loop, whereas
/// BaryLab's evaluate() allocates and returns a new #P x #C matrix (plus the location vector)
/// on every call and copies/validates the points: the comparison includes those costs for
/// BaryLab only. Both use double precision points (vtkPoints of type double).
///
/// Accuracy (computed once per cage, before any timing, and attached to every result as
/// counters): max |w_barylab - w_vtk| over all points and weights, and for each library the
/// partition-of-unity error max_p |sum_i w_i - 1| and the linear reproduction error
/// max_p max_k |sum_i w_i v_i[k] - x[k]|. A benchmark is skipped with an error if the two
/// libraries disagree by more than 1e-9 (NaN counts as disagreement), if one of these errors
/// exceeds 1e-9, or if BaryLab did not classify every point as inside.
///
/// Green coordinates against mean value coordinates (issue 14): the same evaluator loop for
/// BaryLab's bary::GreenCoordinates (phi and psi, the paper's extension off) on the same 3D
/// cages and points (green3d/<cage>/barylab_1t next to mvc3d/<cage>/barylab_1t), and on 2D
/// regular polygons of 16, 64 and 256 vertices with points uniform in the disc of radius 0.9
/// (mvc2d/<polygon>/barylab_1t, green2d/<polygon>/barylab_1t), one thread each: time per point.
///
/// How it was run and what it measured: docs/benchmarks.md.

#include "core/common/cage.h"
#include "core/coordinates/green_coordinates.h"
#include "core/coordinates/mean_value_coordinates.h"
#include "core/detail/simd.h"

#include <Eigen/Geometry>
#include <benchmark/benchmark.h>

#include <vtkIdList.h>
#include <vtkMeanValueCoordinatesInterpolator.h>
#include <vtkPoints.h>
#include <vtkSMPTools.h>
#include <vtkSmartPointer.h>
#include <vtkVersion.h>

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace
{

using bary::Index;

constexpr Index kDefaultNumPoints = 20000; // override with the environment variable BARYLAB_BENCH_POINTS
constexpr double kMaxAllowedDiff = 1e-9;
constexpr std::uint64_t kSeed = 20240531;

// ---------------------------------------------------------------------------------------------
// Cages
// ---------------------------------------------------------------------------------------------

using Tri = std::array<int, 3>;

/// Orients every face of a convex cage that contains the origin outward.
bary::Cage make_cage(const std::vector<Eigen::Vector3d>& verts, std::vector<Tri> faces)
{
  bary::Cage cage;
  cage.V.resize(static_cast<Index>(verts.size()), 3);
  for (std::size_t i = 0; i < verts.size(); ++i)
    cage.V.row(static_cast<Index>(i)) = verts[i].transpose();
  cage.F.resize(static_cast<Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
  {
    Tri& t = faces[f];
    const Eigen::Vector3d& a = verts[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d& b = verts[static_cast<std::size_t>(t[1])];
    const Eigen::Vector3d& c = verts[static_cast<std::size_t>(t[2])];
    if (!((b - a).cross(c - a).norm() > 1e-12))
      throw std::logic_error("degenerate cage face");
    // the origin is strictly inside the convex cage: det[a, b, c] > 0 iff the face is outward
    if (a.dot(b.cross(c)) < 0.0)
      std::swap(t[1], t[2]);
    cage.F.row(static_cast<Index>(f)) << t[0], t[1], t[2];
  }
  return cage;
}

bary::Cage cube()
{
  std::vector<Eigen::Vector3d> V;
  for (int i = 0; i < 8; ++i) // index bits: x = bit 0, y = bit 1, z = bit 2
    V.emplace_back((i & 1) ? 1.0 : -1.0, (i & 2) ? 1.0 : -1.0, (i & 4) ? 1.0 : -1.0);
  const int quads[6][4] = {
    { 0, 2, 6, 4 }, { 1, 3, 7, 5 }, { 0, 1, 5, 4 }, { 2, 3, 7, 6 }, { 0, 1, 3, 2 }, { 4, 5, 7, 6 }
  };
  std::vector<Tri> F;
  for (const auto& q : quads)
  {
    F.push_back({ q[0], q[1], q[2] });
    F.push_back({ q[0], q[2], q[3] });
  }
  return make_cage(V, F);
}

/// Unit icosphere: an icosahedron with every triangle split in 4, @p subdivisions times.
bary::Cage icosphere(int subdivisions)
{
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> V = { { -1, t, 0 }, { 1, t, 0 }, { -1, -t, 0 }, { 1, -t, 0 },
    { 0, -1, t }, { 0, 1, t }, { 0, -1, -t }, { 0, 1, -t }, { t, 0, -1 }, { t, 0, 1 },
    { -t, 0, -1 }, { -t, 0, 1 } };
  for (auto& v : V)
    v.normalize();
  std::vector<Tri> F = { { 0, 11, 5 }, { 0, 5, 1 }, { 0, 1, 7 }, { 0, 7, 10 }, { 0, 10, 11 },
    { 1, 5, 9 }, { 5, 11, 4 }, { 11, 10, 2 }, { 10, 7, 6 }, { 7, 1, 8 }, { 3, 9, 4 }, { 3, 4, 2 },
    { 3, 2, 6 }, { 3, 6, 8 }, { 3, 8, 9 }, { 4, 9, 5 }, { 2, 4, 11 }, { 6, 2, 10 }, { 8, 6, 7 },
    { 9, 8, 1 } };
  for (int s = 0; s < subdivisions; ++s)
  {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto it = midpoint.find(key);
      if (it != midpoint.end())
        return it->second;
      V.push_back((V[static_cast<std::size_t>(a)] + V[static_cast<std::size_t>(b)]).normalized());
      const int id = static_cast<int>(V.size()) - 1;
      midpoint.emplace(key, id);
      return id;
    };
    std::vector<Tri> G;
    G.reserve(4 * F.size());
    for (const Tri& f : F)
    {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      G.push_back({ f[0], ab, ca });
      G.push_back({ f[1], bc, ab });
      G.push_back({ f[2], ca, bc });
      G.push_back({ ab, bc, ca });
    }
    F = std::move(G);
  }
  return make_cage(V, F);
}

// ---------------------------------------------------------------------------------------------
// Points
// ---------------------------------------------------------------------------------------------

/// Uniform in [0, 1) from the top 53 bits: identical on every platform.
double uniform01(std::mt19937_64& gen)
{
  return static_cast<double>(gen() >> 11) * 0x1.0p-53;
}

/// @p n points uniform in [-r, r]^3 (ball = false) or in the ball of radius r (ball = true).
bary::Points interior_points(Index n, double r, bool ball, std::uint64_t seed)
{
  std::mt19937_64 gen(seed);
  bary::Points P(n, 3);
  for (Index p = 0; p < n;)
  {
    const Eigen::Vector3d x(
      r * (2.0 * uniform01(gen) - 1.0), r * (2.0 * uniform01(gen) - 1.0),
      r * (2.0 * uniform01(gen) - 1.0));
    if (ball && x.squaredNorm() >= r * r)
      continue;
    P.row(p++) = x.transpose();
  }
  return P;
}

// ---------------------------------------------------------------------------------------------
// One benchmark case: a cage, its points, their VTK forms, and the accuracy check
// ---------------------------------------------------------------------------------------------

struct Accuracy
{
  bool computed = false;
  std::string error; // empty if the check passed
  double max_diff = NAN;
  double pou_barylab = NAN, pou_vtk = NAN;
  double repro_barylab = NAN, repro_vtk = NAN;
};

struct Case
{
  std::string name;
  bary::Cage cage;
  bary::Points P;                           // #P x 3, column-major (BaryLab's input type)
  std::vector<double> X;                    // the same points, row-major (VTK's input)
  vtkSmartPointer<vtkPoints> vtk_points;    // cage vertices, double precision
  vtkSmartPointer<vtkIdList> vtk_triangles; // 3 ids per triangle
  Accuracy accuracy;

  Case(std::string n, bary::Cage c, bary::Points points)
    : name(std::move(n))
    , cage(std::move(c))
    , P(std::move(points))
  {
    X.resize(static_cast<std::size_t>(3 * P.rows()));
    for (Index p = 0; p < P.rows(); ++p)
      for (int k = 0; k < 3; ++k)
        X[static_cast<std::size_t>(3 * p + k)] = P(p, k);
    vtk_points = vtkSmartPointer<vtkPoints>::New();
    vtk_points->SetDataTypeToDouble();
    vtk_points->SetNumberOfPoints(cage.V.rows());
    for (Index i = 0; i < cage.V.rows(); ++i)
      vtk_points->SetPoint(i, cage.V(i, 0), cage.V(i, 1), cage.V(i, 2));
    vtk_triangles = vtkSmartPointer<vtkIdList>::New();
    vtk_triangles->SetNumberOfIds(3 * cage.F.rows());
    for (Index f = 0; f < cage.F.rows(); ++f)
      for (int k = 0; k < 3; ++k)
        vtk_triangles->SetId(3 * f + k, cage.F(f, k));
  }

  Index num_points() const { return P.rows(); }
  Index num_controls() const { return cage.V.rows(); }

  void vtk_weights(Index p, double* w) const
  {
    vtkMeanValueCoordinatesInterpolator::ComputeInterpolationWeights(
      X.data() + 3 * p, vtk_points, vtk_triangles, w);
  }
};

/// Partition of unity and linear reproduction errors of the row-major weights @p W.
std::pair<double, double> property_errors(const Case& c, const double* W)
{
  const Index np = c.num_points(), nc = c.num_controls();
  double pou = 0.0, repro = 0.0;
  for (Index p = 0; p < np; ++p)
  {
    const double* w = W + p * nc;
    double sum = 0.0;
    Eigen::Vector3d y = Eigen::Vector3d::Zero();
    for (Index i = 0; i < nc; ++i)
    {
      sum += w[i];
      y += w[i] * c.cage.V.row(i).transpose();
    }
    // NaN-propagating max: a NaN error stays NaN and fails the check below
    const double e_pou = std::abs(sum - 1.0);
    const double e_rep = (y - c.P.row(p).transpose()).cwiseAbs().maxCoeff();
    pou = (e_pou > pou || std::isnan(e_pou)) ? e_pou : pou;
    repro = (e_rep > repro || std::isnan(e_rep)) ? e_rep : repro;
  }
  return { pou, repro };
}

const Accuracy& check_accuracy(Case& c)
{
  Accuracy& a = c.accuracy;
  if (a.computed)
    return a;
  a.computed = true;
  const Index np = c.num_points(), nc = c.num_controls();

  bary::MeanValueResult result;
  try
  {
    bary::MeanValueOptions options;
    options.threads = 2;
    const bary::MeanValueCoordinates mvc(c.cage, options);
    result = mvc.evaluate(c.P);
  }
  catch (const std::exception& e)
  {
    a.error = c.name + ": BaryLab threw: " + e.what();
    std::fprintf(stderr, "[accuracy] %s\n", a.error.c_str());
    return a;
  }

  std::vector<double> Wv(static_cast<std::size_t>(np * nc));
#pragma omp parallel for schedule(dynamic, 64) num_threads(2)
  for (Index p = 0; p < np; ++p)
    c.vtk_weights(p, Wv.data() + p * nc);

  double max_diff = 0.0;
  for (Index p = 0; p < np; ++p)
    for (Index i = 0; i < nc; ++i)
    {
      const double d = std::abs(result.W(p, i) - Wv[static_cast<std::size_t>(p * nc + i)]);
      max_diff = (d > max_diff || std::isnan(d)) ? d : max_diff;
    }
  a.max_diff = max_diff;
  std::tie(a.pou_barylab, a.repro_barylab) = property_errors(c, result.W.data());
  std::tie(a.pou_vtk, a.repro_vtk) = property_errors(c, Wv.data());

  char buf[512];
  if (result.inside != np || !result.undefined.empty())
  {
    std::snprintf(buf, sizeof buf, "%s: BaryLab classified %ld of %ld points inside (%zu undefined)",
      c.name.c_str(), static_cast<long>(result.inside), static_cast<long>(np),
      result.undefined.size());
    a.error = buf;
  }
  else if (!(a.max_diff <= kMaxAllowedDiff))
  {
    std::snprintf(buf, sizeof buf, "%s: BaryLab and VTK disagree: max |w_barylab - w_vtk| = %.3g > %.0e",
      c.name.c_str(), a.max_diff, kMaxAllowedDiff);
    a.error = buf;
  }
  else if (!(a.pou_barylab <= kMaxAllowedDiff && a.repro_barylab <= kMaxAllowedDiff &&
             a.pou_vtk <= kMaxAllowedDiff && a.repro_vtk <= kMaxAllowedDiff))
  {
    std::snprintf(buf, sizeof buf,
      "%s: partition of unity / reproduction errors too large: barylab %.3g / %.3g, vtk %.3g / %.3g",
      c.name.c_str(), a.pou_barylab, a.repro_barylab, a.pou_vtk, a.repro_vtk);
    a.error = buf;
  }
  std::fprintf(stderr,
    "[accuracy] %-9s  #C=%4ld #F=%5ld #P=%ld  max|w_barylab-w_vtk|=%.3e  "
    "PoU err: barylab %.3e vtk %.3e  reproduction err: barylab %.3e vtk %.3e  %s\n",
    c.name.c_str(), static_cast<long>(nc), static_cast<long>(c.cage.F.rows()),
    static_cast<long>(np), a.max_diff, a.pou_barylab, a.pou_vtk, a.repro_barylab, a.repro_vtk,
    a.error.empty() ? "OK" : a.error.c_str());
  return a;
}

/// Runs the accuracy check (untimed) and attaches its result; false if the benchmark must stop.
bool setup(benchmark::State& state, Case& c)
{
  const Accuracy& a = check_accuracy(c);
  if (!a.error.empty())
  {
    state.SkipWithError(a.error.c_str());
    return false;
  }
  return true;
}

void finish(benchmark::State& state, const Case& c)
{
  const Accuracy& a = c.accuracy;
  state.SetItemsProcessed(state.iterations() * c.num_points());
  state.counters["points"] = static_cast<double>(c.num_points());
  state.counters["cage_vertices"] = static_cast<double>(c.num_controls());
  state.counters["cage_faces"] = static_cast<double>(c.cage.F.rows());
  state.counters["max_diff_vs_vtk"] = a.max_diff;
  state.counters["pou_err_barylab"] = a.pou_barylab;
  state.counters["pou_err_vtk"] = a.pou_vtk;
  state.counters["repro_err_barylab"] = a.repro_barylab;
  state.counters["repro_err_vtk"] = a.repro_vtk;
}

// ---------------------------------------------------------------------------------------------
// The benchmarks
// ---------------------------------------------------------------------------------------------

void bm_vtk_serial(benchmark::State& state, Case* c)
{
  if (!setup(state, *c))
    return;
  const Index np = c->num_points(), nc = c->num_controls();
  std::vector<double> W(static_cast<std::size_t>(np * nc), 0.0);
  for (auto _ : state)
  {
    for (Index p = 0; p < np; ++p)
      c->vtk_weights(p, W.data() + p * nc);
    benchmark::DoNotOptimize(W.data());
    benchmark::ClobberMemory();
  }
  finish(state, *c);
}

void bm_vtk_omp(benchmark::State& state, Case* c, int threads)
{
  if (!setup(state, *c))
    return;
  const Index np = c->num_points(), nc = c->num_controls();
  std::vector<double> W(static_cast<std::size_t>(np * nc), 0.0);
  for (auto _ : state)
  {
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads)
    for (Index p = 0; p < np; ++p)
      c->vtk_weights(p, W.data() + p * nc);
    benchmark::DoNotOptimize(W.data());
    benchmark::ClobberMemory();
  }
  finish(state, *c);
}

void bm_vtk_smp(benchmark::State& state, Case* c)
{
  if (!setup(state, *c))
    return;
  const Index np = c->num_points(), nc = c->num_controls();
  std::vector<double> W(static_cast<std::size_t>(np * nc), 0.0);
  const Case& cc = *c;
  for (auto _ : state)
  {
    vtkSMPTools::For(0, np, 64, [&](vtkIdType begin, vtkIdType end) {
      for (vtkIdType p = begin; p < end; ++p)
        cc.vtk_weights(p, W.data() + p * nc);
    });
    benchmark::DoNotOptimize(W.data());
    benchmark::ClobberMemory();
  }
  finish(state, *c);
}

/// @p fresh: each call allocates its result (W's #P x #C doubles first touched in the call);
/// otherwise the result's storage is allocated once, untimed, and reused, as the VTK cases above
/// reuse their W.
void bm_barylab(benchmark::State& state, Case* c, int threads, bool portable, bool fresh)
{
  if (!setup(state, *c))
    return;
  bary::MeanValueOptions options;
  options.threads = threads;
  const bary::MeanValueCoordinates mvc(c->cage, options); // validation: untimed (and it passed
                                                          // in setup(), so this does not throw)
  if (portable)
    bary::detail::set_simd_level(bary::detail::SimdLevel::Portable);
  bary::MeanValueResult result;
  if (!fresh)
    mvc.evaluate(c->P, result);
  for (auto _ : state)
  {
    if (fresh)
      result = mvc.evaluate(c->P);
    else
      mvc.evaluate(c->P, result);
    benchmark::DoNotOptimize(result.W.data());
    benchmark::ClobberMemory();
  }
  bary::detail::set_simd_level(bary::detail::supported_simd_level());
  finish(state, *c);
}

void bm_green(benchmark::State& state, Case* c, int threads)
{
  if (!setup(state, *c))
    return;
  bary::GreenOptions options;
  options.threads = threads;
  options.extend_outside = false;
  const bary::GreenCoordinates green(c->cage, options);
  for (auto _ : state)
  {
    bary::GreenResult result = green.evaluate(c->P);
    benchmark::DoNotOptimize(result.W.data());
    benchmark::DoNotOptimize(result.face_weights.data());
    benchmark::ClobberMemory();
  }
  finish(state, *c);
}

/// 2D: a regular polygon of @p n vertices on the unit circle and points in the disc of radius
/// 0.9 (inside: the polygon's inscribed radius cos(pi / n) >= 0.98 for n >= 16).
struct Case2D
{
  std::string name;
  bary::Cage cage;
  bary::Points P;
};

Case2D polygon_case(int n, Index num_points, std::uint64_t seed)
{
  Case2D c;
  c.name = "poly_" + std::to_string(n);
  c.cage.V.resize(n, 2);
  for (int i = 0; i < n; ++i)
  {
    const double a = 2.0 * 3.14159265358979323846 * i / n;
    c.cage.V.row(i) << std::cos(a), std::sin(a);
  }
  std::mt19937_64 gen(seed);
  c.P.resize(num_points, 2);
  for (Index p = 0; p < num_points; ++p)
  {
    double x, y;
    do
    {
      x = 1.8 * uniform01(gen) - 0.9;
      y = 1.8 * uniform01(gen) - 0.9;
    } while (x * x + y * y > 0.81);
    c.P.row(p) << x, y;
  }
  return c;
}

void bm_mvc_2d(benchmark::State& state, const Case2D* c)
{
  bary::MeanValueOptions options;
  options.threads = 1;
  const bary::MeanValueCoordinates mvc(c->cage, options);
  for (auto _ : state)
  {
    bary::MeanValueResult result = mvc.evaluate(c->P);
    benchmark::DoNotOptimize(result.W.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * c->P.rows());
  state.counters["cage_vertices"] = static_cast<double>(c->cage.V.rows());
}

void bm_green_2d(benchmark::State& state, const Case2D* c)
{
  bary::GreenOptions options;
  options.threads = 1;
  options.extend_outside = false;
  const bary::GreenCoordinates green(c->cage, options);
  for (auto _ : state)
  {
    bary::GreenResult result = green.evaluate(c->P);
    benchmark::DoNotOptimize(result.W.data());
    benchmark::DoNotOptimize(result.face_weights.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * c->P.rows());
  state.counters["cage_vertices"] = static_cast<double>(c->cage.V.rows());
}

std::string load_average()
{
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return in ? a + " " + b + " " + c : "unknown";
}

} // namespace

int main(int argc, char** argv)
{
  Index num_points = kDefaultNumPoints;
  if (const char* env = std::getenv("BARYLAB_BENCH_POINTS"))
    num_points = std::max<Index>(1, std::atol(env));

  // Cases live for the whole program; the benchmarks keep pointers to them.
  static std::vector<std::unique_ptr<Case>> cases;
  cases.push_back(std::make_unique<Case>(
    "cube_12f", cube(), interior_points(num_points, 0.9, false, kSeed)));
  cases.push_back(std::make_unique<Case>(
    "ico_320f", icosphere(2), interior_points(num_points, 0.9, true, kSeed + 1)));
  cases.push_back(std::make_unique<Case>(
    "ico_1280f", icosphere(3), interior_points(num_points, 0.9, true, kSeed + 2)));

  vtkSMPTools::Initialize(2);

  for (const auto& up : cases)
  {
    Case* c = up.get();
    const std::string prefix = "mvc3d/" + c->name + "/";
    // Real (wall-clock) time: the multi-threaded variants would otherwise be timed by the CPU
    // time of the main thread only. items_per_second is then points per wall-clock second.
    for (benchmark::internal::Benchmark* b : {
           benchmark::RegisterBenchmark((prefix + "vtk_1t").c_str(), bm_vtk_serial, c),
           benchmark::RegisterBenchmark((prefix + "vtk_smp_2t").c_str(), bm_vtk_smp, c),
           benchmark::RegisterBenchmark((prefix + "vtk_omp_2t").c_str(), bm_vtk_omp, c, 2),
           benchmark::RegisterBenchmark((prefix + "barylab_1t").c_str(), bm_barylab, c, 1, false, false),
           benchmark::RegisterBenchmark((prefix + "barylab_2t").c_str(), bm_barylab, c, 2, false, false),
           benchmark::RegisterBenchmark(
             (prefix + "barylab_1t_fresh").c_str(), bm_barylab, c, 1, false, true),
           benchmark::RegisterBenchmark(
             (prefix + "barylab_1t_portable").c_str(), bm_barylab, c, 1, true, false),
           benchmark::RegisterBenchmark(("green3d/" + c->name + "/barylab_1t").c_str(), bm_green, c, 1) })
      b->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        // besides mean/median/stddev/cv: the fastest and slowest repetition (this machine is
        // shared; the minimum time is the least disturbed one). Applied to counters as well,
        // so items_per_second of the "min" aggregate is the *lowest* rate.
        ->ComputeStatistics("min",
          [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); })
        ->ComputeStatistics("max",
          [](const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); });
  }

  static std::vector<Case2D> cases2d;
  for (const int n : { 16, 64, 256 })
    cases2d.push_back(polygon_case(n, num_points, kSeed + 10 + n));
  for (const Case2D& c : cases2d)
    for (benchmark::internal::Benchmark* b : {
           benchmark::RegisterBenchmark(("mvc2d/" + c.name + "/barylab_1t").c_str(), bm_mvc_2d, &c),
           benchmark::RegisterBenchmark(("green2d/" + c.name + "/barylab_1t").c_str(), bm_green_2d, &c) })
      b->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->ComputeStatistics("min",
          [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); });

  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  benchmark::AddCustomContext("load_average_at_start", load_average());
  benchmark::AddCustomContext("vtk_version", vtkVersion::GetVTKVersion());
  benchmark::AddCustomContext("barylab_simd",
    bary::detail::simd_level() == bary::detail::SimdLevel::AVX2 ? "avx2+fma" : "portable");
  benchmark::AddCustomContext("vtk_smp_backend", vtkSMPTools::GetBackend());
  benchmark::AddCustomContext(
    "vtk_smp_threads", std::to_string(vtkSMPTools::GetEstimatedNumberOfThreads()));
  benchmark::AddCustomContext("omp_max_threads", std::to_string(omp_get_max_threads()));
  benchmark::AddCustomContext("points_per_cage", std::to_string(num_points));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::fprintf(stderr, "[load] load average at end: %s\n", load_average().c_str());
  return 0;
}
