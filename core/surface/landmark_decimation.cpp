#include "core/surface/landmark_decimation.h"

#include "core/common/error.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace bary
{
namespace
{

using Vec3 = Eigen::Vector3d;

constexpr double pi = 3.14159265358979323846;
/// A face is degenerate when twice its area is at most this times its longest edge squared (the
/// sine of its largest angle is then about this small): a collapse may not make one, and one in
/// the input has no normal.
constexpr double degenerate_ratio = 1e-12;
/// A component with this many vertices or fewer is not decimated further.
constexpr Index min_component_vertices = 4;
constexpr const char* what_cancelled = "the landmark decimation";

/// Angle in [0, pi] between two non-zero vectors of any lengths (0 if either is zero).
double angle_between(const Vec3& a, const Vec3& b)
{
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// An angle theta in [0, pi] held as its cosine and sine, so that the costs are computed and
/// compared without trigonometric functions. key increases with theta: sin theta up to pi/2,
/// then 2 - sin theta (precise near 0, where most costs are).
struct Angle
{
  double key = 0.0, cosine = 1.0, sine = 0.0;
  double radians() const { return std::atan2(sine, cosine); }
};

Angle make_angle(double cosine, double sine)
{
  return { cosine >= 0.0 ? sine : 2.0 - sine, cosine, sine };
}

const Angle straight_angle{ 2.0, -1.0, 0.0 };

/// A circular cone of unit directions: those within half_angle of axis. Empty when
/// half_angle < 0. Keeps the cosine and sine of its half-angle.
struct Cone
{
  Vec3 axis = Vec3::Zero();
  double half_angle = -1.0;
  Angle half;
  bool empty() const { return half_angle < 0.0; }
};

Cone make_cone(const Vec3& axis, double half_angle)
{
  return { axis, half_angle, make_angle(std::cos(half_angle), std::sin(half_angle)) };
}

/// The cone holding only the direction of @p n; empty for a zero vector.
Cone cone_of(const Vec3& n)
{
  const double length = n.norm();
  if (!(length > 0.0))
    return {};
  return make_cone(n / length, 0.0);
}

/// The largest angle between the unit vector @p n and a direction in @p c: the angle between n
/// and the axis plus the half-angle, at most pi (0 for an empty cone).
Angle farthest_angle(const Vec3& n, const Cone& c)
{
  if (c.empty())
    return {};
  if (c.half_angle >= pi)
    return straight_angle;
  const double s = n.cross(c.axis).norm(), d = n.dot(c.axis);
  if (c.half_angle == 0.0)
    return make_angle(d, s);
  // cos and sin of (angle to the axis + half-angle); a negative sine means beyond pi.
  const double sine = s * c.half.cosine + d * c.half.sine;
  if (sine < 0.0)
    return straight_angle;
  return make_angle(d * c.half.cosine - s * c.half.sine, sine);
}

/// @p n / |n|, or zero.
Vec3 unit(const Vec3& n)
{
  const double length = n.norm();
  return length > 0.0 ? Vec3(n / length) : Vec3::Zero();
}

Angle max_angle(const Angle& a, const Angle& b)
{
  return b.key > a.key ? b : a;
}

/// The smallest circular cone that holds both cones.
Cone merge(const Cone& a, const Cone& b)
{
  if (a.empty())
    return b;
  if (b.empty())
    return a;
  const double d = angle_between(a.axis, b.axis);
  if (d + b.half_angle <= a.half_angle)
    return a;
  if (d + a.half_angle <= b.half_angle)
    return b;
  const double half_angle = 0.5 * (d + a.half_angle + b.half_angle);
  if (half_angle >= pi)
    return make_cone(a.axis, pi);
  // Turn a's axis towards b's by half_angle - a.half_angle, in (0, d).
  const double turn = half_angle - a.half_angle;
  Vec3 toward = b.axis - a.axis * a.axis.dot(b.axis);
  const double length = toward.norm();
  if (!(length > 1e-300))
  {
    if (a.axis.dot(b.axis) > 0.0) // (nearly) equal axes: keep a's, widen to hold b
      return make_cone(a.axis, std::max(a.half_angle, b.half_angle) + d);
    toward = a.axis.unitOrthogonal(); // opposite axes: any perpendicular plane will do
  }
  else
    toward /= length;
  const Vec3 axis = std::cos(turn) * a.axis + std::sin(turn) * toward;
  return make_cone(axis.normalized(), half_angle);
}

/// Disjoint sets with path halving (union by smaller root, so results are deterministic).
struct DisjointSets
{
  std::vector<int> parent;
  explicit DisjointSets(std::size_t n)
    : parent(n)
  {
    std::iota(parent.begin(), parent.end(), 0);
  }
  int find(int x)
  {
    while (parent[x] != x)
    {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  }
  void unite(int a, int b)
  {
    a = find(a);
    b = find(b);
    if (a != b)
      parent[std::max(a, b)] = std::min(a, b);
  }
};

/// One entry of the queue: vertex u's best collapse when it was computed (its target is kept
/// in the decimator, for the entry with u's current version), and its cost (Angle::key).
struct Candidate
{
  double cost;
  double length2; ///< squared length of the collapsed edge (the tie-break)
  int u;
  std::uint32_t version;
};

/// Orders the queue so that top() is the cheapest collapse; equal costs (a flat region, where
/// every collapse costs 0) go to the shorter edge, so flat regions thin out evenly instead of
/// in vertex-id order; then by u (one valid entry per u; each vertex picks its target by cost,
/// then edge length, then vertex id), then version.
struct CostlierThan
{
  bool operator()(const Candidate& a, const Candidate& b) const
  {
    if (a.cost != b.cost)
      return a.cost > b.cost;
    if (a.length2 != b.length2)
      return a.length2 > b.length2;
    if (a.u != b.u)
      return a.u > b.u;
    return a.version > b.version;
  }
};

std::string face_name(Index f, const Eigen::MatrixXi& F)
{
  return "face " + std::to_string(f) + " (" + std::to_string(F(f, 0)) + ", " +
    std::to_string(F(f, 1)) + ", " + std::to_string(F(f, 2)) + ")";
}

/// Shapes, option range, indices and finiteness.
void validate_input(
  const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const LandmarkDecimationOptions& options)
{
  if (V.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the mesh has no vertices (V has no rows)");
  if (F.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the mesh has no faces (F has no rows)");
  if (V.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "mesh vertices must have 3 coordinates (V with 3 columns), got " + std::to_string(V.cols()));
  if (F.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "faces must be triangles (F with 3 columns), got " + std::to_string(F.cols()) + " columns");
  const Index largest = std::numeric_limits<int>::max() / 4; // face corners are ints
  if (V.rows() > largest || F.rows() > largest)
    throw Error(ErrorCode::InvalidArgument,
      "the mesh is too large: " + std::to_string(V.rows()) + " vertices, " +
        std::to_string(F.rows()) + " faces (at most " + std::to_string(largest) + " of each)");
  if (options.target_vertices < min_component_vertices || options.target_vertices > V.rows())
    throw Error(ErrorCode::InvalidArgument,
      "LandmarkDecimationOptions::target_vertices must be in [" +
        std::to_string(min_component_vertices) + ", " + std::to_string(V.rows()) +
        "] (the mesh has " + std::to_string(V.rows()) + " vertices), got " +
        std::to_string(options.target_vertices));
  const Index n = V.rows();
  for (Index f = 0; f < F.rows(); ++f)
  {
    for (Index k = 0; k < 3; ++k)
      if (F(f, k) < 0 || F(f, k) >= n)
        throw Error(ErrorCode::InvalidArgument,
          face_name(f, F) + " refers to vertex " + std::to_string(F(f, k)) + ", outside [0, " +
            std::to_string(n) + "): the mesh has " + std::to_string(n) + " vertices");
    if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 2) == F(f, 0))
      throw Error(ErrorCode::InvalidArgument,
        face_name(f, F) + " repeats a vertex; remove it or repair the mesh");
  }
  for (Index i = 0; i < n; ++i)
    if (!V.row(i).allFinite())
    {
      std::ostringstream s;
      s << "mesh vertex " << i << " has a non-finite coordinate (" << V(i, 0) << ", " << V(i, 1)
        << ", " << V(i, 2) << ")";
      throw Error(ErrorCode::NonFinite, s.str());
    }
}

/// The mesh being decimated and the queue of collapses.
///
/// The queue holds one valid entry per vertex u that has a legal collapse (older entries are
/// recognised by their version): the cost (Angle::key) of u's cheapest collapse, whose target
/// is target_[u]. The cost of u -> v depends only on the faces around u (their vertices, normals
/// and cones) and, for a boundary u, on the boundary edges next to u; a collapse changes those
/// only for the kept vertex and the removed vertex's neighbours, which collapse() evaluates
/// again. Elsewhere a collapse can only make a queued collapse illegal (the link condition of
/// a vertex two edges away, a component reaching the minimum size): a popped entry is evaluated
/// again, and done only if it is still legal at the same cost (otherwise u is evaluated again).
class Decimator
{
public:
  Decimator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

  /// Fills the queue with every vertex's best collapse.
  void queue_all(const ProgressCallback& progress);
  /// Collapses until @p target vertices remain or no legal collapse is left.
  void run(Index target, const ProgressCallback& progress);
  LandmarkDecimation result() const;

private:
  /// A face of the mesh being decimated (kept together: they are read together).
  struct Face
  {
    std::array<int, 3> vertices;
    bool alive;
    Vec3 unit_normal; ///< zero for a degenerate face
    Cone cone;
  };

  /// Faces that hold u and v (the faces removed by u -> v) and their third vertices.
  struct Removed
  {
    int count = 0;
    std::array<int, 2> face{ -1, -1 };
    std::array<int, 2> opposite{ -1, -1 };
  };
  /// A face (u, a, b) around the vertex u whose collapses are being evaluated, with what
  /// evaluate() reads of it, copied together.
  struct FanFace
  {
    int face, a, b;
    Vec3 pa, pb;        ///< positions of a and b
    double ab2;         ///< |b - a|^2
    Vec3 unit_normal;
    Cone cone;
  };

  Vec3 normal(int a, int b, int c) const { return (P_[b] - P_[a]).cross(P_[c] - P_[a]); }
  /// Whether the triangle (a, b, c) is degenerate (see degenerate_ratio); @p n is its normal.
  bool degenerate(const Vec3& n, int a, int b, int c) const
  {
    const double longest = std::max({ (P_[b] - P_[a]).squaredNorm(),
      (P_[c] - P_[b]).squaredNorm(), (P_[a] - P_[c]).squaredNorm() });
    return !(n.squaredNorm() > degenerate_ratio * degenerate_ratio * longest * longest);
  }
  /// Sets the unit normal of face f from its vertices (zero if f is degenerate).
  void set_unit_normal(int f)
  {
    const auto& t = faces_[f].vertices;
    const Vec3 n = normal(t[0], t[1], t[2]);
    faces_[f].unit_normal = degenerate(n, t[0], t[1], t[2]) ? Vec3::Zero() : unit(n);
  }
  static bool has(const std::array<int, 3>& t, int x)
  {
    return t[0] == x || t[1] == x || t[2] == x;
  }
  bool can_collapse(int u) const
  {
    return alive_[u] && component_size_[component_[u]] > min_component_vertices;
  }
  /// Marks the neighbours of u with a new mark_stamp_ and lists them in neighbours_.
  void mark_neighbours(int u);
  /// mark_neighbours(u), and u's faces into fan_.
  void load_fan(int u);
  /// Faces around u that hold v. False if that is not what a manifold edge uv has.
  bool removed_faces(int u, int v, bool boundary_edge, Removed& removed) const;
  /// Legality and cost of u -> v, with u's fan loaded by load_fan(u). Returns false when
  /// illegal or when the cost's key exceeds @p bound (then @p cost is meaningless).
  bool evaluate(int u, int v, double bound, Angle& cost);
  /// Recomputes u's best collapse and queues it (a new version invalidates older entries).
  void update(int u);
  /// Adds @p c to the queue; drops the outdated entries when they are more than half of it.
  void push(const Candidate& c);
  /// Performs u -> v (legal) and updates the queue.
  void collapse(int u, int v, const Angle& cost);

  std::vector<Vec3> P_;
  std::vector<Face> faces_;
  std::vector<char> flipped_; ///< faces turned over to orient the mesh (turned back in result())
  std::vector<std::vector<int>> faces_of_; ///< the live faces around each vertex
  std::vector<char> alive_, on_boundary_;
  std::vector<int> next_, previous_;       ///< along the boundary loop (-1 inside)
  std::vector<Cone> edge_cone_;            ///< directions of the boundary edge v -> next_[v]
  std::vector<int> component_;
  std::vector<Index> component_size_;
  std::vector<std::uint32_t> version_;     ///< of each vertex's valid queue entry
  std::vector<int> target_;                ///< its target (-1: none)
  std::vector<std::uint32_t> mark_, seen_;
  std::uint32_t mark_stamp_ = 0, seen_stamp_ = 0;
  std::vector<int> neighbours_, update_;
  std::vector<FanFace> fan_;
  std::vector<Candidate> queue_; ///< a binary heap by CostlierThan (top: front)
  Index alive_count_ = 0, collapses_ = 0;
  double max_cost_ = 0.0;
};

Decimator::Decimator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F)
{
  const int n = static_cast<int>(V.rows());
  const int m = static_cast<int>(F.rows());
  P_.resize(n);
  for (int i = 0; i < n; ++i)
    P_[i] = V.row(i).transpose();
  faces_.resize(m);
  faces_of_.resize(n);
  for (int f = 0; f < m; ++f)
  {
    faces_[f].vertices = { F(f, 0), F(f, 1), F(f, 2) };
    for (int x : faces_[f].vertices)
      faces_of_[x].push_back(f);
  }
  for (int i = 0; i < n; ++i)
    if (faces_of_[i].empty())
      throw Error(ErrorCode::InvalidArgument,
        "mesh vertex " + std::to_string(i) +
          " belongs to no face; remove unreferenced vertices first");

  // Halfedges sorted by edge (low, high vertex), then face and corner (the halfedge's start).
  struct Halfedge
  {
    std::uint64_t edge;
    int corner; ///< 3 face + corner
    int low() const { return static_cast<int>(edge >> 32); }
    int high() const { return static_cast<int>(edge & 0xffffffffu); }
  };
  // Bucketed by the low vertex, then each bucket sorted.
  std::vector<int> bucket(static_cast<std::size_t>(n) + 1, 0);
  for (int f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k)
      ++bucket[std::min(faces_[f].vertices[k], faces_[f].vertices[(k + 1) % 3]) + 1];
  std::partial_sum(bucket.begin(), bucket.end(), bucket.begin());
  std::vector<Halfedge> halfedges(static_cast<std::size_t>(m) * 3);
  {
    std::vector<int> fill(bucket.begin(), bucket.end() - 1);
    for (int f = 0; f < m; ++f)
      for (int k = 0; k < 3; ++k)
      {
        const auto a = static_cast<std::uint64_t>(faces_[f].vertices[k]);
        const auto b = static_cast<std::uint64_t>(faces_[f].vertices[(k + 1) % 3]);
        halfedges[fill[std::min(a, b)]++] = { std::min(a, b) << 32 | std::max(a, b), 3 * f + k };
      }
  }
  for (int x = 0; x < n; ++x)
    std::sort(halfedges.begin() + bucket[x], halfedges.begin() + bucket[x + 1],
      [](const Halfedge& p, const Halfedge& q) {
        return p.edge != q.edge ? p.edge < q.edge : p.corner < q.corner;
      });
  // The edges in two faces (interior) and in one (boundary).
  struct Interior
  {
    int low, high, f, g;
    bool same_direction; ///< f and g traverse the edge the same way
  };
  struct Boundary
  {
    int low, high, f;
  };
  std::vector<Interior> interior;
  std::vector<Boundary> boundary;
  interior.reserve(halfedges.size() / 2);
  // Corner c = 3 f + k holds faces_[f].vertices[k]; the halfedge at c goes to the next corner.
  auto start = [&](int c) { return faces_[c / 3].vertices[c % 3]; };
  for (std::size_t i = 0; i < halfedges.size();)
  {
    std::size_t j = i + 1;
    while (j < halfedges.size() && halfedges[j].edge == halfedges[i].edge)
      ++j;
    const Halfedge& h = halfedges[i];
    if (j - i >= 3)
    {
      std::string faces;
      for (std::size_t k = i; k < j && k < i + 6; ++k)
        faces += (k > i ? ", " : "") + std::to_string(halfedges[k].corner / 3);
      if (j - i > 6)
        faces += ", ...";
      throw Error(ErrorCode::InvalidArgument,
        "edge (" + std::to_string(h.low()) + ", " + std::to_string(h.high()) + ") is shared by " +
          std::to_string(j - i) + " faces (" + faces +
          "): the mesh must be edge-manifold (every edge in one or two faces)");
    }
    if (j - i == 2)
    {
      const Halfedge& g = halfedges[i + 1];
      interior.push_back({ h.low(), h.high(), h.corner / 3, g.corner / 3,
        start(h.corner) == start(g.corner) });
    }
    else
      boundary.push_back({ h.low(), h.high(), h.corner / 3 });
    i = j;
  }

  // Orientation: two faces that traverse their shared edge the same way disagree. Faces are
  // flipped (internally) so that none disagree, component by component from its lowest face,
  // which keeps its orientation; a disagreement that remains means the component cannot be
  // oriented.
  {
    std::vector<int> first(static_cast<std::size_t>(m) + 1, 0);
    for (const Interior& e : interior)
    {
      ++first[e.f + 1];
      ++first[e.g + 1];
    }
    std::partial_sum(first.begin(), first.end(), first.begin());
    std::vector<int> across(2 * interior.size());
    {
      std::vector<int> fill(first.begin(), first.end() - 1);
      for (std::size_t e = 0; e < interior.size(); ++e)
      {
        across[fill[interior[e].f]++] = static_cast<int>(e);
        across[fill[interior[e].g]++] = static_cast<int>(e);
      }
    }
    flipped_.assign(m, 0);
    std::vector<char> visited(m, 0);
    std::vector<int> stack;
    for (int root = 0; root < m; ++root)
    {
      if (visited[root])
        continue;
      visited[root] = 1;
      stack.push_back(root);
      while (!stack.empty())
      {
        const int f = stack.back();
        stack.pop_back();
        for (int i = first[f]; i < first[f + 1]; ++i)
        {
          const Interior& e = interior[across[i]];
          const int g = e.f == f ? e.g : e.f;
          const char flip = static_cast<char>(flipped_[f] ^ (e.same_direction ? 1 : 0));
          if (!visited[g])
          {
            visited[g] = 1;
            flipped_[g] = flip;
            stack.push_back(g);
          }
          else if (flipped_[g] != flip)
            throw Error(ErrorCode::InvalidArgument,
              "the mesh is not orientable (it contains a Moebius strip): its faces cannot be "
              "oriented consistently, e.g. across edge (" +
                std::to_string(e.low) + ", " + std::to_string(e.high) + ") of faces " +
                std::to_string(e.f) + " and " + std::to_string(e.g));
        }
      }
    }
    for (int f = 0; f < m; ++f)
      if (flipped_[f])
        std::swap(faces_[f].vertices[1], faces_[f].vertices[2]);
  }

  // Corners (f, k) around the same vertex joined across interior edges: one set per fan.
  auto corner = [&](int f, int x) {
    const auto& t = faces_[f].vertices;
    return 3 * f + (t[0] == x ? 0 : (t[1] == x ? 1 : 2));
  };
  DisjointSets corners(static_cast<std::size_t>(m) * 3);
  for (const Interior& e : interior)
  {
    corners.unite(corner(e.f, e.low), corner(e.g, e.low));
    corners.unite(corner(e.f, e.high), corner(e.g, e.high));
  }
  // Boundary loops, in the direction of the (oriented) faces.
  next_.assign(n, -1);
  previous_.assign(n, -1);
  for (const Boundary& e : boundary)
  {
    const auto& t = faces_[e.f].vertices;
    const int k = corner(e.f, e.low) % 3;
    const bool forward = t[(k + 1) % 3] == e.high;
    const int a = forward ? e.low : e.high, b = forward ? e.high : e.low;
    if (next_[a] < 0) // a second boundary edge out of a is a pinch, refused below
      next_[a] = b;
    if (previous_[b] < 0)
      previous_[b] = a;
  }
  for (int x = 0; x < n; ++x)
  {
    int root = -1;
    for (int f : faces_of_[x])
    {
      const int k = faces_[f].vertices[0] == x ? 0 : (faces_[f].vertices[1] == x ? 1 : 2);
      const int r = corners.find(3 * f + k);
      if (root >= 0 && r != root)
        throw Error(ErrorCode::InvalidArgument,
          "mesh vertex " + std::to_string(x) +
            " is non-manifold: its faces form more than one fan (faces " +
            std::to_string(faces_of_[x].front()) + " and " + std::to_string(f) +
            " meet only at this vertex); the mesh must be vertex-manifold");
      root = r;
    }
  }

  on_boundary_.assign(n, 0);
  edge_cone_.resize(n);
  for (int x = 0; x < n; ++x)
    if (next_[x] >= 0)
    {
      on_boundary_[x] = 1;
      edge_cone_[x] = cone_of(P_[next_[x]] - P_[x]);
    }
  for (int f = 0; f < m; ++f)
  {
    faces_[f].alive = true;
    set_unit_normal(f);
    faces_[f].cone = cone_of(faces_[f].unit_normal);
  }

  DisjointSets vertices(n);
  for (int f = 0; f < m; ++f)
  {
    vertices.unite(faces_[f].vertices[0], faces_[f].vertices[1]);
    vertices.unite(faces_[f].vertices[0], faces_[f].vertices[2]);
  }
  component_.resize(n);
  component_size_.assign(n, 0);
  for (int x = 0; x < n; ++x)
  {
    component_[x] = vertices.find(x);
    ++component_size_[component_[x]];
  }

  alive_.assign(n, 1);
  alive_count_ = n;
  version_.assign(n, 0);
  target_.assign(n, -1);
  mark_.assign(n, 0);
  seen_.assign(n, 0);
}

void Decimator::mark_neighbours(int u)
{
  ++mark_stamp_;
  neighbours_.clear();
  for (int f : faces_of_[u])
    for (int w : faces_[f].vertices)
      if (w != u && mark_[w] != mark_stamp_)
      {
        mark_[w] = mark_stamp_;
        neighbours_.push_back(w);
      }
}

void Decimator::load_fan(int u)
{
  mark_neighbours(u);
  fan_.clear();
  for (int f : faces_of_[u])
  {
    const auto& t = faces_[f].vertices;
    const int k = t[0] == u ? 0 : (t[1] == u ? 1 : 2);
    const int a = t[(k + 1) % 3], b = t[(k + 2) % 3];
    fan_.push_back({ f, a, b, P_[a], P_[b], (P_[b] - P_[a]).squaredNorm(), faces_[f].unit_normal,
      faces_[f].cone });
  }
}

bool Decimator::removed_faces(int u, int v, bool boundary_edge, Removed& removed) const
{
  for (int f : faces_of_[u])
    if (has(faces_[f].vertices, v))
    {
      if (removed.count == 2)
        return false;
      const auto& t = faces_[f].vertices;
      removed.face[removed.count] = f;
      removed.opposite[removed.count] =
        t[0] != u && t[0] != v ? t[0] : (t[1] != u && t[1] != v ? t[1] : t[2]);
      ++removed.count;
    }
  return removed.count == (boundary_edge ? 1 : 2);
}

bool Decimator::evaluate(int u, int v, double bound, Angle& cost)
{
  if (!alive_[v])
    return false;
  // A boundary vertex moves only along its boundary edges.
  const bool boundary_edge = on_boundary_[u] != 0;
  if (boundary_edge && v != next_[u] && v != previous_[u])
    return false;
  Removed removed;
  std::array<const Cone*, 2> removed_cone{ nullptr, nullptr };
  for (const FanFace& q : fan_)
    if (q.a == v || q.b == v)
    {
      if (removed.count == 2)
        return false;
      removed.face[removed.count] = q.face;
      removed.opposite[removed.count] = q.a == v ? q.b : q.a;
      removed_cone[removed.count] = &q.cone;
      ++removed.count;
    }
  if (removed.count != (boundary_edge ? 1 : 2))
    return false;

  // Changed faces (u, a, b) -> (v, a, b): not degenerate, not folded, and their cost.
  const Vec3& pv = P_[v];
  cost = Angle{};
  for (const FanFace& q : fan_)
  {
    if (q.face == removed.face[0] || q.face == removed.face[1])
      continue;
    if (q.cone.half.key > bound)
      return false; // the cost is at least the half-angle
    const Vec3 ea = q.pa - pv, eb = q.pb - pv;
    const Vec3 n = ea.cross(eb);
    const double longest = std::max({ ea.squaredNorm(), eb.squaredNorm(), q.ab2 });
    if (!(n.squaredNorm() > degenerate_ratio * degenerate_ratio * longest * longest))
      return false;
    if (!(n.dot(q.unit_normal) > 0.0) && q.unit_normal.squaredNorm() > 0.0)
      return false; // a turn of 90 degrees or more
    const Vec3 m = n / std::sqrt(n.squaredNorm());
    cost = max_angle(cost, farthest_angle(m, q.cone));
    for (int k = 0; k < removed.count; ++k)
      if (q.a == removed.opposite[k] || q.b == removed.opposite[k])
        cost = max_angle(cost, farthest_angle(m, *removed_cone[k]));
    if (cost.key > bound)
      return false;
  }

  // Link condition: the common neighbours of u and v are the removed faces' third vertices.
  ++seen_stamp_;
  int common = 0;
  for (int g : faces_of_[v])
    for (int w : faces_[g].vertices)
      if (w != v && mark_[w] == mark_stamp_ && seen_[w] != seen_stamp_)
      {
        seen_[w] = seen_stamp_;
        if (++common > removed.count)
          return false;
      }
  if (common != removed.count)
    return false;

  if (boundary_edge)
  {
    // Along p -> u -> v the new edge is p -> v; along v -> u -> q it is v -> q.
    const bool forward = v == next_[u];
    const int from = forward ? previous_[u] : v;
    const int to = forward ? v : next_[u];
    const Vec3 direction = unit(P_[to] - P_[from]);
    cost = max_angle(cost, farthest_angle(direction, edge_cone_[from]));
    cost = max_angle(cost, farthest_angle(direction, edge_cone_[u]));
  }
  return cost.key <= bound;
}

void Decimator::update(int u)
{
  ++version_[u];
  if (!can_collapse(u))
  {
    target_[u] = -1;
    return;
  }
  load_fan(u);
  // The previous best target first: its cost is usually still low and bounds the others.
  const auto previous = std::find(neighbours_.begin(), neighbours_.end(), target_[u]);
  if (previous != neighbours_.end())
    std::iter_swap(neighbours_.begin(), previous);
  double best = std::numeric_limits<double>::infinity();
  double best_length2 = std::numeric_limits<double>::infinity();
  int best_v = -1;
  for (int v : neighbours_)
  {
    Angle cost;
    if (!evaluate(u, v, best, cost))
      continue;
    const double length2 = (P_[static_cast<std::size_t>(v)] - P_[static_cast<std::size_t>(u)]).squaredNorm();
    if (cost.key < best ||
      (cost.key == best && (length2 < best_length2 || (length2 == best_length2 && v < best_v))))
    {
      best = cost.key;
      best_length2 = length2;
      best_v = v;
    }
  }
  target_[u] = best_v;
  if (best_v >= 0)
    push({ best, best_length2, u, version_[u] });
}

void Decimator::collapse(int u, int v, const Angle& cost)
{
  const bool boundary_edge = on_boundary_[u] != 0;
  Removed removed;
  removed_faces(u, v, boundary_edge, removed);
  // u's neighbours: their faces change (as do v's), so their collapses are evaluated again.
  mark_neighbours(u);
  update_ = neighbours_;

  // Changed faces: merge the cones of the adjacent removed faces and the new normal.
  for (int f : faces_of_[u])
  {
    if (f == removed.face[0] || f == removed.face[1])
      continue;
    Cone c = faces_[f].cone;
    for (int k = 0; k < removed.count; ++k)
      if (has(faces_[f].vertices, removed.opposite[k]))
        c = merge(c, faces_[removed.face[k]].cone);
    for (int& x : faces_[f].vertices)
      if (x == u)
        x = v;
    set_unit_normal(f);
    faces_[f].cone = merge(c, cone_of(faces_[f].unit_normal));
    faces_of_[v].push_back(f);
  }
  for (int k = 0; k < removed.count; ++k)
  {
    const int r = removed.face[k];
    faces_[r].alive = false;
    for (int x : { v, removed.opposite[k] })
    {
      auto& list = faces_of_[x];
      list.erase(std::find(list.begin(), list.end(), r));
    }
  }
  std::vector<int>().swap(faces_of_[u]);

  if (boundary_edge)
  {
    const bool forward = v == next_[u];
    const int from = forward ? previous_[u] : v;
    const int to = forward ? v : next_[u];
    edge_cone_[from] =
      merge(merge(edge_cone_[from], edge_cone_[u]), cone_of(P_[to] - P_[from]));
    next_[from] = to;
    previous_[to] = from;
    next_[u] = previous_[u] = -1;
  }
  alive_[u] = 0;
  ++version_[u];
  --alive_count_;
  --component_size_[component_[u]];
  ++collapses_;
  max_cost_ = std::max(max_cost_, cost.radians());

  // No other collapse changes cost: the faces around other vertices keep their geometry and
  // their cones. Some may have become illegal (link condition); that is seen when they are
  // popped.
  for (int x : update_)
    update(x);
}

void Decimator::push(const Candidate& c)
{
  queue_.push_back(c);
  std::push_heap(queue_.begin(), queue_.end(), CostlierThan{});
  if (queue_.size() > 1024 && static_cast<Index>(queue_.size()) > 2 * alive_count_)
  {
    // At most one entry per live vertex is current: keep those (the order of equal entries
    // does not matter, CostlierThan is a total order on them).
    queue_.erase(std::remove_if(queue_.begin(), queue_.end(),
                   [this](const Candidate& e) {
                     return !alive_[e.u] || e.version != version_[e.u];
                   }),
      queue_.end());
    std::make_heap(queue_.begin(), queue_.end(), CostlierThan{});
  }
}

void Decimator::queue_all(const ProgressCallback& progress)
{
  const int n = static_cast<int>(P_.size());
  ProgressReporter reporter(progress, n, 0.0, 0.1);
  for (int x = 0; x < n; ++x)
  {
    update(x);
    if (!reporter.step())
      reporter.throw_if_cancelled(what_cancelled);
  }
}

void Decimator::run(Index target, const ProgressCallback& progress)
{
  ProgressReporter reporter(progress, alive_count_ - target, 0.1, 1.0);
  while (alive_count_ > target && !queue_.empty())
  {
    const Candidate top = queue_.front();
    std::pop_heap(queue_.begin(), queue_.end(), CostlierThan{});
    queue_.pop_back();
    if (!alive_[top.u] || top.version != version_[top.u])
      continue;
    if (!can_collapse(top.u))
    {
      update(top.u);
      continue;
    }
    const int v = target_[top.u];
    load_fan(top.u);
    Angle cost;
    if (!evaluate(top.u, v, std::numeric_limits<double>::infinity(), cost) ||
      cost.key != top.cost)
    {
      update(top.u); // its cost rose or it became illegal: queue its current best instead
      continue;
    }
    collapse(top.u, v, cost);
    if (!reporter.step())
      reporter.throw_if_cancelled(what_cancelled);
  }
  if (!reporter.finish())
    reporter.throw_if_cancelled(what_cancelled);
}

LandmarkDecimation Decimator::result() const
{
  LandmarkDecimation out;
  out.landmarks.reserve(static_cast<std::size_t>(alive_count_));
  for (int x = 0; x < static_cast<int>(alive_.size()); ++x)
    if (alive_[x])
      out.landmarks.push_back(x);
  const auto faces =
    std::count_if(faces_.begin(), faces_.end(), [](const Face& f) { return f.alive; });
  out.faces.resize(faces, 3);
  Index row = 0;
  for (std::size_t f = 0; f < faces_.size(); ++f)
    if (faces_[f].alive)
    {
      for (int k = 0; k < 3; ++k)
        out.faces(row, k) = faces_[f].vertices[k];
      if (flipped_[f])
        std::swap(out.faces(row, 1), out.faces(row, 2));
      ++row;
    }
  out.collapses = collapses_;
  out.max_normal_deviation = max_cost_;
  return out;
}

} // namespace

LandmarkDecimation decimation_landmarks(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
  const LandmarkDecimationOptions& options, const ProgressCallback& progress)
{
  validate_input(V, F, options);
  Decimator decimator(V, F);
  decimator.queue_all(progress);
  decimator.run(options.target_vertices, progress);
  return decimator.result();
}

} // namespace bary
