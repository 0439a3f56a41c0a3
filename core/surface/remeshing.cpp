#include "core/surface/remeshing.h"

#include "core/common/error.h"

#include <algorithm>
#include <map>
#include <string>
#include <utility>

namespace bary
{
namespace
{

using Edge = std::pair<int, int>;

Edge edge(int a, int b)
{
  return { std::min(a, b), std::max(a, b) };
}

/// Forward problems for the rows of W (#rows by #points, each row's anchors the current
/// points): rows whose anchors include an invalid point are invalid without being solved.
std::vector<std::pair<SurfacePoint, char>> solve_rows(const WeightedAverages& wa,
  const std::vector<SurfacePoint>& points, const std::vector<char>& valid,
  const std::vector<std::vector<std::pair<int, double>>>& rows,
  const std::vector<SurfacePoint>* hints, int threads)
{
  // Anchors: the valid points, renumbered.
  std::vector<int> index(points.size(), -1);
  std::vector<SurfacePoint> anchors;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (valid[i])
    {
      index[i] = static_cast<int>(anchors.size());
      anchors.push_back(points[i]);
    }
  std::vector<std::size_t> solved;
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<SurfacePoint> row_hints;
  for (std::size_t r = 0; r < rows.size(); ++r)
  {
    bool ok = !rows[r].empty();
    for (const auto& [i, w] : rows[r])
      ok = ok && index[static_cast<std::size_t>(i)] >= 0;
    if (!ok)
      continue;
    for (const auto& [i, w] : rows[r])
      entries.emplace_back(static_cast<int>(solved.size()), index[static_cast<std::size_t>(i)], w);
    if (hints)
      row_hints.push_back((*hints)[r]);
    solved.push_back(r);
  }
  std::vector<std::pair<SurfacePoint, char>> out(rows.size(), { SurfacePoint{}, 0 });
  if (solved.empty() || anchors.empty())
    return out;
  SparseWeights W(static_cast<Index>(solved.size()), static_cast<Index>(anchors.size()));
  W.setFromTriplets(entries.begin(), entries.end());
  ForwardOptions options;
  options.threads = threads;
  const ForwardResult f = wa.forward(anchors, W, options, {}, hints ? &row_hints : nullptr);
  for (std::size_t k = 0; k < solved.size(); ++k)
    out[solved[k]] = { f.points[k], f.valid[k] };
  return out;
}

} // namespace

void validate_remesh_options(const RemeshOptions& options)
{
  if (options.levels < 0 || options.levels > kMaxRemeshLevels)
    throw Error(ErrorCode::InvalidArgument, "the subdivision levels must be in [0, " +
        std::to_string(kMaxRemeshLevels) + "], got " + std::to_string(options.levels));
  if (options.smoothing_steps < 0 || options.smoothing_steps > 1000)
    throw Error(ErrorCode::InvalidArgument, "the smoothing steps must be in [0, 1000], got " +
        std::to_string(options.smoothing_steps));
  if (options.threads < 0 || options.threads > 1024)
    throw Error(ErrorCode::InvalidArgument,
      "the thread count must be in [0, 1024], got " + std::to_string(options.threads));
}

QuadRemesh semiregular_remesh(const WeightedAverages& wa, const std::vector<SurfacePoint>& coarse,
  const Eigen::MatrixXi& quads, const RemeshOptions& options, const ProgressCallback& progress)
{
  if (quads.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the coarse quad mesh has no quads");
  if (quads.cols() != 4)
    throw Error(ErrorCode::SizeMismatch,
      "a quad mesh needs 4 indices per quad, got " + std::to_string(quads.cols()));
  validate_remesh_options(options);
  validate_surface_points(wa.mesh(), coarse, "coarse vertex");
  const int nc = static_cast<int>(coarse.size());
  std::map<Edge, int> uses;
  for (Index q = 0; q < quads.rows(); ++q)
    for (int k = 0; k < 4; ++k)
    {
      const int a = quads(q, k), b = quads(q, (k + 1) % 4);
      if (a < 0 || a >= nc)
        throw Error(ErrorCode::InvalidArgument, "quad " + std::to_string(q) + " refers to vertex " +
            std::to_string(a) + " but there are " + std::to_string(nc) + " coarse vertices");
      if (a == b)
        throw Error(ErrorCode::InvalidArgument, "quad " + std::to_string(q) + " repeats vertex " +
            std::to_string(a));
      if (++uses[edge(a, b)] > 2)
        throw Error(ErrorCode::InvalidArgument, "edge (" + std::to_string(std::min(a, b)) + ", " +
            std::to_string(std::max(a, b)) + ") is in more than two quads");
    }

  QuadRemesh m;
  m.points = coarse;
  m.valid.assign(coarse.size(), 1);
  m.quads = quads;
  const int phases = options.levels + options.smoothing_steps;
  int phase = 0;
  auto report = [&] {
    ++phase;
    if (progress && !progress(static_cast<double>(phase) / std::max(1, phases)))
      throw Error(ErrorCode::Cancelled, "the remeshing was cancelled");
  };
  for (int level = 0; level < options.levels; ++level)
  {
    const int n = static_cast<int>(m.points.size());
    std::map<Edge, int> mid;
    std::vector<std::vector<std::pair<int, double>>> rows;
    auto midpoint = [&](int a, int b) {
      const auto [it, added] = mid.emplace(edge(a, b), n + static_cast<int>(rows.size()));
      if (added)
        rows.push_back({ { a, 0.5 }, { b, 0.5 } });
      return it->second;
    };
    Eigen::MatrixXi next(4 * m.quads.rows(), 4);
    for (Index q = 0; q < m.quads.rows(); ++q)
    {
      const int a = m.quads(q, 0), b = m.quads(q, 1), c = m.quads(q, 2), d = m.quads(q, 3);
      const int ab = midpoint(a, b), bc = midpoint(b, c), cd = midpoint(c, d), da = midpoint(d, a);
      const int centre = n + static_cast<int>(rows.size());
      rows.push_back({ { a, 0.25 }, { b, 0.25 }, { c, 0.25 }, { d, 0.25 } });
      next.row(4 * q) << a, ab, centre, da;
      next.row(4 * q + 1) << ab, b, bc, centre;
      next.row(4 * q + 2) << centre, bc, c, cd;
      next.row(4 * q + 3) << da, centre, cd, d;
    }
    const auto solved = solve_rows(wa, m.points, m.valid, rows, nullptr, options.threads);
    for (const auto& [p, ok] : solved)
    {
      m.points.push_back(p);
      m.valid.push_back(ok);
    }
    m.quads = next;
    report();
  }

  // Laplacian smoothing on the surface: interior vertices to their neighbours' average.
  const int n = static_cast<int>(m.points.size());
  std::map<Edge, int> edge_uses;
  for (Index q = 0; q < m.quads.rows(); ++q)
    for (int k = 0; k < 4; ++k)
      ++edge_uses[edge(m.quads(q, k), m.quads(q, (k + 1) % 4))];
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(n));
  std::vector<char> on_boundary(static_cast<std::size_t>(n), 0);
  for (const auto& [e, count] : edge_uses)
  {
    neighbours[static_cast<std::size_t>(e.first)].push_back(e.second);
    neighbours[static_cast<std::size_t>(e.second)].push_back(e.first);
    if (count == 1)
      on_boundary[static_cast<std::size_t>(e.first)] = on_boundary[static_cast<std::size_t>(e.second)] = 1;
  }
  for (int step = 0; step < options.smoothing_steps; ++step)
  {
    std::vector<std::vector<std::pair<int, double>>> rows(static_cast<std::size_t>(n));
    for (int v = 0; v < n; ++v)
    {
      const auto& nb = neighbours[static_cast<std::size_t>(v)];
      if (on_boundary[static_cast<std::size_t>(v)] || !m.valid[static_cast<std::size_t>(v)] || nb.empty())
        continue;
      for (const int u : nb)
        rows[static_cast<std::size_t>(v)].emplace_back(u, 1.0 / static_cast<double>(nb.size()));
    }
    const auto solved = solve_rows(wa, m.points, m.valid, rows, &m.points, options.threads);
    for (int v = 0; v < n; ++v)
      if (!rows[static_cast<std::size_t>(v)].empty())
      {
        // A vertex whose neighbours include an invalid one, or whose forward problem failed,
        // keeps its place (it is not made invalid by smoothing).
        if (solved[static_cast<std::size_t>(v)].second)
          m.points[static_cast<std::size_t>(v)] = solved[static_cast<std::size_t>(v)].first;
      }
    report();
  }
  for (const char ok : m.valid)
    m.failures += ok ? 0 : 1;
  return m;
}

} // namespace bary
