// Studies of bounded biharmonic weights against the paper (Jacobson et al. 2011) and of their
// solver, printed as Markdown tables for docs/bounded-biharmonic-weights.md and
// docs/benchmarks.md:
//
//   bbw_study lumping   Voronoi (§3.4) against barycentric mass lumping on the bundled cages
//                       (data/cage2d.obj, data/cage3d.obj: cage-vertex handles) and libigl's
//                       knight (7 bones; its MATLAB active-set weights as the reference):
//                       max / mean |W_voronoi - W_barycentric|, the Laplacian energy, the
//                       support, the solve time, the distance to the MATLAB weights.
//   bbw_study maxima [--handles N] [--seed S] [--levels A,B,...] [--tolerance T] [--3d]
//                       Fig. 16: N random point handles (default 50, seed 2011) in the unit
//                       square meshed by CGAL (mesh_polygon, handles inserted as Steiner
//                       points) at each target triangle count (default 1000,4000,16000);
//                       bounded (fast and coupled) and unbounded weights; for every handle's
//                       weight the strict local maxima (value above every 1-ring neighbour
//                       by more than T, default 1e-8, and above T; the handle's own vertex
//                       excluded) and minima (below every neighbour by more than T), split
//                       into interior and boundary vertices, with the largest prominence of a
//                       maximum. --3d: the same in the unit cube instead (TetGen at 5,000
//                       and 20,000 tetrahedra requested unless --levels; bounded fast and
//                       unbounded).
//                       --barycentric: barycentric lumping instead of Voronoi; --raw: the
//                       fast mode's weights before normalization.
//   bbw_study interior [--mesh NAME] [--mu A,B,...]
//                       The fast mode's QPs (Eq. 8 subject to Eq. 6, one per handle: BBW's
//                       energy matrix with the default Voronoi lumping and tolerance) on
//                       libigl's NAME (default hand; ../shared/data/igl/NAME.mesh / .tgf,
//                       handles by libigl's rule): the active-set solver (BoxConstrainedQP)
//                       from its default start, against a primal-dual interior-point method
//                       (Mehrotra's predictor-corrector on 0 <= w <= 1 over the unknown rows,
//                       one supernodal factorization of Q(U, U) + diag per iteration, one AMD
//                       ordering) run until its mean complementarity mu / s_y <= A (each level
//                       of --mu, default 1e-10,1e-12,1e-14,1e-16,1e-18), then the active-set
//                       solver started from the interior point's active set (w < z / s_y:
//                       lower; 1 - w < s / s_y: upper): does a good interior point shorten the
//                       active-set iterations, and what does an interior-point iteration cost?
#include "core/coordinates/bbw.h"
#include "core/meshing/domain_mesh.h"
#include "core/solvers/box_constrained_qp.h"
#include "core/solvers/fem_operators.h"
#include "core/solvers/sparse_cholesky.h"

#include "cage_catalogue.h"
#include "igl_formats.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <queue>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace
{
using namespace bary;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t)
{
  return std::chrono::duration<double>(Clock::now() - t).count();
}

std::vector<std::set<int>> one_rings(Index n, const Eigen::MatrixXi& T)
{
  std::vector<std::set<int>> ring(static_cast<std::size_t>(n));
  for (Index t = 0; t < T.rows(); ++t)
    for (Index a = 0; a < T.cols(); ++a)
      for (Index b = 0; b < T.cols(); ++b)
        if (a != b)
          ring[static_cast<std::size_t>(T(t, a))].insert(T(t, b));
  return ring;
}

/// Prominence of the local maximum of w at v: w(v) minus the highest level at which a path
/// from v reaches a larger value (w(v) + 1 when none: the global maximum).
double prominence(const Eigen::VectorXd& w, const std::vector<std::set<int>>& ring, int v)
{
  std::vector<double> best(static_cast<std::size_t>(w.size()), -1e300);
  std::priority_queue<std::pair<double, int>> queue;
  best[static_cast<std::size_t>(v)] = w(v);
  queue.push({ w(v), v });
  while (!queue.empty())
  {
    const auto [level, a] = queue.top();
    queue.pop();
    if (level < best[static_cast<std::size_t>(a)])
      continue;
    if (w(a) > w(v))
      return w(v) - level;
    for (const int c : ring[static_cast<std::size_t>(a)])
    {
      const double through = std::min(level, w(c));
      if (through > best[static_cast<std::size_t>(c)])
      {
        best[static_cast<std::size_t>(c)] = through;
        queue.push({ through, c });
      }
    }
  }
  return w(v) + 1.0;
}

struct ExtremaCount
{
  int max_interior = 0, max_boundary = 0, min_interior = 0, min_boundary = 0;
  int handles_with_max = 0;   ///< handles whose weight has at least one spurious maximum
  double largest_prominence = 0, largest_value = 0;
};

ExtremaCount count_extrema(const DenseWeights& W, const std::vector<std::set<int>>& ring,
  const std::vector<char>& boundary, const Eigen::VectorXi& handle_vertex, double tol)
{
  ExtremaCount c;
  for (Index j = 0; j < W.cols(); ++j)
  {
    const Eigen::VectorXd w = W.col(j);
    bool any = false;
    for (Index v = 0; v < w.size(); ++v)
    {
      if (j < handle_vertex.size() && v == handle_vertex(j))
        continue;
      bool is_max = w(v) > tol, is_min = true;
      for (const int u : ring[static_cast<std::size_t>(v)])
      {
        is_max = is_max && w(v) > w(u) + tol;
        is_min = is_min && w(v) < w(u) - tol;
      }
      const bool b = boundary[static_cast<std::size_t>(v)] != 0;
      if (is_max)
      {
        any = true;
        (b ? c.max_boundary : c.max_interior)++;
        const double p = prominence(w, ring, static_cast<int>(v));
        c.largest_prominence = std::max(c.largest_prominence, p > 1.0 ? w(v) : p);
        c.largest_value = std::max(c.largest_value, w(v));
      }
      if (is_min)
        (b ? c.min_boundary : c.min_interior)++;
    }
    c.handles_with_max += any;
  }
  return c;
}

/// A comma-separated list of integers or numbers.
template<typename T>
std::vector<T> parse_list(const std::string& s)
{
  std::vector<T> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ','))
  {
    std::size_t used = 0;
    try
    {
      if constexpr (std::is_integral_v<T>)
        out.push_back(static_cast<T>(std::stoi(item, &used)));
      else
        out.push_back(static_cast<T>(std::stod(item, &used)));
    }
    catch (const std::logic_error&)
    {
      used = 0;
    }
    if (used == 0 || used != item.size())
      throw std::invalid_argument("'" + item + "' in the list '" + s + "' is not a number");
  }
  return out;
}

void print_extrema_row(const std::string& domain, Index vertices, Index cells, const char* method,
  const BBWResult& r, const ExtremaCount& c, double seconds)
{
  std::printf("| %s | %lld | %lld | %s | %d + %d | %d | %.3g | %.3g | %d + %d | %.3g | %.3g | %.1f |\n",
    domain.c_str(), static_cast<long long>(vertices), static_cast<long long>(cells), method,
    c.max_interior, c.max_boundary, c.handles_with_max, c.largest_value, c.largest_prominence,
    c.min_interior, c.min_boundary, Eigen::MatrixXd(r.W).minCoeff(), Eigen::MatrixXd(r.W).maxCoeff(),
    seconds);
  std::fflush(stdout);
}

/// Study variants (command-line switches): the lumping, and the fast weights before
/// normalization (--raw: each handle's QP solution as it is).
BBWMassLumping study_lumping = BBWMassLumping::Voronoi;
bool study_raw = false;

void run_methods(const std::string& domain, const Eigen::MatrixXd& V, const Eigen::MatrixXi& T,
  const std::vector<int>& boundary_list, const Eigen::VectorXi& handle_vertex, double tol,
  bool coupled)
{
  BBWHandles h;
  h.point_vertex = handle_vertex;
  std::vector<char> boundary(static_cast<std::size_t>(V.rows()), 0);
  for (const int v : boundary_list)
    boundary[static_cast<std::size_t>(v)] = 1;
  const auto ring = one_rings(V.rows(), T);
  struct Method
  {
    const char* name;
    BBWMode mode;
    bool bounded;
  };
  std::vector<Method> methods = { { "bounded, fast", BBWMode::Fast, true } };
  if (coupled)
    methods.push_back({ "bounded, coupled", BBWMode::Coupled, true });
  methods.push_back({ "unbounded", BBWMode::Fast, false });
  for (const Method& m : methods)
  {
    BBWOptions o; // tolerances 1e-10
    o.mode = m.mode;
    o.bounded = m.bounded;
    o.mass_lumping = study_lumping;
    o.normalize = !(study_raw && m.mode == BBWMode::Fast);
    const auto start = Clock::now();
    const BBWResult r = bounded_biharmonic_weights(V, T, h, o);
    const double seconds = seconds_since(start);
    print_extrema_row(domain, V.rows(), T.rows(), m.name, r,
      count_extrema(r.W, ring, boundary, handle_vertex, tol), seconds);
  }
}

int maxima(int argc, char** argv)
{
  int handles = 50;
  unsigned seed = 2011;
  double tol = 1e-8;
  bool three_d = false, levels_given = false;
  std::vector<int> levels = { 1000, 4000, 16000 };
  for (int a = 2; a < argc; ++a)
  {
    const std::string arg = argv[a];
    if (arg == "--handles" && a + 1 < argc)
      handles = std::stoi(argv[++a]);
    else if (arg == "--seed" && a + 1 < argc)
      seed = static_cast<unsigned>(std::stoul(argv[++a]));
    else if (arg == "--levels" && a + 1 < argc)
    {
      levels = parse_list<int>(argv[++a]);
      levels_given = true;
    }
    else if (arg == "--tolerance" && a + 1 < argc)
      tol = std::stod(argv[++a]);
    else if (arg == "--3d")
      three_d = true;
    else if (arg == "--barycentric")
      study_lumping = BBWMassLumping::Barycentric;
    else if (arg == "--raw")
      study_raw = true;
    else
    {
      std::cerr << "unknown argument " << arg << "\n";
      return 2;
    }
  }
  std::printf("%d random point handles (std::mt19937 seed %u, uniform in the open unit "
              "square or cube), %s lumping%s, tolerance %g\n\n",
    handles, seed, study_lumping == BBWMassLumping::Voronoi ? "Voronoi" : "barycentric",
    study_raw ? ", fast weights before normalization" : "", tol);
  std::printf("| domain | vertices | cells | weights | spurious maxima (interior + boundary) | "
              "handles with one | largest such max | largest prominence | strict minima "
              "(interior + boundary) | min w | max w | seconds |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  if (three_d)
  {
    for (const int level : levels_given ? levels : std::vector<int>{ 5000, 20000 })
    {
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> u(0.0, 1.0);
      SurfaceMeshOptions o;
      o.target_cells = level;
      o.steiner_points.resize(handles, 3);
      for (int k = 0; k < handles; ++k)
      {
        const double x = u(rng), y = u(rng), z = u(rng);
        o.steiner_points.row(k) << x, y, z;
      }
      Cage cube = test::unit_cube(); // [0, 1]^3 or [-1, 1]^3: mapped onto [0, 1]^3
      const double lo = cube.V.minCoeff(), hi = cube.V.maxCoeff();
      cube.V = (cube.V.array() - lo) / (hi - lo);
      const DomainMesh mesh = mesh_closed_surface(cube, o);
      std::set<int> distinct(mesh.steiner_vertex.data(), mesh.steiner_vertex.data() + handles);
      if (distinct.count(-1) || static_cast<int>(distinct.size()) != handles)
      {
        std::cerr << "a handle point was skipped or merged in the cube at level " << level << "\n";
        return 1;
      }
      run_methods("cube", mesh.V, mesh.T, mesh.boundary_vertices, mesh.steiner_vertex, tol, false);
    }
    return 0;
  }
  for (const int level : levels)
  {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    PolygonMeshOptions o;
    o.target_cells = level;
    o.steiner_points.resize(handles, 2);
    for (int k = 0; k < handles; ++k)
    {
      const double x = u(rng), y = u(rng);
      o.steiner_points.row(k) << x, y;
    }
    const DomainMesh mesh = mesh_polygon(test::unit_square(), o);
    std::set<int> distinct(mesh.steiner_vertex.data(), mesh.steiner_vertex.data() + handles);
    if (distinct.count(-1) || static_cast<int>(distinct.size()) != handles)
    {
      std::cerr << "a handle point was skipped or merged at level " << level << "\n";
      return 1;
    }
    run_methods("square", mesh.V, mesh.T, mesh.boundary_vertices, mesh.steiner_vertex, tol, true);
  }
  return 0;
}

// --- lumping ----------------------------------------------------------------------------------

struct Problem
{
  std::string name;
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  BBWHandles handles;
  Eigen::MatrixXd reference; ///< MATLAB weights (before normalization) or empty
};

Problem cage_problem(const std::string& name, const DomainMesh& mesh, Index controls)
{
  Problem p;
  p.name = name;
  p.V = mesh.V;
  p.T = mesh.T;
  p.handles.extra_handles = controls;
  p.handles.fixed_vertices = Eigen::Map<const Eigen::VectorXi>(
    mesh.boundary_vertices.data(), static_cast<Index>(mesh.boundary_vertices.size()));
  p.handles.fixed_values = DenseWeights(mesh.boundary_weights);
  return p;
}

/// A primal-dual interior point of min 1/2 w^T A w + b^T w subject to 0 <= w <= 1: w strictly
/// inside, z, s > 0 the multipliers of w >= 0 and w <= 1.
struct InteriorPoint
{
  Eigen::VectorXd w, z, s;
  int iterations = 0;
  double factor_seconds = 0, seconds = 0;
};

/// Mehrotra's predictor-corrector (one factorization of A + Z W^-1 + S (1 - W)^-1 per
/// iteration, two solves; one step length for primal and dual, 0.995 of the way to the
/// boundary) from w = 1/2, z = s = 0.1 s_y, until the mean complementarity is <= mu_stop * s_y.
InteriorPoint interior_point(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b,
  const Eigen::VectorXi& ordering, double sy, double mu_stop)
{
  const auto start = Clock::now();
  const Index n = A.rows();
  InteriorPoint p;
  p.w = Eigen::VectorXd::Constant(n, 0.5);
  p.z = Eigen::VectorXd::Constant(n, 0.1 * sy);
  p.s = p.z;
  SparseCholeskySettings settings;
  settings.ordering = ordering;
  settings.trusted = true;
  SparseCholesky factor(SparseCholesky::Backend::Supernodal);
  Eigen::SparseMatrix<double> H = A;
  auto complementarity = [&](const Eigen::VectorXd& w, const Eigen::VectorXd& z,
                           const Eigen::VectorXd& s) {
    return (w.dot(z) + (1.0 - w.array()).matrix().dot(s)) / (2.0 * static_cast<double>(n));
  };
  for (; p.iterations < 200; ++p.iterations)
  {
    Eigen::VectorXd& w = p.w;
    Eigen::VectorXd& z = p.z;
    Eigen::VectorXd& s = p.s;
    const double mu = complementarity(w, z, s);
    if (mu <= mu_stop * sy)
      break;
    const Eigen::VectorXd gap = (1.0 - w.array()).matrix();
    const Eigen::VectorXd residual = A * w + b - z + s;
    H = A;
    for (Index i = 0; i < n; ++i)
      H.coeffRef(i, i) += z(i) / w(i) + s(i) / gap(i);
    const auto t = Clock::now();
    factor.compute(H, Eigen::VectorXi(), settings);
    p.factor_seconds += seconds_since(t);
    // The Newton step for the targets w z = cz, (1 - w) s = cs.
    Eigen::VectorXd dw, dz, ds;
    auto direction = [&](const Eigen::VectorXd& cz, const Eigen::VectorXd& cs) {
      const Eigen::VectorXd rhs = -residual - cz.cwiseQuotient(w) + cs.cwiseQuotient(gap);
      dw = factor.solve(rhs);
      dz = (-cz - z.cwiseProduct(dw)).cwiseQuotient(w);
      ds = (-cs + s.cwiseProduct(dw)).cwiseQuotient(gap);
    };
    auto step_to_boundary = [&]() {
      double a = 1.0;
      for (Index i = 0; i < n; ++i)
      {
        if (dw(i) < 0.0)
          a = std::min(a, -w(i) / dw(i));
        if (dw(i) > 0.0)
          a = std::min(a, gap(i) / dw(i));
        if (dz(i) < 0.0)
          a = std::min(a, -z(i) / dz(i));
        if (ds(i) < 0.0)
          a = std::min(a, -s(i) / ds(i));
      }
      return a;
    };
    const Eigen::VectorXd wz = w.cwiseProduct(z), gs = gap.cwiseProduct(s);
    direction(wz, gs); // predictor (affine scaling)
    const double a_aff = step_to_boundary();
    const double mu_aff = complementarity(w + a_aff * dw, z + a_aff * dz, s + a_aff * ds);
    const double sigma = std::pow(mu_aff / mu, 3.0);
    const Eigen::VectorXd cz = (wz + dw.cwiseProduct(dz)).array() - sigma * mu;
    const Eigen::VectorXd cs = (gs - dw.cwiseProduct(ds)).array() - sigma * mu;
    direction(cz, cs); // corrector
    const double a = std::min(1.0, 0.995 * step_to_boundary());
    w += a * dw;
    z += a * dz;
    s += a * ds;
  }
  p.seconds = seconds_since(start);
  return p;
}

int interior(int argc, char** argv)
{
  std::string name = "hand";
  std::vector<double> levels = { 1e-10, 1e-12, 1e-14, 1e-16, 1e-18 };
  for (int a = 2; a < argc; ++a)
  {
    const std::string arg = argv[a];
    if (arg == "--mesh" && a + 1 < argc)
      name = argv[++a];
    else if (arg == "--mu" && a + 1 < argc)
      levels = parse_list<double>(argv[++a]);
    else
      throw std::invalid_argument("unknown argument " + arg);
  }
  for (const double level : levels)
    if (!(level > 0.0) || !std::isfinite(level))
      throw std::invalid_argument("--mu: every level must be finite and > 0");
  const std::string dir = std::string(BARYLAB_SHARED_DIR) + "/igl/";
  const auto mesh = test::read_medit_mesh(dir + name + ".mesh");
  const auto tgf = test::read_tgf(dir + name + ".tgf");
  const BBWHandles handles = handles_from_skeleton(mesh.V, tgf.C, Eigen::VectorXi(), tgf.E);
  const BBWBoundaryConditions bc = bbw_boundary_conditions(handles, mesh.V.rows());
  const BBWOptions defaults;
  const BoundedBiharmonicWeights bbw(mesh.V, mesh.T, defaults);
  const Eigen::SparseMatrix<double>& Q = bbw.energy_matrix();
  const Index n = Q.rows();

  // The unknown rows U and A = Q(U, U).
  std::vector<int> position(static_cast<std::size_t>(n), 0), unknown;
  for (Index k = 0; k < bc.vertices.size(); ++k)
    position[static_cast<std::size_t>(bc.vertices(k))] = -1;
  for (Index i = 0; i < n; ++i)
    if (position[static_cast<std::size_t>(i)] == 0)
    {
      position[static_cast<std::size_t>(i)] = static_cast<int>(unknown.size());
      unknown.push_back(static_cast<int>(i));
    }
  const Index nu = static_cast<Index>(unknown.size());
  std::vector<Eigen::Triplet<double>> entries;
  for (Index c = 0; c < n; ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(Q, c); it; ++it)
      if (position[static_cast<std::size_t>(c)] >= 0 && position[static_cast<std::size_t>(it.row())] >= 0)
        entries.emplace_back(position[static_cast<std::size_t>(it.row())], position[static_cast<std::size_t>(c)], it.value());
  Eigen::SparseMatrix<double> A(nu, nu);
  A.setFromTriplets(entries.begin(), entries.end());
  const Eigen::VectorXi ordering = fill_reducing_ordering(A);

  const BoxConstrainedQP qp(Q);
  BoxQPOptions box;
  box.tolerance = defaults.tolerance;
  box.backend = defaults.backend;
  const Index m = bc.values.cols();
  std::cout << "libigl's " << name << ": " << n << " vertices, " << nu << " unknown, " << m
            << " handles; BBW's Q, tolerance " << box.tolerance << ", one thread\n\n";

  // The active-set solver from its default start, per handle.
  const Eigen::VectorXd no_linear_term = Eigen::VectorXd::Zero(n); // Eq. 8 has none
  const Eigen::SparseMatrix<double> Q_abs = Q.cwiseAbs();
  std::vector<Eigen::VectorXd> bu(static_cast<std::size_t>(m)),
    lower(static_cast<std::size_t>(m)), upper(static_cast<std::size_t>(m));
  std::vector<double> sy(static_cast<std::size_t>(m));
  int pdas_iterations = 0, pdas_factorizations = 0;
  double pdas_seconds = 0, pdas_factor_seconds = 0;
  for (Index j = 0; j < m; ++j)
  {
    const auto ju = static_cast<std::size_t>(j);
    Eigen::VectorXd& l = lower[ju];
    Eigen::VectorXd& u = upper[ju];
    l = Eigen::VectorXd::Zero(n);
    u = Eigen::VectorXd::Ones(n);
    Eigen::VectorXd known = Eigen::VectorXd::Zero(n);
    for (Index k = 0; k < bc.vertices.size(); ++k)
      l(bc.vertices(k)) = u(bc.vertices(k)) = known(bc.vertices(k)) = bc.values(k, j);
    const BoxQPResult r = qp.solve(no_linear_term, l, u, box);
    pdas_iterations += r.iterations;
    pdas_factorizations += r.factorizations;
    pdas_seconds += r.seconds;
    pdas_factor_seconds += r.factor_seconds;
    // The interior-point problem on U: b_U = Q(U, N) w_N, s_y as BoxConstrainedQP's (of w).
    const Eigen::VectorXd qk = Q * known;
    bu[ju].resize(nu);
    for (Index k = 0; k < nu; ++k)
      bu[ju](k) = qk(unknown[static_cast<std::size_t>(k)]);
    const Eigen::VectorXd magnitude = Q_abs * r.x.cwiseAbs();
    sy[ju] = 0.0;
    for (Index k = 0; k < nu; ++k)
      sy[ju] = std::max(sy[ju], magnitude(unknown[static_cast<std::size_t>(k)]));
  }
  std::cout << "| start | interior-point iterations | their time | per iteration | active-set "
               "iterations after | their time | total |\n|---|---:|---:|---:|---:|---:|---:|\n";
  std::printf("| the active-set solver's default | – | – | – | %d (%d new factorizations; "
              "factoring and modifying %.2f s) | %.2f s | %.2f s |\n",
    pdas_iterations, pdas_factorizations, pdas_factor_seconds, pdas_seconds, pdas_seconds);
  for (const double level : levels)
  {
    int ip_iterations = 0, as_iterations = 0;
    double ip_seconds = 0, ip_factor_seconds = 0, as_seconds = 0;
    for (Index j = 0; j < m; ++j)
    {
      const auto ju = static_cast<std::size_t>(j);
      const InteriorPoint p = interior_point(A, bu[ju], ordering, sy[ju], level);
      ip_iterations += p.iterations;
      ip_seconds += p.seconds;
      ip_factor_seconds += p.factor_seconds;
      BoxQPWarmStart warm;
      warm.state = Eigen::Matrix<BoxQPState, Eigen::Dynamic, 1>::Constant(n, BoxQPState::Free);
      for (Index k = 0; k < nu; ++k)
      {
        const int i = unknown[static_cast<std::size_t>(k)];
        if (p.z(k) > p.w(k) * sy[ju])
          warm.state(i) = BoxQPState::Lower;
        else if (p.s(k) > (1.0 - p.w(k)) * sy[ju])
          warm.state(i) = BoxQPState::Upper;
      }
      const BoxQPResult r = qp.solve(no_linear_term, lower[ju], upper[ju], box, &warm);
      if (!r.converged)
        throw std::runtime_error("the active-set solver did not converge from an interior point");
      as_iterations += r.iterations;
      as_seconds += r.seconds;
    }
    std::printf("| interior point to mu / s_y <= %.0e | %d | %.2f s | %.2f ms factorization, %.2f "
                "ms in all | %d | %.2f s | %.2f s |\n",
      level, ip_iterations, ip_seconds, 1e3 * ip_factor_seconds / std::max(1, ip_iterations),
      1e3 * ip_seconds / std::max(1, ip_iterations), as_iterations, as_seconds,
      ip_seconds + as_seconds);
  }
  return 0;
}

int lumping()
{
  std::vector<Problem> problems;
  {
    const Cage c = test::read_polygon_obj(std::string(BARYLAB_DATA_DIR) + "/cage2d.obj");
    problems.push_back(cage_problem("data/cage2d.obj (gingerbread, 3000 triangles requested)",
      mesh_polygon(c), c.num_controls()));
  }
  {
    const test::ObjMesh obj = test::read_obj(std::string(BARYLAB_DATA_DIR) + "/cage3d.obj");
    Cage c;
    c.V = obj.V;
    c.F = obj.F;
    SurfaceMeshOptions o;
    o.target_cells = 5000;
    problems.push_back(cage_problem(
      "data/cage3d.obj (5,000 tetrahedra requested)", mesh_closed_surface(c, o), c.num_controls()));
  }
  const std::string dir = std::string(BARYLAB_SHARED_DIR) + "/igl/";
  if (std::filesystem::exists(dir + "decimated-knight-matlab-active-set.dmat"))
  {
    const test::MeditMesh mesh = test::read_medit_mesh(dir + "decimated-knight.mesh");
    const test::TgfSkeleton skeleton = test::read_tgf(dir + "decimated-knight.tgf");
    Problem p;
    p.name = "libigl decimated-knight (7 bones)";
    p.V = mesh.V;
    p.T = mesh.T;
    p.handles =
      handles_from_skeleton(mesh.V, skeleton.C, Eigen::VectorXi(), skeleton.E, std::sqrt(1e-7));
    p.reference = test::read_dmat(dir + "decimated-knight-matlab-active-set.dmat");
    problems.push_back(std::move(p));
  }
  std::printf("| problem | vertices | cells | lumping | seconds (best of 2) | energy 1/2 sum w^T Q w | "
              "support (entries > 1e-6) | max / mean abs difference to the other lumping | "
              "max / mean abs difference to MATLAB |\n|---|---|---|---|---|---|---|---|---|\n");
  for (const Problem& p : problems)
  {
    DenseWeights W[2];
    double seconds[2] = { 1e300, 1e300 }, energy[2] = { 0, 0 }, support[2] = { 0, 0 };
    for (int k = 0; k < 2; ++k)
    {
      BBWOptions o;
      o.mass_lumping = k == 0 ? BBWMassLumping::Barycentric : BBWMassLumping::Voronoi;
      o.normalize = p.reference.size() == 0; // the MATLAB weights are before normalization
      o.require_convergence = false;
      for (int repeat = 0; repeat < 2; ++repeat)
      {
        const auto start = Clock::now();
        const BoundedBiharmonicWeights bbw(p.V, p.T, o);
        const BBWResult r = bbw.compute(p.handles);
        seconds[k] = std::min(seconds[k], seconds_since(start));
        W[k] = r.W;
        energy[k] = 0.0;
        for (Index j = 0; j < r.W.cols(); ++j)
          energy[k] += 0.5 * r.W.col(j).dot(bbw.energy_matrix() * r.W.col(j));
      }
      support[k] = double((W[k].array() > 1e-6).count()) / double(W[k].size());
    }
    {
      const Eigen::VectorXd mb = mass_matrix(p.V, p.T, MassMatrixType::Barycentric).diagonal();
      const Eigen::VectorXd mv = mass_matrix(p.V, p.T, MassMatrixType::Voronoi).diagonal();
      const Eigen::VectorXd ratio = mv.cwiseQuotient(mb);
      std::fprintf(stderr, "%s: Voronoi / barycentric vertex mass in [%.3g, %.3g]\n",
        p.name.c_str(), ratio.minCoeff(), ratio.maxCoeff());
    }
    for (int k = 0; k < 2; ++k)
    {
      const DenseWeights d = (W[k] - W[1 - k]).cwiseAbs();
      std::string to_matlab = "-";
      if (p.reference.size() > 0)
      {
        const Eigen::MatrixXd e = (Eigen::MatrixXd(W[k]) - p.reference).cwiseAbs();
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, "%.3g / %.3g", e.maxCoeff(), e.mean());
        to_matlab = buffer;
      }
      std::printf("| %s | %lld | %lld | %s | %.3f | %.6g | %.2f%% | %.3g / %.3g | %s |\n",
        p.name.c_str(), static_cast<long long>(p.V.rows()), static_cast<long long>(p.T.rows()),
        k == 0 ? "barycentric" : "Voronoi", seconds[k], energy[k], 100.0 * support[k],
        d.maxCoeff(), d.mean(), to_matlab.c_str());
      std::fflush(stdout);
    }
  }
  return 0;
}

} // namespace

int main(int argc, char** argv)
{
  const std::string what = argc > 1 ? argv[1] : "";
  try
  {
    if (what == "lumping")
      return lumping();
    if (what == "maxima")
      return maxima(argc, argv);
    if (what == "interior")
      return interior(argc, argv);
  }
  catch (const std::exception& e)
  {
    std::cerr << "bbw_study: " << e.what() << "\n";
    return 1;
  }
  std::cerr << "usage: bbw_study lumping | maxima [--handles N] [--seed S] [--levels A,B,...] "
               "[--tolerance T] [--3d] [--barycentric] [--raw] | interior [--mesh NAME] [--mu A,B,...]\n";
  return 2;
}
