#include "core/surface/weighted_averages.h"

#include "core/common/error.h"
#include "core/detail/format.h"
#include "core/detail/parallel_for.h"
#include "core/detail/phong_kernel.h"
#include "core/detail/simd.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace bary
{

namespace detail
{

/// What the forward problem's search reads, laid out for its kernels:
/// - per vertex v, the embedded coordinates of its one-ring in single precision, in blocks of
///   kLanes vertices (structure of arrays, entry [(block D + d) kLanes + lane]; the last block
///   padded with kPad, whose squared distance overflows to +inf): one step of the greedy walk
///   measures a ring of up to eight vertices in one pass over D;
/// - v's tangent frame in single precision and, per triangle of v's fan (SurfaceMesh::
///   vertex_faces order), the inverse of the 2 by 2 matrix of its edges from v seen in that
///   frame: with the frame's two dot products with ybar - v they give the barycentric
///   coordinates, in the triangle seen in v's tangent plane, of the foot of ybar on that plane
///   (where a Phong projection at v would be, Property 3): the triangles are tried in order of
///   how far inside that point falls (as kLanes-wide blocks where the fan has at most kLanes
///   triangles, the usual case);
/// - a grid that proposes a start vertex near any point (grid_vertex).
/// Single precision only chooses where the search starts (the walk's end and the first
/// triangle); every Phong projection is computed in double precision.
struct SurfaceSearch
{
  static constexpr int kLanes = 8;
  static constexpr float kPad = 1e30f;
  struct Fan
  {
    int face = 0;                 ///< the triangle
    int corners[3] = { 0, 0, 0 }; ///< F(face, 0..2)
    /// The inverse of [T (u - v), T (w - v)] (T: v's frame; u, w: the triangle's corners after v)
    float t00 = 0, t01 = 0, t10 = 0, t11 = 0;
  };
  /// A fan of at most kLanes triangles: the Fans' members as lanes (0 in the padding).
  struct FanBlock
  {
    float t00[kLanes], t01[kLanes], t10[kLanes], t11[kLanes];
    float pad[kLanes];       ///< 0 per triangle, +inf in the padding
    int face[kLanes];
    int corners[3][kLanes];
  };
  std::vector<float> frames;           ///< #V by 2 D, single precision (t1, then t2)
  std::vector<int> block_offsets;      ///< #V + 1: first block of each ring
  std::vector<float, AlignedAllocator<float>> blocks;
  std::vector<float> E;                ///< #V by D, row-major, single precision
  /// The mesh's vertices, row-major, four doubles each (the fourth 0): a result's position
  /// from three lines instead of nine.
  std::vector<double, AlignedAllocator<double>> V;
  std::vector<Fan> fans;               ///< indexed like SurfaceMesh::vertex_faces
  std::vector<int> fan_block;          ///< per vertex: its FanBlock, or -1
  std::vector<FanBlock, AlignedAllocator<FanBlock>> fan_blocks;
  int max_valence = 0;
  /// A start for the walk near any point: a grid over the three coordinates of the embedding
  /// with the largest extent (cells of about one mean embedded edge length, at most 2^20 cells),
  /// each cell holding the vertex whose coordinates there are nearest to the cell's centre, or,
  /// within two cells of such a cell, the nearest of its neighbours' vertices (ybar is off the
  /// surface); -1: none.
  int axes[3] = { 0, 1, 0 };
  int cells[3] = { 1, 1, 1 };
  float origin[3] = { 0, 0, 0 }, inverse_size[3] = { 0, 0, 0 };
  float extent[3] = { 1, 1, 1 }; ///< cells[a] as float
  float grid_accept = 0; ///< (2 cells)^2: a grid vertex this near to ybar is start enough
  std::vector<int> grid;

  /// The grid's vertex for the point y (single precision, D numbers), or -1.
  int grid_vertex(const float* y) const
  {
    const float x0 = (y[axes[0]] - origin[0]) * inverse_size[0];
    const float x1 = (y[axes[1]] - origin[1]) * inverse_size[1];
    const float x2 = (y[axes[2]] - origin[2]) * inverse_size[2];
    if (!(x0 >= 0.0f && x0 < extent[0] && x1 >= 0.0f && x1 < extent[1] && x2 >= 0.0f &&
          x2 < extent[2]))
      return -1;
    return grid[static_cast<std::size_t>(
      (static_cast<int>(x2) * cells[1] + static_cast<int>(x1)) * cells[0] + static_cast<int>(x0))];
  }

  SurfaceSearch(const SurfaceMesh& mesh, const Eigen::MatrixXd& Ed, const Eigen::MatrixXd& Fr)
  {
    frames.resize(static_cast<std::size_t>(Fr.size()));
    for (Index v = 0; v < Fr.rows(); ++v)
      for (Index k = 0; k < Fr.cols(); ++k)
        frames[static_cast<std::size_t>(v * Fr.cols() + k)] = static_cast<float>(Fr(v, k));
    const Index nv = mesh.vertex_count();
    const int D = static_cast<int>(Ed.cols());
    E.resize(static_cast<std::size_t>(nv * D));
    for (Index v = 0; v < nv; ++v)
      for (int d = 0; d < D; ++d)
        E[static_cast<std::size_t>(v * D + d)] = static_cast<float>(Ed(v, d));
    // Rings.
    block_offsets.assign(static_cast<std::size_t>(nv + 1), 0);
    for (Index v = 0; v < nv; ++v)
    {
      const int k = mesh.ring_offsets[static_cast<std::size_t>(v + 1)] -
        mesh.ring_offsets[static_cast<std::size_t>(v)];
      max_valence = std::max(max_valence, k);
      block_offsets[static_cast<std::size_t>(v + 1)] =
        block_offsets[static_cast<std::size_t>(v)] + (k + kLanes - 1) / kLanes;
    }
    blocks.assign(static_cast<std::size_t>(block_offsets.back()) * D * kLanes, kPad);
    for (Index v = 0; v < nv; ++v)
    {
      const int begin = mesh.ring_offsets[static_cast<std::size_t>(v)];
      const int k = mesh.ring_offsets[static_cast<std::size_t>(v + 1)] - begin;
      float* out = blocks.data() + static_cast<std::size_t>(block_offsets[static_cast<std::size_t>(v)]) * D * kLanes;
      for (int i = 0; i < k; ++i)
      {
        const int u = mesh.ring[static_cast<std::size_t>(begin + i)];
        for (int d = 0; d < D; ++d)
          out[((i / kLanes) * D + d) * kLanes + i % kLanes] = E[static_cast<std::size_t>(u * D + d)];
      }
    }
    V.assign(static_cast<std::size_t>(4 * nv), 0.0);
    for (Index v = 0; v < nv; ++v)
      for (int k = 0; k < 3; ++k)
        V[static_cast<std::size_t>(4 * v + k)] = mesh.V(v, k);
    build_grid(mesh, Ed);
    // Fans.
    fans.resize(mesh.vertex_faces.size());
    fan_block.assign(static_cast<std::size_t>(nv), -1);
    for (Index v = 0; v < nv; ++v)
    {
      const int t0 = mesh.face_offsets[static_cast<std::size_t>(v)];
      const int t1 = mesh.face_offsets[static_cast<std::size_t>(v + 1)];
      for (int t = t0; t < t1; ++t)
      {
        Fan& fan = fans[static_cast<std::size_t>(t)];
        fan.face = mesh.vertex_faces[static_cast<std::size_t>(t)];
        for (int k = 0; k < 3; ++k)
          fan.corners[k] = mesh.F(fan.face, k);
        const int k = fan.corners[0] == v ? 0 : fan.corners[1] == v ? 1 : 2;
        const int u = fan.corners[(k + 1) % 3], w = fan.corners[(k + 2) % 3];
        Eigen::Matrix2d T;
        for (int r = 0; r < 2; ++r)
        {
          const Eigen::RowVectorXd tr = Fr.row(v).segment(r * D, D);
          T(r, 0) = tr.dot(Ed.row(u) - Ed.row(v));
          T(r, 1) = tr.dot(Ed.row(w) - Ed.row(v));
        }
        // A triangle seen edge-on from v's plane (not in a valid embedding) scores 0.
        const double det = T.determinant();
        if (std::abs(det) > 1e-12 * T.cwiseAbs().maxCoeff() * T.cwiseAbs().maxCoeff())
        {
          const Eigen::Matrix2d Ti = T.inverse();
          fan.t00 = static_cast<float>(Ti(0, 0));
          fan.t01 = static_cast<float>(Ti(0, 1));
          fan.t10 = static_cast<float>(Ti(1, 0));
          fan.t11 = static_cast<float>(Ti(1, 1));
        }
      }
      if (t1 - t0 <= kLanes)
      {
        FanBlock b{};
        for (int l = 0; l < kLanes; ++l)
          b.pad[l] = std::numeric_limits<float>::infinity();
        for (int t = t0; t < t1; ++t)
        {
          const Fan& fan = fans[static_cast<std::size_t>(t)];
          const int l = t - t0;
          b.t00[l] = fan.t00;
          b.t01[l] = fan.t01;
          b.t10[l] = fan.t10;
          b.t11[l] = fan.t11;
          b.pad[l] = 0;
          b.face[l] = fan.face;
          for (int k = 0; k < 3; ++k)
            b.corners[k][l] = fan.corners[k];
        }
        fan_block[static_cast<std::size_t>(v)] = static_cast<int>(fan_blocks.size());
        fan_blocks.push_back(b);
      }
    }
  }

  void build_grid(const SurfaceMesh& mesh, const Eigen::MatrixXd& Ed)
  {
    const int D = static_cast<int>(Ed.cols());
    const Eigen::RowVectorXd low = Ed.colwise().minCoeff(), high = Ed.colwise().maxCoeff();
    std::vector<int> order(static_cast<std::size_t>(D));
    for (int d = 0; d < D; ++d)
      order[static_cast<std::size_t>(d)] = d;
    std::stable_sort(order.begin(), order.end(),
      [&](int a, int b) { return high(a) - low(a) > high(b) - low(b); });
    double edge = 0;
    for (Index v = 0; v < mesh.vertex_count(); ++v)
      for (int i = mesh.ring_offsets[static_cast<std::size_t>(v)];
           i < mesh.ring_offsets[static_cast<std::size_t>(v + 1)]; ++i)
        edge += (Ed.row(v) - Ed.row(mesh.ring[static_cast<std::size_t>(i)])).norm();
    edge /= static_cast<double>(mesh.ring.size());
    double size = edge;
    const int dims = std::min(D, 3);
    for (;;)
    {
      double total = 1;
      for (int a = 0; a < dims; ++a)
        total *= std::min(256.0, std::ceil((high(order[static_cast<std::size_t>(a)]) - low(order[static_cast<std::size_t>(a)])) / size) + 1);
      if (total <= 1 << 20)
        break;
      size *= 1.25;
    }
    for (int a = 0; a < 3; ++a)
    {
      if (a < dims)
      {
        const int d = order[static_cast<std::size_t>(a)];
        axes[a] = d;
        cells[a] = static_cast<int>(std::min(256.0, std::ceil((high(d) - low(d)) / size) + 1));
        origin[a] = static_cast<float>(low(d) - 0.5 * size);
        inverse_size[a] = static_cast<float>(1.0 / size);
      }
      else
      {
        // D = 2: one cell along the third axis (x = 0 for every finite coordinate).
        axes[a] = 0;
        cells[a] = 1;
        origin[a] = 0;
        inverse_size[a] = 0;
      }
    }
    grid_accept = static_cast<float>(4 * size * size);
    for (int a = 0; a < 3; ++a)
      extent[a] = static_cast<float>(cells[a]);
    grid.assign(static_cast<std::size_t>(cells[0]) * cells[1] * cells[2], -1);
    std::vector<float> nearest(grid.size(), std::numeric_limits<float>::infinity());
    for (Index v = 0; v < mesh.vertex_count(); ++v)
    {
      const float* e = E.data() + v * D;
      int index = 0;
      float d2 = 0;
      bool inside = true;
      for (int a = 2; a >= 0; --a)
      {
        const float x = (e[axes[a]] - origin[a]) * inverse_size[a];
        if (!(x >= 0.0f && x < static_cast<float>(cells[a])))
          inside = false;
        const int c = std::max(0, std::min(cells[a] - 1, static_cast<int>(x)));
        index = index * cells[a] + c;
        const float off = x - (static_cast<float>(c) + 0.5f);
        d2 += off * off;
      }
      if (inside && d2 < nearest[static_cast<std::size_t>(index)])
      {
        nearest[static_cast<std::size_t>(index)] = d2;
        grid[static_cast<std::size_t>(index)] = static_cast<int>(v);
      }
    }
    // Empty cells next to the surface (ybar is off the surface) take the vertex of a
    // neighbouring cell nearest to their centre; twice.
    for (int pass = 0; pass < 2; ++pass)
    {
      std::vector<int> filled = grid;
      for (int z = 0; z < cells[2]; ++z)
        for (int y = 0; y < cells[1]; ++y)
          for (int x = 0; x < cells[0]; ++x)
          {
            const std::size_t at = (static_cast<std::size_t>(z) * cells[1] + y) * cells[0] + x;
            if (grid[at] >= 0)
              continue;
            float closest = std::numeric_limits<float>::infinity();
            for (int dz = -1; dz <= 1; ++dz)
              for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                {
                  const int X = x + dx, Y = y + dy, Z = z + dz;
                  if (X < 0 || Y < 0 || Z < 0 || X >= cells[0] || Y >= cells[1] || Z >= cells[2])
                    continue;
                  const int u = grid[(static_cast<std::size_t>(Z) * cells[1] + Y) * cells[0] + X];
                  if (u < 0)
                    continue;
                  const float* e = E.data() + static_cast<Index>(u) * D;
                  const float centre[3] = { static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f,
                    static_cast<float>(z) + 0.5f };
                  float d2 = 0;
                  for (int a = 0; a < 3; ++a)
                  {
                    const float off = (e[axes[a]] - origin[a]) * inverse_size[a] - centre[a];
                    d2 += a < dims ? off * off : 0.0f;
                  }
                  if (d2 < closest)
                  {
                    closest = d2;
                    filled[at] = u;
                  }
                }
          }
      grid.swap(filled);
    }
  }
};

} // namespace detail

namespace
{

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using detail::SurfaceSearch;

constexpr Index kChunk = 256; // queries per chunk: the unit of warm starts and of parallelism

double squared_distance(const double* a, const double* b, int D)
{
  double s = 0;
  for (int d = 0; d < D; ++d)
  {
    const double t = a[d] - b[d];
    s += t * t;
  }
  return s;
}

/// Per-thread scratch of the forward problem, sized once per call (no allocation per query).
struct ForwardWorkspace
{
  std::vector<int> stamp;  ///< per triangle: the query that last visited it
  std::vector<int> queue;  ///< breadth-first queue of triangles
  std::vector<std::pair<float, int>> order; ///< the walk's last vertex's triangles, ordered
  std::vector<float> scores; ///< per lane: the scores of the walk's last vertex's triangles
  int scores_stride = 0;
  std::vector<float> dist;   ///< a walk step's squared distances (a ring)
  std::vector<float> anchor_distance; ///< per anchor: squared distance to ybar
  std::vector<int> row_index;          ///< the row's anchors (sparse weights)
  std::vector<double> row_weight;      ///< the row's weights
  std::vector<double> ybar;            ///< per lane: D numbers
  std::vector<double> point;           ///< D numbers
  std::vector<float> ybar_float;       ///< per lane: D numbers
  int query = 0;
  Index tried = 0;         ///< Phong projections attempted
  Index failures = 0;      ///< queries without a projection
  Index bad_row = std::numeric_limits<Index>::max(); ///< the first row not an average's
  double bad_sum = 0;      ///< its sum (NaN: a weight is not finite)
  struct Retry;            ///< a second try waiting (flush_retries)
  std::vector<Retry> retry; ///< four
  int retries = 0;
  std::vector<double> retry_y;     ///< per retry: ybar (D numbers)
  std::vector<float> retry_scores; ///< per retry: the scores of its first vertex's triangles
};

/// What a forward query reads (shared by the threads).
struct ForwardContext
{
  int D = 0;
  Index anchors = 0, anchors_padded = 0; ///< #anchors, and rounded up to a multiple of 8
  const double* Y = nullptr;  ///< #anchors by D, row-major
  const float* Yt = nullptr;  ///< D by anchors_padded, row-major, single precision (SoA)
  const float* Y_float = nullptr; ///< #anchors by D, row-major, single precision
  const Index* anchor_corners = nullptr;
  const SurfaceMesh* mesh = nullptr;
  const SurfaceSearch* search = nullptr;
  const double* E = nullptr;  ///< #V by D, row-major
  const double* frames = nullptr; ///< PhongProjection's frames (#V by 2 D) and per-triangle data
  const double* data = nullptr;
  Index cap = 0;              ///< triangles tried per query at most
};

/// y = sum_j weight_j Y_{index_j} (index null: j), D numbers; the rows in two interleaved
/// partial sums (even and odd j) added at the end.
template<int kD>
BARY_ALWAYS_INLINE void weighted_sum(const double* Y, int D, const int* index,
  const double* weight, int count, double* y)
{
  using detail::v4d;
  const int n = kD > 0 ? kD : D;
  if (kD == 8)
  {
    // both halves of a row at once (the same sums as below)
    const v4d zero = { 0.0, 0.0, 0.0, 0.0 };
    v4d even0 = zero, even1 = zero, odd0 = zero, odd1 = zero;
    int j = 0;
    if (!index)
    {
      // four rows a turn (the same two chains, in the same order)
      for (; j + 4 <= count; j += 4)
      {
        const double* r0 = Y + j * 8;
        even0 += BARY_LOAD4(r0) * weight[j];
        even1 += BARY_LOAD4(r0 + 4) * weight[j];
        odd0 += BARY_LOAD4(r0 + 8) * weight[j + 1];
        odd1 += BARY_LOAD4(r0 + 12) * weight[j + 1];
        even0 += BARY_LOAD4(r0 + 16) * weight[j + 2];
        even1 += BARY_LOAD4(r0 + 20) * weight[j + 2];
        odd0 += BARY_LOAD4(r0 + 24) * weight[j + 3];
        odd1 += BARY_LOAD4(r0 + 28) * weight[j + 3];
      }
      for (; j + 2 <= count; j += 2)
      {
        const double* r0 = Y + j * 8;
        even0 += BARY_LOAD4(r0) * weight[j];
        even1 += BARY_LOAD4(r0 + 4) * weight[j];
        odd0 += BARY_LOAD4(r0 + 8) * weight[j + 1];
        odd1 += BARY_LOAD4(r0 + 12) * weight[j + 1];
      }
    }
    else
      for (; j + 2 <= count; j += 2)
      {
        const double* r0 = Y + index[j] * 8;
        const double* r1 = Y + index[j + 1] * 8;
        even0 += BARY_LOAD4(r0) * weight[j];
        even1 += BARY_LOAD4(r0 + 4) * weight[j];
        odd0 += BARY_LOAD4(r1) * weight[j + 1];
        odd1 += BARY_LOAD4(r1 + 4) * weight[j + 1];
      }
    if (j < count)
    {
      const double* r0 = Y + (index ? index[j] : j) * 8;
      even0 += BARY_LOAD4(r0) * weight[j];
      even1 += BARY_LOAD4(r0 + 4) * weight[j];
    }
    BARY_STORE4(y, even0 + odd0);
    BARY_STORE4(y + 4, even1 + odd1);
    return;
  }
  int d = 0;
  for (; d + 4 <= n; d += 4)
  {
    v4d even = { 0.0, 0.0, 0.0, 0.0 }, odd = even;
    int j = 0;
    for (; j + 2 <= count; j += 2)
    {
      even += BARY_LOAD4(Y + (index ? index[j] : j) * n + d) * weight[j];
      odd += BARY_LOAD4(Y + (index ? index[j + 1] : j + 1) * n + d) * weight[j + 1];
    }
    if (j < count)
      even += BARY_LOAD4(Y + (index ? index[j] : j) * n + d) * weight[j];
    BARY_STORE4(y + d, even + odd);
  }
  for (; d < n; ++d)
  {
    double even = 0.0, odd = 0.0;
    int j = 0;
    for (; j + 2 <= count; j += 2)
    {
      even += Y[(index ? index[j] : j) * n + d] * weight[j];
      odd += Y[(index ? index[j + 1] : j + 1) * n + d] * weight[j + 1];
    }
    if (j < count)
      even += Y[(index ? index[j] : j) * n + d] * weight[j];
    y[d] = even + odd;
  }
}

/// Squared distances (single precision) from y to the eight points of a structure-of-arrays
/// block (entry [d * stride + lane]). D = 8: summed as a balanced tree over d; otherwise in
/// order. point_distance computes the same for one point.
template<int kD>
BARY_ALWAYS_INLINE void block_distances(const float* block, Index stride, int D,
  const float* y, float* out)
{
  using detail::v8f;
  if (kD == 8)
  {
    v8f t[8];
    for (int d = 0; d < 8; ++d)
    {
      // y - block: the block is the subtraction's memory operand (the same square)
      t[d] = y[d] - BARY_LOAD8F(block + d * stride);
      t[d] *= t[d];
    }
    BARY_STORE8F(out, ((t[0] + t[1]) + (t[2] + t[3])) + ((t[4] + t[5]) + (t[6] + t[7])));
    return;
  }
  v8f t = BARY_LOAD8F(block) - y[0];
  v8f acc = t * t;
  for (int d = 1; d < D; ++d)
  {
    t = BARY_LOAD8F(block + d * stride) - y[d];
    acc += t * t;
  }
  BARY_STORE8F(out, acc);
}

template<int kD>
BARY_ALWAYS_INLINE float point_distance(const float* e, const float* y, int D)
{
  if (kD == 8)
  {
#if defined(__GNUC__) && !defined(__clang__)
    // the same tree in one vector: adjacent lanes, then pairs, then the halves
    using detail::v8f;
    using detail::v8i;
    v8f t = BARY_LOAD8F(e) - BARY_LOAD8F(y);
    t *= t;
    t += __builtin_shuffle(t, v8i{ 1, 0, 3, 2, 5, 4, 7, 6 });
    t += __builtin_shuffle(t, v8i{ 2, 3, 0, 1, 6, 7, 4, 5 });
    return t[0] + t[4];
#else
    float t[8];
    for (int d = 0; d < 8; ++d)
    {
      t[d] = e[d] - y[d];
      t[d] *= t[d];
    }
    return ((t[0] + t[1]) + (t[2] + t[3])) + ((t[4] + t[5]) + (t[6] + t[7]));
#endif
  }
  float t = e[0] - y[0];
  float acc = t * t;
  for (int d = 1; d < D; ++d)
  {
    t = e[d] - y[d];
    acc += t * t;
  }
  return acc;
}

/// Phong projection of y onto triangle f (Newton from the Euclidean projection).
template<int kD>
BARY_ALWAYS_INLINE bool project_face(const ForwardContext& c, int D, int f, const double* y, double* xi)
{
  const Eigen::MatrixXi& F = c.mesh->F;
  const int c0 = F(f, 0), c1 = F(f, 1), c2 = F(f, 2);
  return detail::phong_project<kD>(c.data + static_cast<std::size_t>(f) * detail::kPhongData,
    c.frames + c0 * 2 * D, c.frames + c1 * 2 * D, c.frames + c2 * 2 * D, c.E + c0 * D,
    c.E + c1 * D, c.E + c2 * D, D, y, true, 0.0, 0.0, xi);
}

/// A row of weights is an average's when every weight is finite and they sum to 1 within 1e-9
/// of the sum of their magnitudes (four partial sums, added pairwise). @p sum: the row's sum, or
/// NaN when a weight is not finite.
BARY_ALWAYS_INLINE bool weights_row_valid(const double* w, int count, double& sum)
{
  using detail::v4d;
  const v4d zero = { 0.0, 0.0, 0.0, 0.0 };
  v4d s = zero, a = zero;
  int i = 0;
  for (; i + 4 <= count; i += 4)
  {
    const v4d x = BARY_LOAD4(w + i);
    s += x;
#if defined(__GNUC__)
    typedef long long v4l __attribute__((vector_size(32)));
    const v4l magnitude_bits = { ~(1LL << 63), ~(1LL << 63), ~(1LL << 63), ~(1LL << 63) };
    a += reinterpret_cast<v4d>(reinterpret_cast<v4l>(x) & magnitude_bits);
#else
    a += BARY_SELECT(x < zero, zero - x, x);
#endif
  }
  double tail = 0, tail_magnitude = 0;
  for (; i < count; ++i)
  {
    tail += w[i];
    tail_magnitude += std::abs(w[i]);
  }
#if defined(__GNUC__) && !defined(__clang__)
  // both sums in one vector: lanes (0 + 1, 2 + 3) of s and a side by side, then the halves
  typedef long long v4i __attribute__((vector_size(32)));
  v4d u = __builtin_shuffle(s, a, v4i{ 0, 4, 2, 6 }) + __builtin_shuffle(s, a, v4i{ 1, 5, 3, 7 });
  u += __builtin_shuffle(u, v4i{ 2, 3, 0, 1 });
  sum = u[0] + tail;
  const double magnitude = u[1] + tail_magnitude;
#else
  sum = ((s[0] + s[1]) + (s[2] + s[3])) + tail;
  const double magnitude = ((a[0] + a[1]) + (a[2] + a[3])) + tail_magnitude;
#endif
  if (!(magnitude <= std::numeric_limits<double>::max()))
  {
    // NaN or infinite: a weight is not finite, or finite ones overflow (then say what they sum to)
    bool finite = true;
    for (int k = 0; k < count; ++k)
      finite = finite && std::isfinite(w[k]);
    if (!finite)
      sum = std::numeric_limits<double>::quiet_NaN();
    return false;
  }
  return std::abs(sum - 1.0) <= 1e-9 * std::max(1.0, magnitude);
}

/// The lowest set bit's position of a nonzero lane mask.
inline int lowest_lane(unsigned mask)
{
#if defined(__GNUC__)
  return __builtin_ctz(mask);
#else
  int l = 0;
  while (!(mask & 1u))
  {
    mask >>= 1;
    ++l;
  }
  return l;
#endif
}

/// What a query returns besides its point.
enum class QueryOutcome
{
  Found,
  NotFound,
  BadWeights ///< the row is not an average's (weights_row_valid)
};

/// A forward query in flight (lane l of a group): its triangles to try and its Phong setup.
/// (No initialisers: four are made per group of queries; the stages fill what they use, and
/// only an active lane's are read.)
struct Pending
{
  int v;                    ///< the walk's vertex (at the end: its last)
  float best;               ///< its squared distance to ybar (single precision)
  int face;                 ///< the first triangle to try
  int corners[3];           ///< its corners
  int first;                ///< the first triangle to try: order[first]
  int fan_size;             ///< v's triangles, in the lane's order buffer
  double dots[8];           ///< phong_dots of the first triangle
  const double* data;
};

/// A second try waiting: query q, whose first triangle (p.face) had no projection, on the
/// triangle across the edge Newton left it by.
struct ForwardWorkspace::Retry
{
  Index q = 0;
  Pending p{};
  int across = -1;
  double dots[8];           ///< phong_dots of the across triangle
  const double* data = nullptr;
};

/// The start of a forward query (§3.3): the row checked, ybar, the start vertex (@p start, or
/// the grid's or the nearest anchor's) into p. @p index: the row's anchors (null: all, in
/// order).
template<int kD>
BARY_ALWAYS_INLINE QueryOutcome start_query(const ForwardContext& c, const int* index,
  const double* weight, int count, Index start, ForwardWorkspace& ws, int lane, Pending& p,
  double& row_sum)
{
  if (!weights_row_valid(weight, count, row_sum))
    return QueryOutcome::BadWeights;
  using detail::v8f;
  using detail::v8i;
  const int D = kD > 0 ? kD : c.D;
  constexpr int L = SurfaceSearch::kLanes;
  const v8i iota = { 0, 1, 2, 3, 4, 5, 6, 7 };
  double* y = ws.ybar.data() + lane * D;
  weighted_sum<kD>(c.Y, D, index, weight, count, y);
  float* yf = ws.ybar_float.data() + lane * D;
#if defined(__GNUC__) && !defined(__clang__)
  if (kD == 8)
  {
    typedef float v4f __attribute__((vector_size(16), aligned(4), may_alias));
    *reinterpret_cast<v4f*>(yf) = __builtin_convertvector(BARY_LOAD4(y), v4f);
    *reinterpret_cast<v4f*>(yf + 4) = __builtin_convertvector(BARY_LOAD4(y + 4), v4f);
  }
  else
#endif
    for (int d = 0; d < D; ++d)
      yf[d] = static_cast<float>(y[d]);
  const SurfaceSearch& search = *c.search;
  float best = std::numeric_limits<float>::infinity();
  if (start >= 0)
    best = point_distance<kD>(search.E.data() + start * D, yf, D);
  else
  {
    // The grid's vertex near ybar; unless it is within two cells of ybar, also the corner of
    // the anchor nearest to ybar in R^D (among the row's anchors for sparse weights; the paper
    // starts from the heaviest anchor "if a better initial guess is not available"): the nearer.
    const int g = search.grid_vertex(yf);
    if (g >= 0)
    {
      best = point_distance<kD>(search.E.data() + static_cast<Index>(g) * D, yf, D);
      start = g;
    }
    if (!(best <= search.grid_accept))
    {
      Index nearest = -1;
      if (!index)
      {
        float* dist = ws.anchor_distance.data();
        block_distances<kD>(c.Yt, c.anchors_padded, D, yf, dist);
        v8f dmin = BARY_LOAD8F(dist);
        v8i imin = iota;
        for (Index a = L; a < c.anchors; a += L)
        {
          block_distances<kD>(c.Yt + a, c.anchors_padded, D, yf, dist + a);
          const v8f da = BARY_LOAD8F(dist + a);
          const v8i closer = da < dmin;
          dmin = BARY_SELECT(closer, da, dmin);
          imin = BARY_SELECT(closer, iota + static_cast<int>(a), imin);
        }
        float value;
        int at;
        detail::lane_min(dmin, imin, value, at);
        nearest = at;
      }
      else
      {
        float closest = std::numeric_limits<float>::infinity();
        for (int j = 0; j < count; ++j)
        {
          const float dist = point_distance<kD>(c.Y_float + index[j] * D, yf, D);
          if (dist < closest)
          {
            closest = dist;
            nearest = index[j];
          }
        }
      }
      if (nearest >= 0)
      {
        const Index corner = c.anchor_corners[nearest];
        const float dc = point_distance<kD>(search.E.data() + corner * D, yf, D);
        if (dc < best)
        {
          best = dc;
          start = corner;
        }
      }
    }
    if (start < 0)
      return QueryOutcome::NotFound;
  }
  p.v = static_cast<int>(start);
  p.best = best;
  return QueryOutcome::Found;
}

/// One step of the greedy walk on the edge graph (single precision): to the ring vertex nearest
/// to ybar when it is nearer than the current vertex (true), else false (the walk's end). From
/// the first step on, the distances compared are the ring kernel's, which gives a vertex the
/// same value in every ring it belongs to: the walk strictly descends and ends, at a vertex
/// nearer than all its neighbours.
template<int kD>
BARY_ALWAYS_INLINE bool walk_step(const ForwardContext& c, ForwardWorkspace& ws, int lane, Pending& p)
{
  using detail::v8f;
  using detail::v8i;
  const int D = kD > 0 ? kD : c.D;
  constexpr int L = SurfaceSearch::kLanes;
  const v8i iota = { 0, 1, 2, 3, 4, 5, 6, 7 };
  const SurfaceSearch& search = *c.search;
  const SurfaceMesh& mesh = *c.mesh;
  const float* yf = ws.ybar_float.data() + lane * D;
  const int v = p.v;
  const int r0 = mesh.ring_offsets[static_cast<std::size_t>(v)];
  const int k = mesh.ring_offsets[static_cast<std::size_t>(v + 1)] - r0;
  const float* blk = search.blocks.data() +
    static_cast<std::size_t>(search.block_offsets[static_cast<std::size_t>(v)]) * D * L;
  float* dist = ws.dist.data();
  block_distances<kD>(blk, L, D, yf, dist);
  v8f dmin = BARY_LOAD8F(dist);
  v8i imin = iota;
  for (int base = L; base < k; base += L)
  {
    block_distances<kD>(blk + base * D, L, D, yf, dist + base);
    const v8f db = BARY_LOAD8F(dist + base);
    const v8i closer = db < dmin;
    dmin = BARY_SELECT(closer, db, dmin);
    imin = BARY_SELECT(closer, iota + base, imin);
  }
  float value;
  int at;
  detail::lane_min(dmin, imin, value, at);
  if (!(value < p.best))
    return false;
  p.best = value;
  p.v = mesh.ring[static_cast<std::size_t>(r0 + at)];
  return true;
}

/// After the walk: v's triangles scored, the first one to try. A triangle's score is minus the
/// smallest barycentric coordinate, in the triangle seen in v's tangent plane, of the foot of
/// ybar on that plane (SurfaceSearch): the smallest score (the point deepest inside) first.
template<int kD>
BARY_ALWAYS_INLINE void choose_triangle(const ForwardContext& c, ForwardWorkspace& ws, int lane, Pending& p)
{
  using detail::v8f;
  using detail::v8i;
  const int D = kD > 0 ? kD : c.D;
  const v8i iota = { 0, 1, 2, 3, 4, 5, 6, 7 };
  const SurfaceSearch& search = *c.search;
  const SurfaceMesh& mesh = *c.mesh;
  const int v = p.v;
  // The frame's dot products with ybar - v.
  float p0, p1;
  {
    const float* t = search.frames.data() + static_cast<Index>(v) * 2 * D;
    const float* e = search.E.data() + static_cast<Index>(v) * D;
    const float* y = ws.ybar_float.data() + lane * D;
    if (kD == 8)
    {
      const v8f w = BARY_LOAD8F(y) - BARY_LOAD8F(e);
      const v8f a = BARY_LOAD8F(t) * w, b = BARY_LOAD8F(t + 8) * w;
#if defined(__GNUC__) && !defined(__clang__)
      // lanes (l, l + 4) of a and b side by side, then pairs, then the last two
      v8f h = __builtin_shuffle(a, b, v8i{ 0, 1, 2, 3, 8, 9, 10, 11 }) +
        __builtin_shuffle(a, b, v8i{ 4, 5, 6, 7, 12, 13, 14, 15 });
      h = h + __builtin_shuffle(h, v8i{ 2, 3, 0, 1, 6, 7, 4, 5 });
      p0 = h[0] + h[1];
      p1 = h[4] + h[5];
#else
      p0 = ((a[0] + a[4]) + (a[2] + a[6])) + ((a[1] + a[5]) + (a[3] + a[7]));
      p1 = ((b[0] + b[4]) + (b[2] + b[6])) + ((b[1] + b[5]) + (b[3] + b[7]));
#endif
    }
    else
    {
      p0 = p1 = 0.0f;
      for (int d = 0; d < D; ++d)
      {
        const float w = y[d] - e[d];
        p0 += t[d] * w;
        p1 += t[D + d] * w;
      }
    }
  }
  const int f0 = mesh.face_offsets[static_cast<std::size_t>(v)];
  const int fan_size = mesh.face_offsets[static_cast<std::size_t>(v + 1)] - f0;
  float* scores = ws.scores.data() + lane * ws.scores_stride;
  int first;
  const int fb = search.fan_block[static_cast<std::size_t>(v)];
  if (fb >= 0)
  {
    const SurfaceSearch::FanBlock& b = search.fan_blocks[static_cast<std::size_t>(fb)];
    const v8f alpha = BARY_LOAD8F(b.t00) * p0 + BARY_LOAD8F(b.t01) * p1;
    const v8f beta = BARY_LOAD8F(b.t10) * p0 + BARY_LOAD8F(b.t11) * p1;
    const v8f one = { 1, 1, 1, 1, 1, 1, 1, 1 };
    const v8f gamma = (one - alpha) - beta;
    v8f low = BARY_SELECT(alpha < gamma, alpha, gamma);
    low = BARY_SELECT(beta < low, beta, low);
    const v8f score = BARY_LOAD8F(b.pad) - low; // the smallest wins; the padding is +inf
    BARY_STORE8F(scores, score);
    float value;
    int at;
    detail::lane_min(score, iota, value, at);
    first = at;
    for (int k = 0; k < 3; ++k)
      p.corners[k] = b.corners[k][first];
  }
  else
  {
    first = 0;
    for (int l = 0; l < fan_size; ++l)
    {
      const SurfaceSearch::Fan& fan = search.fans[static_cast<std::size_t>(f0 + l)];
      const float alpha = fan.t00 * p0 + fan.t01 * p1, beta = fan.t10 * p0 + fan.t11 * p1;
      const float gamma = (1.0f - alpha) - beta;
      float low = alpha < gamma ? alpha : gamma;
      low = beta < low ? beta : low;
      scores[l] = 0.0f - low;
      if (scores[l] < scores[first])
        first = l;
    }
    for (int k = 0; k < 3; ++k)
      p.corners[k] = search.fans[static_cast<std::size_t>(f0 + first)].corners[k];
  }
  p.first = first;
  p.fan_size = fan_size;
  p.face = mesh.vertex_faces[static_cast<std::size_t>(f0 + first)];
  p.data = c.data + static_cast<std::size_t>(p.face) * detail::kPhongData;
}

/// The dot products of the first triangle to try (phong_dots).
template<int kD>
BARY_ALWAYS_INLINE void first_dots(const ForwardContext& c, ForwardWorkspace& ws, int lane, Pending& p)
{
  const int D = kD > 0 ? kD : c.D;
  const double* y = ws.ybar.data() + lane * D;
  const Index c0 = p.corners[0], c1 = p.corners[1], c2 = p.corners[2];
  detail::phong_dots<kD>(c.frames + c0 * 2 * D, c.frames + c1 * 2 * D, c.frames + c2 * 2 * D,
    c.E + c0 * D, c.E + c1 * D, c.E + c2 * D, D, y, p.dots);
}

/// The triangle across the edge where Newton's iterate @p last left triangle f (its most
/// negative coordinate), or -1 (none negative, or the boundary).
inline int across_edge(const SurfaceMesh& mesh, int f, const double* last)
{
  const int k = last[0] <= last[1] && last[0] <= last[2] ? 0 : last[1] <= last[2] ? 1 : 2;
  return last[k] < 0 ? mesh.face_neighbors(f, k) : -1;
}

/// The rest of a forward query whose first triangle has no projection (rarely): the
/// breadth-first search over triangles, from v's other triangles. Newton's last iterate on the
/// first triangle shows where the projection lies: the triangle across the edge it left by
/// (@p across; -1: none) comes first, then v's other triangles in order, then the neighbours of
/// each triangle tried. @p tried: how many of the first and the across triangle were tried
/// already. @p y: ybar; @p scores: the scores of v's triangles. True and @p out when a
/// projection is found.
template<int kD>
BARY_ALWAYS_INLINE bool search_rest(const ForwardContext& c, ForwardWorkspace& ws,
  const double* y, const float* scores, const Pending& p, int across, int tried,
  SurfacePoint& out)
{
  const int D = kD > 0 ? kD : c.D;
  std::pair<float, int>* order = ws.order.data();
  const int fan_size = p.fan_size, first = p.first;
  const int f0 = c.mesh->face_offsets[static_cast<std::size_t>(p.v)];
  for (int l = 0; l < fan_size; ++l)
    order[l] = { scores[l], c.mesh->vertex_faces[static_cast<std::size_t>(f0 + l)] };
  double xi[3];
  const int query = ++ws.query;
  for (int l = 0; l < fan_size; ++l)
    ws.stamp[static_cast<std::size_t>(order[l].second)] = query;
  ws.queue.clear();
  ws.queue.push_back(p.face);
  if (across >= 0)
  {
    ws.queue.push_back(across);
    ws.stamp[static_cast<std::size_t>(across)] = query;
  }
  std::swap(order[first], order[fan_size - 1]);
  std::sort(order, order + fan_size - 1);
  for (int l = 0; l + 1 < fan_size; ++l)
    if (order[l].second != across)
      ws.queue.push_back(order[l].second);
  const Eigen::MatrixXi& neighbors = c.mesh->face_neighbors;
  for (std::size_t head = 0; head < ws.queue.size() && static_cast<Index>(head) < c.cap; ++head)
  {
    const int f = ws.queue[head];
    if (static_cast<int>(head) >= tried)
    {
      ++ws.tried;
      if (project_face<kD>(c, D, f, y, xi))
      {
        out.face = f;
        out.barycentric = Eigen::Vector3d(xi[0], xi[1], xi[2]);
        return true;
      }
    }
    for (int k = 0; k < 3; ++k)
    {
      const int g = neighbors(f, k);
      if (g >= 0 && ws.stamp[static_cast<std::size_t>(g)] != query)
      {
        ws.stamp[static_cast<std::size_t>(g)] = query;
        ws.queue.push_back(g);
      }
    }
  }
  return false;
}

/// The weights of the queries and where they start.
struct ForwardRows
{
  Index anchors = 0;
  const double* dense = nullptr;  ///< #queries by #anchors, row-major; or null:
  const int* outer = nullptr;     ///< sparse rows (compressed row storage)
  const int* inner = nullptr;
  const double* values = nullptr;
  const int* start = nullptr;     ///< per query: its start vertex from a hint, or -1; or null
  bool warm_start = false;        ///< start from the previous query's result (in the chunk)
};

/// Where the results go.
struct ForwardOutput
{
  SurfacePoint* points = nullptr;
  char* valid = nullptr;
  double* positions = nullptr;    ///< #queries by 3, column-major (column stride: queries)
  Index queries = 0;
};

/// Query q's result into the output (valid, point, position; a failure: NaN, counted).
/// @p corners: the corners of the point's triangle when the caller has them (else null: F's).
BARY_ALWAYS_INLINE void write_result(const ForwardContext& c, const ForwardOutput& o, Index q,
  bool ok, ForwardWorkspace& ws, const int* corners = nullptr)
{
  SurfacePoint& out = o.points[q];
  o.valid[q] = ok ? 1 : 0;
  if (!ok)
  {
    out = SurfacePoint{};
    ++ws.failures;
    for (int k = 0; k < 3; ++k)
      o.positions[k * o.queries + q] = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  int k0, k1, k2;
  if (corners)
  {
    k0 = corners[0];
    k1 = corners[1];
    k2 = corners[2];
  }
  else
  {
    const Eigen::MatrixXi& F = c.mesh->F;
    k0 = F(out.face, 0);
    k1 = F(out.face, 1);
    k2 = F(out.face, 2);
  }
  // The corners' positions from the row-major copy (one line each); lane 3 is padding.
  using detail::v4d;
  const double* V = c.search->V.data();
  const v4d x = BARY_LOAD4(V + 4 * static_cast<std::size_t>(k0)) * out.barycentric(0) +
    BARY_LOAD4(V + 4 * static_cast<std::size_t>(k1)) * out.barycentric(1) +
    BARY_LOAD4(V + 4 * static_cast<std::size_t>(k2)) * out.barycentric(2);
  double* position = o.positions + q;
  position[0] = x[0];
  position[o.queries] = x[1];
  position[2 * o.queries] = x[2];
}

/// phong_newton4 as a function of its own per instruction set: its vectors get the registers
/// (inlined into the search, they would share them with the search's state).
using Newton4 = void (*)(const double* const*, const double* const*, const bool*, int*, double (*)[3]);

BARY_NOINLINE void newton4_portable(const double* const* dots, const double* const* data,
  const bool* active, int* status, double (*xi)[3])
{
  detail::phong_newton4(dots, data, active, status, xi);
}

BARY_TARGET_AVX2 BARY_NOINLINE void newton4_avx2(const double* const* dots,
  const double* const* data, const bool* active, int* status, double (*xi)[3])
{
  detail::phong_newton4(dots, data, active, status, xi);
}

/// The second tries waiting in ws (queries whose first triangle had no projection), four at a
/// time in phong_newton4: the triangles across the edges Newton left their first ones by; the
/// queries whose second try has no projection either go on with search_rest.
template<int kD>
BARY_ALWAYS_INLINE void flush_retries(const ForwardContext& c, ForwardWorkspace& ws, const ForwardOutput& o,
  Newton4 newton4)
{
  const int D = kD > 0 ? kD : c.D;
  const int n = ws.retries;
  if (n == 0)
    return;
  const double* dots[4];
  const double* data[4];
  bool active[4];
  for (int l = 0; l < 4; ++l)
  {
    active[l] = l < n;
    dots[l] = ws.retry[l].dots;
    data[l] = ws.retry[l].data;
  }
  int status[4];
  double xi[4][3];
  newton4(dots, data, active, status, xi);
  for (int l = 0; l < n; ++l)
  {
    ForwardWorkspace::Retry& r = ws.retry[l];
    ++ws.tried;
    if (status[l] < 0)
      status[l] = detail::phong_newton(dots[l], data[l], true, 0.0, 0.0, xi[l]) ? 1 : 0;
    SurfacePoint& out = o.points[r.q];
    bool ok = status[l] == 1;
    if (ok)
    {
      out.face = r.across;
      out.barycentric = Eigen::Vector3d(xi[l][0], xi[l][1], xi[l][2]);
    }
    else
      ok = search_rest<kD>(c, ws, ws.retry_y.data() + l * D,
        ws.retry_scores.data() + l * ws.scores_stride, r.p, r.across, 2, out);
    write_result(c, o, r.q, ok, ws);
  }
  ws.retries = 0;
}

/// The forward queries [begin, end): four at a time (their Phong projections by phong_newton4,
/// whose latencies overlap), one at a time with a warm start (each starts where the previous
/// one ended). The first row that is not an average's is recorded in ws (bad_row, bad_sum).
template<int kD>
BARY_ALWAYS_INLINE void forward_chunk(const ForwardContext& c, const ForwardRows& rows,
  Index begin, Index end, ForwardWorkspace& ws, const ForwardOutput& o, Newton4 newton4)
{
  const int D = kD > 0 ? kD : c.D;
  const Eigen::MatrixXi& F = c.mesh->F;
  const int group = rows.warm_start ? 1 : 4;
  for (Index q0 = begin; q0 < end; q0 += group)
  {
    const int m = static_cast<int>(std::min<Index>(group, end - q0));
    Pending pending[4];
    unsigned found = 0; // lanes whose query started (bit l)
    for (int l = 0; l < m; ++l)
    {
      const Index q = q0 + l;
      const double* weight;
      const int* index = nullptr;
      int count;
      if (rows.dense)
      {
        weight = rows.dense + q * rows.anchors;
        count = static_cast<int>(rows.anchors);
      }
      else
      {
        weight = rows.values + rows.outer[q];
        index = rows.inner + rows.outer[q];
        count = rows.outer[q + 1] - rows.outer[q];
      }
      Index start = rows.start ? rows.start[q] : -1;
      if (rows.warm_start && q > begin && o.valid[q - 1])
      {
        const SurfacePoint& previous = o.points[q - 1];
        Index k;
        previous.barycentric.maxCoeff(&k);
        start = F(previous.face, k);
      }
      double sum = 0;
      const QueryOutcome outcome = start_query<kD>(c, index, weight, count, start, ws, l, pending[l], sum);
      if (outcome == QueryOutcome::Found)
        found |= 1u << l;
      else if (outcome == QueryOutcome::BadWeights && q < ws.bad_row)
      {
        ws.bad_row = q;
        ws.bad_sum = sum;
      }
    }
    // The lanes' walks in turns: their steps are independent, so their latencies overlap.
    for (unsigned walking = found; walking != 0;)
      for (unsigned w = walking; w != 0; w &= w - 1)
      {
        const int l = lowest_lane(w);
        if (!walk_step<kD>(c, ws, l, pending[l]))
          walking &= ~(1u << l);
      }
    for (unsigned w = found; w != 0; w &= w - 1)
    {
      const int l = lowest_lane(w);
      choose_triangle<kD>(c, ws, l, pending[l]);
      first_dots<kD>(c, ws, l, pending[l]);
    }
    const bool active[4] = { (found & 1u) != 0, (found & 2u) != 0, (found & 4u) != 0, (found & 8u) != 0 };
    const double* dots[4];
    const double* data[4];
    for (int l = 0; l < 4; ++l)
    {
      dots[l] = pending[l].dots;
      data[l] = active[l] ? pending[l].data : nullptr;
    }
    int status[4];
    double xi[4][3];
    if (m == 1)
    {
      status[0] = 0;
      if (active[0])
        status[0] = detail::phong_newton(dots[0], data[0], true, 0.0, 0.0, xi[0]) ? 1 : 0;
    }
    else
      newton4(dots, data, active, status, xi);
    for (int l = 0; l < m; ++l)
    {
      const Index q = q0 + l;
      SurfacePoint& out = o.points[q];
      bool ok = false, first = false;
      if (active[l])
      {
        ++ws.tried;
        if (status[l] < 0) // a corner: the one-triangle iteration decides
          status[l] = detail::phong_newton(dots[l], data[l], true, 0.0, 0.0, xi[l]) ? 1 : 0;
        if (status[l] == 1)
        {
          out.face = pending[l].face;
          out.barycentric = Eigen::Vector3d(xi[l][0], xi[l][1], xi[l][2]);
          ok = first = true;
        }
        else
        {
          const Pending& p = pending[l];
          const float* scores = ws.scores.data() + l * ws.scores_stride;
          const int across = across_edge(*c.mesh, p.face, xi[l]);
          if (across < 0 || rows.warm_start)
            ok = search_rest<kD>(c, ws, ws.ybar.data() + l * D, scores, p, across, 1, out);
          else
          {
            // Later, with three others: the second try usually succeeds.
            ForwardWorkspace::Retry& r = ws.retry[ws.retries];
            r.q = q;
            r.p = p;
            r.across = across;
            const double* y = ws.ybar.data() + l * D;
            std::copy(y, y + D, ws.retry_y.data() + ws.retries * D);
            std::copy(scores, scores + p.fan_size, ws.retry_scores.data() + ws.retries * ws.scores_stride);
            const int c0 = F(across, 0), c1 = F(across, 1), c2 = F(across, 2);
            r.data = c.data + static_cast<std::size_t>(across) * detail::kPhongData;
            detail::phong_dots<kD>(c.frames + c0 * 2 * D, c.frames + c1 * 2 * D,
              c.frames + c2 * 2 * D, c.E + c0 * D, c.E + c1 * D, c.E + c2 * D, D, y, r.dots);
            if (++ws.retries == 4)
              flush_retries<kD>(c, ws, o, newton4);
            continue;
          }
        }
      }
      write_result(c, o, q, ok, ws, first ? pending[l].corners : nullptr);
    }
  }
  flush_retries<kD>(c, ws, o, newton4);
}

void forward_chunk_portable(const ForwardContext& c, const ForwardRows& rows, Index begin,
  Index end, ForwardWorkspace& ws, const ForwardOutput& o)
{
  if (c.D == 8)
    forward_chunk<8>(c, rows, begin, end, ws, o, newton4_portable);
  else
    forward_chunk<0>(c, rows, begin, end, ws, o, newton4_portable);
}

BARY_TARGET_AVX2 void forward_chunk_avx2(const ForwardContext& c, const ForwardRows& rows,
  Index begin, Index end, ForwardWorkspace& ws, const ForwardOutput& o)
{
  if (c.D == 8)
    forward_chunk<8>(c, rows, begin, end, ws, o, newton4_avx2);
  else
    forward_chunk<0>(c, rows, begin, end, ws, o, newton4_avx2);
}

/// lambda = M^+ b for the symmetric positive semidefinite 3 x 3 M of the inverse problem,
/// b = (0, 0, 1). When M is well conditioned relative to its diagonal (the Cholesky factor of M
/// equilibrated to a unit diagonal has every pivot above 1e-6, tested without the factor:
/// pivot_1^2 = c22 / (M00 M11), pivot_2^2 = det M / (M22 c22) with c the cofactors) the inverse
/// by cofactors (the usual case: one division); else the eigen-decomposition's pseudo-inverse
/// of the equilibrated matrix (directions below 1e-14 of the largest eigenvalue dropped: anchors
/// that do not span the tangent plane). Then one step of iterative refinement with the residual
/// b - A w that @p residual(lambda, r) writes into r.
template<class Residual>
BARY_ALWAYS_INLINE void solve_constraints(const double M[3][3], Residual&& residual, double* lambda)
{
  const double m00 = M[0][0], m01 = M[0][1], m02 = M[0][2], m11 = M[1][1], m12 = M[1][2],
               m22 = M[2][2];
  const double c00 = m11 * m22 - m12 * m12, c01 = m02 * m12 - m01 * m22,
               c02 = m01 * m12 - m02 * m11, c11 = m00 * m22 - m02 * m02,
               c12 = m01 * m02 - m00 * m12, c22 = m00 * m11 - m01 * m01;
  const double det = m00 * c00 + m01 * c01 + m02 * c02;
  double r[3];
  if (c22 > 1e-12 * (m00 * m11) && det > 1e-12 * (m22 * c22))
  {
    const double inv = 1.0 / det;
    lambda[0] = c02 * inv;
    lambda[1] = c12 * inv;
    lambda[2] = c22 * inv;
    residual(lambda, r);
    lambda[0] += (c00 * r[0] + c01 * r[1] + c02 * r[2]) * inv;
    lambda[1] += (c01 * r[0] + c11 * r[1] + c12 * r[2]) * inv;
    lambda[2] += (c02 * r[0] + c12 * r[1] + c22 * r[2]) * inv;
    return;
  }
  double scale[3];
  Eigen::Matrix3d A;
  for (int i = 0; i < 3; ++i)
    scale[i] = 1.0 / std::sqrt(std::max(M[i][i], 1e-300));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      A(i, j) = scale[i] * M[i][j] * scale[j];
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A);
  const Eigen::Vector3d ev = eig.eigenvalues();
  const Eigen::Matrix3d& U = eig.eigenvectors();
  const double cutoff = 1e-14 * ev.cwiseAbs().maxCoeff();
  auto solve = [&](const double* rhs, double* out) {
    const double rs[3] = { scale[0] * rhs[0], scale[1] * rhs[1], scale[2] * rhs[2] };
    double y[3] = { 0.0, 0.0, 0.0 };
    for (int k = 0; k < 3; ++k)
      if (ev(k) > cutoff)
      {
        const double coefficient = (U(0, k) * rs[0] + U(1, k) * rs[1] + U(2, k) * rs[2]) / ev(k);
        for (int i = 0; i < 3; ++i)
          y[i] += U(i, k) * coefficient;
      }
    for (int i = 0; i < 3; ++i)
      out[i] = scale[i] * y[i];
  };
  const double b[3] = { 0.0, 0.0, 1.0 };
  solve(b, lambda);
  double correction[3];
  residual(lambda, r);
  solve(r, correction);
  for (int i = 0; i < 3; ++i)
    lambda[i] += correction[i];
}

/// Per-thread scratch of the inverse problem (#anchors numbers each, D for yhat, 2 D for P).
struct InverseState
{
  std::vector<double> yhat, P, t0, t1, Dii, x;
};

/// What an inverse query reads (shared by the threads).
struct InverseContext
{
  int D = 0;
  Index anchors = 0;
  Index stride = 0;           ///< #anchors rounded up to a multiple of 4
  const double* Yt = nullptr; ///< D by stride, row-major (structure of arrays)
  double gamma = 10, coincide = 0;
  const Eigen::MatrixXi* F = nullptr;
  const double* E = nullptr;      ///< #V by D, row-major
  const double* frames = nullptr; ///< PhongProjection's frames (#V by 2 D) and per-triangle data
  const double* data = nullptr;
  const SurfacePoint* points = nullptr;
  DenseWeights* W = nullptr;
};

/// P0 / |P0| and P1 minus its P0 part over its norm (Gram-Schmidt on Psi's rows). D = 8: four
/// coordinates at a time, the lanes' sums added pairwise.
template<int kD>
BARY_ALWAYS_INLINE void orthonormalize(double* P0, double* P1, int D)
{
  using detail::v4d;
  if (kD == 8)
  {
    const v4d p0a = BARY_LOAD4(P0), p0b = BARY_LOAD4(P0 + 4);
    v4d p1a = BARY_LOAD4(P1), p1b = BARY_LOAD4(P1 + 4);
    v4d t = p0a * p0a + p0b * p0b;
    const double n0 = 1.0 / std::sqrt((t[0] + t[1]) + (t[2] + t[3]));
    const v4d q0a = p0a * n0, q0b = p0b * n0;
    t = q0a * p1a + q0b * p1b;
    const double dot = (t[0] + t[1]) + (t[2] + t[3]);
    p1a -= q0a * dot;
    p1b -= q0b * dot;
    t = p1a * p1a + p1b * p1b;
    const double n1 = 1.0 / std::sqrt((t[0] + t[1]) + (t[2] + t[3]));
    BARY_STORE4(P0, q0a);
    BARY_STORE4(P0 + 4, q0b);
    BARY_STORE4(P1, p1a * n1);
    BARY_STORE4(P1 + 4, p1b * n1);
    return;
  }
  double n0 = 0;
  for (int d = 0; d < D; ++d)
    n0 += P0[d] * P0[d];
  n0 = 1.0 / std::sqrt(n0);
  double dot = 0;
  for (int d = 0; d < D; ++d)
  {
    P0[d] *= n0;
    dot += P0[d] * P1[d];
  }
  double n1 = 0;
  for (int d = 0; d < D; ++d)
  {
    P1[d] -= dot * P0[d];
    n1 += P1[d] * P1[d];
  }
  n1 = 1.0 / std::sqrt(n1);
  for (int d = 0; d < D; ++d)
    P1[d] *= n1;
}

/// For the G groups of four anchors from @p g: t0, t1 (the tangential coordinates of
/// y_i - yhat, each summed over d in order), D_ii = |v_T|^2 + gamma |v_O|^2, and the running
/// minimum of D_ii in @p low. d is the outer loop: yhat and P are read once per coordinate.
template<int kD, int G>
BARY_ALWAYS_INLINE void anchor_terms(const InverseContext& c, int D, Index g, const double* yhat,
  const double* P0, const double* P1, double gamma, double* t0, double* t1, double* Dii, detail::v4d& low)
{
  using detail::v4d;
  const int n = kD > 0 ? kD : D;
  const double* Y = c.Yt + g;
  v4d a0[G], a1[G], n2[G];
  for (int k = 0; k < G; ++k)
  {
    const v4d v = BARY_LOAD4(Y + 4 * k) - yhat[0];
    a0[k] = v * P0[0];
    a1[k] = v * P1[0];
    n2[k] = v * v;
  }
  for (int d = 1; d < n; ++d)
  {
    const double* Yd = Y + d * c.stride;
    const double y = yhat[d], p0 = P0[d], p1 = P1[d];
    for (int k = 0; k < G; ++k)
    {
      const v4d v = BARY_LOAD4(Yd + 4 * k) - y;
      a0[k] += v * p0;
      a1[k] += v * p1;
      n2[k] += v * v;
    }
  }
  const v4d zero = { 0.0, 0.0, 0.0, 0.0 };
  for (int k = 0; k < G; ++k)
  {
    const v4d t2 = a0[k] * a0[k] + a1[k] * a1[k];
    const v4d off = n2[k] - t2;
    const v4d dii = t2 + BARY_SELECT(off > zero, off, zero) * gamma;
    BARY_STORE4(t0 + g + 4 * k, a0[k]);
    BARY_STORE4(t1 + g + 4 * k, a1[k]);
    BARY_STORE4(Dii + g + 4 * k, dii);
    low = BARY_SELECT(dii < low, dii, low);
  }
}

/// The inverse problem (§3.4, Eq. 13) of points [begin, end). See weighted_averages.h.
template<int kD>
BARY_ALWAYS_INLINE void inverse_rows(const InverseContext& c, InverseState& s, Index begin, Index end)
{
  using detail::v4d;
  const int D = kD > 0 ? kD : c.D;
  const Index n = c.anchors;
  const double gamma = c.gamma;
  double* yhat = s.yhat.data();
  double* P0 = s.P.data();
  double* P1 = P0 + D;
  double* t0 = s.t0.data();
  double* t1 = s.t1.data();
  double* Dii = s.Dii.data();
  double* x = s.x.data();
  for (Index q = begin; q < end; ++q)
  {
    const SurfacePoint& p = c.points[q];
    const Index f = p.face;
    const double xa = p.barycentric(0), xb = p.barycentric(1), xc = p.barycentric(2);
    const Index c0 = (*c.F)(f, 0), c1 = (*c.F)(f, 1), c2 = (*c.F)(f, 2);
    {
      const double* v0 = c.E + c0 * D;
      const double* v1 = c.E + c1 * D;
      const double* v2 = c.E + c2 * D;
      int d = 0;
      for (; d + 4 <= D; d += 4)
        BARY_STORE4(yhat + d, (BARY_LOAD4(v0 + d) * xa + BARY_LOAD4(v1 + d) * xb) + BARY_LOAD4(v2 + d) * xc);
      for (; d < D; ++d)
        yhat[d] = xa * v0[d] + xb * v1[d] + xc * v2[d];
    }
    // Orthonormal basis of the interpolated tangent plane.
    detail::phong_psi<kD>(c.data + f * detail::kPhongData, c.frames + c0 * 2 * D,
      c.frames + c1 * 2 * D, c.frames + c2 * 2 * D, D, xa, xb, xc, P0);
    orthonormalize<kD>(P0, P1, D);
    // Per anchor, four at a time (the padding's coordinates are 1e150: D^-2 = 0 there): the
    // tangential coordinates of y_i - yhat (t0, t1, each summed over d in order) and
    // D_ii = |v_T|^2 + gamma |v_O|^2.
    const v4d zero = { 0.0, 0.0, 0.0, 0.0 };
    const double inf = std::numeric_limits<double>::infinity();
    v4d low = { inf, inf, inf, inf };
    for (Index g = 0; g < n; g += 16)
    {
      switch (std::min<Index>(4, (n - g + 3) / 4))
      {
      case 4:
        anchor_terms<kD, 4>(c, D, g, yhat, P0, P1, gamma, t0, t1, Dii, low);
        break;
      case 3:
        anchor_terms<kD, 3>(c, D, g, yhat, P0, P1, gamma, t0, t1, Dii, low);
        break;
      case 2:
        anchor_terms<kD, 2>(c, D, g, yhat, P0, P1, gamma, t0, t1, Dii, low);
        break;
      default:
        anchor_terms<kD, 1>(c, D, g, yhat, P0, P1, gamma, t0, t1, Dii, low);
      }
    }
    double smallest = std::min(std::min(low[0], low[1]), std::min(low[2], low[3]));
    double* w = c.W->data() + q * n;
    if (smallest <= c.coincide)
    {
      // The point is an anchor: interpolation (split evenly among coinciding anchors).
      Index count = 0;
      for (Index i = 0; i < n; ++i)
        count += Dii[i] <= c.coincide;
      for (Index i = 0; i < n; ++i)
        w[i] = Dii[i] <= c.coincide ? 1.0 / static_cast<double>(count) : 0.0;
      continue;
    }
    // w = D^-2 A^T (A D^-2 A^T)^+ b with A's rows (t0, t1, 1) and b = (0, 0, 1): the
    // tangential constraint written on y_i - yhat (equivalent given sum w = 1, better
    // conditioned). D^-2 is scaled to a largest entry of 1: (D_min / D_ii)^2. Sums over the
    // anchors: four partial sums (one per lane), then added pairwise.
    v4d m00 = zero, m01 = zero, m02 = zero, m11 = zero, m12 = zero, m22 = zero;
    const v4d closest = { smallest, smallest, smallest, smallest };
    for (Index g = 0; g < n; g += 4)
    {
      const v4d r = closest / BARY_LOAD4(Dii + g);
      const v4d v = r * r; // the weights of D^-2
      BARY_STORE4(x + g, v);
      const v4d a0 = BARY_LOAD4(t0 + g), a1 = BARY_LOAD4(t1 + g);
      const v4d va0 = v * a0, va1 = v * a1;
      m00 += va0 * a0;
      m01 += va0 * a1;
      m02 += va0;
      m11 += va1 * a1;
      m12 += va1;
      m22 += v;
    }
    double sums[8];
    detail::lane_sums(m00, m01, m02, m11, sums);
    detail::lane_sums(m12, m22, zero, zero, sums + 4);
    const double M[3][3] = { { sums[0], sums[1], sums[2] }, { sums[1], sums[3], sums[4] },
      { sums[2], sums[4], sums[5] } };
    double lambda[3];
    solve_constraints(M,
      [&](const double* l, double* r) {
        // residual b - A w for w = D^-2 A^T l
        v4d r0 = zero, r1 = zero, r2 = zero;
        for (Index g = 0; g < n; g += 4)
        {
          const v4d a0 = BARY_LOAD4(t0 + g), a1 = BARY_LOAD4(t1 + g);
          const v4d wi = BARY_LOAD4(x + g) * ((a0 * l[0] + a1 * l[1]) + l[2]);
          r0 += a0 * wi;
          r1 += a1 * wi;
          r2 += wi;
        }
        double rs[4];
        detail::lane_sums(r0, r1, r2, zero, rs);
        r[0] = -rs[0];
        r[1] = -rs[1];
        r[2] = 1.0 - rs[2];
      },
      lambda);
    v4d total = zero;
    for (Index g = 0; g < n; g += 4)
    {
      const v4d wi = BARY_LOAD4(x + g) *
        ((BARY_LOAD4(t0 + g) * lambda[0] + BARY_LOAD4(t1 + g) * lambda[1]) + lambda[2]);
      BARY_STORE4(x + g, wi);
      total += wi;
    }
    const double sum = (total[0] + total[1]) + (total[2] + total[3]);
    // Partition of unity exactly: the tangential constraint sum w_i (y_i - yhat) = 0 is
    // homogeneous, so scaling the row keeps it. It matters where the anchors do not span the
    // tangent plane and the pseudo-inverse satisfies the constraints only in the least-squares
    // sense. A row that sums to (almost) 0 has no such scaling: it falls back to the anchor
    // nearest in the metric of D (the round trip then tells whether the point is reached).
    if (std::abs(sum) > 1e-12)
    {
      Index i = 0;
      for (; i + 4 <= n; i += 4)
        BARY_STORE4(w + i, BARY_LOAD4(x + i) / sum);
      for (; i < n; ++i)
        w[i] = x[i] / sum;
    }
    else
    {
      Index nearest = 0;
      for (Index i = 1; i < n; ++i)
        if (Dii[i] < Dii[nearest])
          nearest = i;
      for (Index i = 0; i < n; ++i)
        w[i] = i == nearest ? 1.0 : 0.0;
    }
  }
}

void inverse_rows_portable(const InverseContext& c, InverseState& s, Index begin, Index end)
{
  if (c.D == 8)
    inverse_rows<8>(c, s, begin, end);
  else
    inverse_rows<0>(c, s, begin, end);
}

BARY_TARGET_AVX2 void inverse_rows_avx2(
  const InverseContext& c, InverseState& s, Index begin, Index end)
{
  if (c.D == 8)
    inverse_rows<8>(c, s, begin, end);
  else
    inverse_rows<0>(c, s, begin, end);
}

/// #anchors rounded up to a multiple of 4 (the kernels' vectors).
Index padded(Index n)
{
  return (n + 3) / 4 * 4;
}

/// D by padded(n), row-major: the anchors' embedded coordinates as structure of arrays (1e150
/// in the padding: far from everything).
std::vector<double> transposed(const RowMatrix& Y)
{
  const Index stride = padded(Y.rows());
  std::vector<double> Yt(static_cast<std::size_t>(Y.cols() * stride), 1e150);
  for (Index i = 0; i < Y.rows(); ++i)
    for (Index d = 0; d < Y.cols(); ++d)
      Yt[static_cast<std::size_t>(d * stride + i)] = Y(i, d);
  return Yt;
}

/// The corner of a surface point with the largest barycentric coordinate.
int nearest_corner(const Eigen::MatrixXi& F, const SurfacePoint& p)
{
  Index k;
  p.barycentric.maxCoeff(&k);
  return F(p.face, k);
}

} // namespace

void validate_forward_options(const ForwardOptions& options)
{
  if (options.max_triangles < 0 || options.max_triangles > std::numeric_limits<int>::max())
    throw Error(ErrorCode::InvalidArgument, "the triangle cap must be in [0, 2^31), got " +
        std::to_string(options.max_triangles));
  if (options.threads < 0 || options.threads > 1024)
    throw Error(ErrorCode::InvalidArgument,
      "the thread count must be in [0, 1024], got " + std::to_string(options.threads));
}

void validate_round_trip_tolerance(double tolerance)
{
  if (!(tolerance > 0 && tolerance <= 1e6))
    throw Error(ErrorCode::InvalidArgument, "the round-trip tolerance must be in (0, 1e6] (times "
        "the mean edge length), got " + detail::format_number(tolerance));
}

void validate_inverse_options(const InverseOptions& options)
{
  if (!(options.gamma >= 1.0 && options.gamma <= 1e6))
    throw Error(ErrorCode::InvalidArgument,
      "gamma must be in [1, 1e6], got " + detail::format_number(options.gamma));
  if (options.threads < 0 || options.threads > 1024)
    throw Error(ErrorCode::InvalidArgument,
      "the thread count must be in [0, 1024], got " + std::to_string(options.threads));
}

void validate_surface_points(
  const SurfaceMesh& mesh, const std::vector<SurfacePoint>& points, const char* what)
{
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const SurfacePoint& p = points[i];
    auto name = [&] { return std::string(what) + " " + std::to_string(i); };
    if (p.face < 0 || p.face >= mesh.face_count())
      throw Error(ErrorCode::InvalidArgument, name() + " is on triangle " +
          std::to_string(p.face) + " but the surface has " + std::to_string(mesh.face_count()) +
          " triangles");
    const Eigen::Vector3d& b = p.barycentric;
    if (!(std::isfinite(b(0)) && std::isfinite(b(1)) && std::isfinite(b(2))) || b(0) < -1e-9 ||
      b(1) < -1e-9 || b(2) < -1e-9 || std::abs(b.sum() - 1.0) > 1e-9)
      throw Error(ErrorCode::InvalidArgument, name() + " has barycentric coordinates " +
          detail::format_point(p.barycentric.data(), 3) +
          " (they must be finite, >= 0 and sum to 1)");
  }
}

WeightedAverages::WeightedAverages(SurfaceMesh mesh, const Eigen::MatrixXd& E)
  : mesh_(std::make_shared<const SurfaceMesh>(std::move(mesh)))
  , phong_(std::make_shared<const PhongProjection>(*mesh_, E))
  , search_(std::make_shared<const detail::SurfaceSearch>(*mesh_, E, phong_->frames()))
  , E_(E)
{
}

Eigen::MatrixXd WeightedAverages::embed(const std::vector<SurfacePoint>& points) const
{
  return surface_point_positions(mesh_->F, E_, points);
}

ForwardResult WeightedAverages::forward(const std::vector<SurfacePoint>& anchors,
  const DenseWeights& W, const ForwardOptions& options, const ProgressCallback& progress) const
{
  if (W.cols() != static_cast<Index>(anchors.size()))
    throw Error(ErrorCode::SizeMismatch, "the weights have " + std::to_string(W.cols()) +
        " columns but there are " + std::to_string(anchors.size()) + " anchors",
      "give one weight per anchor in every row");
  return forward_rows(anchors, W.rows(), W.data(), nullptr, nullptr, nullptr, options, progress,
    nullptr);
}

ForwardResult WeightedAverages::forward(const std::vector<SurfacePoint>& anchors,
  const SparseWeights& W, const ForwardOptions& options, const ProgressCallback& progress,
  const std::vector<SurfacePoint>* hints) const
{
  if (W.cols() != static_cast<Index>(anchors.size()))
    throw Error(ErrorCode::SizeMismatch, "the weights have " + std::to_string(W.cols()) +
        " columns but there are " + std::to_string(anchors.size()) + " anchors",
      "give one weight per anchor in every row");
  if (hints && static_cast<Index>(hints->size()) != W.rows())
    throw Error(ErrorCode::SizeMismatch, "there are " + std::to_string(hints->size()) +
        " start hints for " + std::to_string(W.rows()) + " queries");
  if (!W.isCompressed())
  {
    SparseWeights compressed = W;
    compressed.makeCompressed();
    return forward(anchors, compressed, options, progress, hints);
  }
  return forward_rows(anchors, W.rows(), nullptr, W.outerIndexPtr(), W.innerIndexPtr(),
    W.valuePtr(), options, progress, hints);
}

ForwardResult WeightedAverages::forward_rows(const std::vector<SurfacePoint>& anchors, Index nq,
  const double* dense, const int* outer, const int* inner, const double* values,
  const ForwardOptions& options, const ProgressCallback& progress,
  const std::vector<SurfacePoint>* hints) const
{
  const auto t0 = std::chrono::steady_clock::now();
  if (anchors.empty())
    throw Error(ErrorCode::EmptyInput, "no anchors: a weighted average needs at least one");
  validate_surface_points(*mesh_, anchors, "anchor");
  validate_forward_options(options);
  const Index n = static_cast<Index>(anchors.size());
  const int D = dimension();
  const RowMatrix Y = embed(anchors);
  const Index stride8 = (n + SurfaceSearch::kLanes - 1) / SurfaceSearch::kLanes * SurfaceSearch::kLanes;
  std::vector<float> Ytf(static_cast<std::size_t>(D * stride8), SurfaceSearch::kPad);
  std::vector<float> Yf(static_cast<std::size_t>(n * D));
  for (Index i = 0; i < n; ++i)
    for (int d = 0; d < D; ++d)
    {
      Ytf[static_cast<std::size_t>(d * stride8 + i)] = static_cast<float>(Y(i, d));
      Yf[static_cast<std::size_t>(i * D + d)] = static_cast<float>(Y(i, d));
    }
  std::vector<Index> anchor_corners(anchors.size());
  for (std::size_t i = 0; i < anchors.size(); ++i)
    anchor_corners[i] = nearest_corner(mesh_->F, anchors[i]);
  std::vector<int> starts;
  if (hints)
  {
    starts.resize(static_cast<std::size_t>(nq));
    for (Index q = 0; q < nq; ++q)
    {
      const SurfacePoint& h = (*hints)[static_cast<std::size_t>(q)];
      starts[static_cast<std::size_t>(q)] = h.face >= 0 ? static_cast<int>(nearest_corner(mesh_->F, h)) : -1;
    }
  }
  ForwardContext context;
  context.D = D;
  context.anchors = n;
  context.anchors_padded = stride8;
  context.Y = Y.data();
  context.Yt = Ytf.data();
  context.Y_float = Yf.data();
  context.anchor_corners = anchor_corners.data();
  context.mesh = mesh_.get();
  context.search = search_.get();
  context.E = phong_->E_.data();
  context.frames = phong_->frame_rows_.data();
  context.data = phong_->data_.data();
  context.cap = options.max_triangles > 0 ? options.max_triangles : mesh_->face_count();
  ForwardRows rows;
  rows.anchors = n;
  rows.dense = dense;
  rows.outer = outer;
  rows.inner = inner;
  rows.values = values;
  rows.start = hints ? starts.data() : nullptr;
  rows.warm_start = options.warm_start;
  const bool avx2 = detail::simd_level() == detail::SimdLevel::AVX2;
  ForwardResult result;
  result.points.resize(static_cast<std::size_t>(nq));
  result.valid.resize(static_cast<std::size_t>(nq));
  result.positions.resize(nq, 3);
  ForwardOutput output;
  output.points = result.points.data();
  output.valid = result.valid.data();
  output.positions = result.positions.data();
  output.queries = nq;
  ProgressReporter reporter(progress, std::max<Index>(nq, 1));
  auto make_state = [&] {
    ForwardWorkspace ws;
    ws.stamp.assign(static_cast<std::size_t>(mesh_->face_count()), 0);
    ws.queue.reserve(64);
    ws.scores_stride = search_->max_valence + SurfaceSearch::kLanes;
    ws.scores.resize(static_cast<std::size_t>(4 * ws.scores_stride));
    ws.order.resize(static_cast<std::size_t>(ws.scores_stride));
    ws.dist.resize(static_cast<std::size_t>(search_->max_valence + SurfaceSearch::kLanes));
    ws.anchor_distance.resize(static_cast<std::size_t>(stride8));
    ws.ybar.resize(static_cast<std::size_t>(4 * D));
    ws.ybar_float.resize(static_cast<std::size_t>(4 * D));
    ws.retry.resize(4);
    ws.retry_y.resize(static_cast<std::size_t>(4 * D));
    ws.retry_scores.resize(static_cast<std::size_t>(4 * ws.scores_stride));
    ws.point.resize(static_cast<std::size_t>(D));
    return ws;
  };
  // Search::BruteForce: every triangle, the projection closest to ybar (Definition 2).
  auto brute = [&](ForwardWorkspace& ws, Index q) {
    const double* weight = dense ? dense + q * n : values + outer[q];
    const int* index = dense ? nullptr : inner + outer[q];
    const int count = dense ? static_cast<int>(n) : outer[q + 1] - outer[q];
    double sum = 0;
    if (!weights_row_valid(weight, count, sum))
    {
      ws.bad_row = std::min(ws.bad_row, q);
      if (ws.bad_row == q)
        ws.bad_sum = sum;
      return false;
    }
    double* ybar = ws.ybar.data();
    std::fill(ybar, ybar + D, 0.0);
    for (int j = 0; j < count; ++j)
      if (weight[j] != 0.0)
        for (int d = 0; d < D; ++d)
          ybar[d] += weight[j] * Y(index ? index[j] : j, d);
    SurfacePoint& out = result.points[static_cast<std::size_t>(q)];
    double best = std::numeric_limits<double>::infinity();
    Eigen::Vector3d xi;
    for (Index f = 0; f < mesh_->face_count(); ++f)
    {
      ++ws.tried;
      if (!phong_->project(f, ybar, xi))
        continue;
      phong_->position(f, xi, ws.point.data());
      const double d = squared_distance(ws.point.data(), ybar, D);
      if (d < best)
      {
        best = d;
        out.face = f;
        out.barycentric = xi;
      }
    }
    return best < std::numeric_limits<double>::infinity();
  };
  const Eigen::MatrixXi& F = mesh_->F;
  const Eigen::MatrixXd& V = mesh_->V;
  auto body = [&](ForwardWorkspace& ws, Index begin, Index end) {
    if (options.search == ForwardOptions::Search::Local)
    {
      if (avx2)
        forward_chunk_avx2(context, rows, begin, end, ws, output);
      else
        forward_chunk_portable(context, rows, begin, end, ws, output);
      return;
    }
    for (Index q = begin; q < end; ++q)
    {
      const bool ok = brute(ws, q);
      result.valid[static_cast<std::size_t>(q)] = ok ? 1 : 0;
      SurfacePoint& out = result.points[static_cast<std::size_t>(q)];
      if (!ok)
      {
        out = SurfacePoint{};
        ++ws.failures;
        result.positions.row(q).setConstant(std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      result.positions.row(q) = out.barycentric(0) * V.row(F(out.face, 0)) +
        out.barycentric(1) * V.row(F(out.face, 1)) + out.barycentric(2) * V.row(F(out.face, 2));
    }
  };
  Index tried = 0, failures = 0, bad_row = std::numeric_limits<Index>::max();
  double bad_sum = 0;
  detail::parallel_for(nq, kChunk, options.threads, reporter, "the weighted averages", make_state,
    body, [&](ForwardWorkspace& ws) {
      tried += ws.tried;
      failures += ws.failures;
      if (ws.bad_row < bad_row)
      {
        bad_row = ws.bad_row;
        bad_sum = ws.bad_sum;
      }
    });
  // Rows that are not an average's are found by the queries (each row is read once); the first
  // one is reported, whatever the number of threads.
  if (bad_row < nq)
  {
    if (std::isnan(bad_sum))
      throw Error(ErrorCode::NonFinite,
        "weights row " + std::to_string(bad_row) + " has a non-finite weight");
    throw Error(ErrorCode::InvalidArgument, "weights row " + std::to_string(bad_row) +
        " sums to " + detail::format_number(bad_sum, 15) + ", not 1",
      "weights of an average must sum to 1");
  }
  result.triangles_tried = tried;
  result.failures = failures;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

DenseWeights WeightedAverages::inverse(const std::vector<SurfacePoint>& anchors,
  const std::vector<SurfacePoint>& points, const InverseOptions& options,
  const ProgressCallback& progress) const
{
  if (anchors.empty())
    throw Error(ErrorCode::EmptyInput, "no anchors: weights need at least one");
  validate_surface_points(*mesh_, anchors, "anchor");
  validate_surface_points(*mesh_, points, "point");
  validate_inverse_options(options);
  const int D = dimension();
  const Index n = static_cast<Index>(anchors.size());
  const RowMatrix Y = embed(anchors);
  const std::vector<double> Yt = transposed(Y);
  const double extent2 = (E_.colwise().maxCoeff() - E_.colwise().minCoeff()).squaredNorm();
  const Index np = static_cast<Index>(points.size());
  DenseWeights W(np, n);
  InverseContext context;
  context.D = D;
  context.anchors = n;
  context.stride = padded(n);
  context.Yt = Yt.data();
  context.gamma = options.gamma;
  context.coincide = 1e-24 * extent2;
  context.F = &mesh_->F;
  context.E = phong_->E_.data();
  context.frames = phong_->frame_rows_.data();
  context.data = phong_->data_.data();
  context.points = points.data();
  context.W = &W;
  const bool avx2 = detail::simd_level() == detail::SimdLevel::AVX2;
  ProgressReporter reporter(progress, std::max<Index>(np, 1));
  auto make_state = [&] {
    InverseState s;
    s.yhat.resize(static_cast<std::size_t>(D));
    s.P.resize(static_cast<std::size_t>(2 * D));
    for (auto* v : { &s.t0, &s.t1, &s.Dii, &s.x })
      v->resize(static_cast<std::size_t>(padded(n)));
    return s;
  };
  auto body = [&](InverseState& s, Index begin, Index end) {
    if (avx2)
      inverse_rows_avx2(context, s, begin, end);
    else
      inverse_rows_portable(context, s, begin, end);
  };
  detail::parallel_for(np, kChunk, options.threads, reporter, "the inverse weighted averages",
    make_state, body, [](InverseState&) {});
  return W;
}

RoundTrip WeightedAverages::round_trip(const std::vector<SurfacePoint>& anchors,
  const std::vector<SurfacePoint>& points, const DenseWeights& W, double tolerance,
  const ForwardOptions& options, const ProgressCallback& progress) const
{
  if (W.rows() != static_cast<Index>(points.size()))
    throw Error(ErrorCode::SizeMismatch, "the weights have " + std::to_string(W.rows()) +
        " rows but there are " + std::to_string(points.size()) + " points");
  validate_round_trip_tolerance(tolerance);
  validate_surface_points(*mesh_, points, "point");
  const ForwardResult f = forward(anchors, W, options, progress);
  const Eigen::MatrixXd X = surface_point_positions(mesh_->F, mesh_->V, points);
  RoundTrip r;
  r.error.resize(points.size());
  r.returned.assign(points.size(), 0);
  r.failures = f.failures;
  const double limit = tolerance * mesh_->mean_edge_length;
  std::vector<double> finite;
  for (std::size_t p = 0; p < points.size(); ++p)
  {
    if (!f.valid[p])
    {
      r.error[p] = std::numeric_limits<double>::quiet_NaN();
      ++r.not_returned;
      continue;
    }
    r.error[p] = (f.positions.row(static_cast<Index>(p)) - X.row(static_cast<Index>(p))).norm();
    finite.push_back(r.error[p]);
    r.returned[p] = r.error[p] <= limit ? 1 : 0;
    if (!r.returned[p])
      ++r.not_returned;
  }
  if (!finite.empty())
  {
    r.max_error = *std::max_element(finite.begin(), finite.end());
    std::nth_element(finite.begin(), finite.begin() + static_cast<std::ptrdiff_t>(finite.size() / 2), finite.end());
    r.median_error = finite[finite.size() / 2];
  }
  return r;
}

} // namespace bary
