#include "cage_catalogue.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

namespace bary::test
{
namespace
{

constexpr double kPi = 3.14159265358979323846;

Eigen::MatrixXd rows_to_matrix(const std::vector<std::array<double, 3>>& rows, int dim)
{
  Eigen::MatrixXd V(static_cast<Index>(rows.size()), dim);
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (int k = 0; k < dim; ++k)
      V(static_cast<Index>(i), k) = rows[i][static_cast<std::size_t>(k)];
  return V;
}

Eigen::MatrixXi faces_to_matrix(const std::vector<std::array<int, 3>>& faces)
{
  Eigen::MatrixXi F(static_cast<Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 3; ++k)
      F(static_cast<Index>(f), k) = faces[f][static_cast<std::size_t>(k)];
  return F;
}

double point_segment_distance(
  const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  double t = len2 > 0.0 ? (p - a).dot(ab) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return (a + t * ab - p).norm();
}

double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
  const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
  // Project onto the plane; inside the triangle the plane distance is the answer, otherwise
  // the closest point lies on one of the edges.
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double n2 = n.squaredNorm();
  const Eigen::Vector3d q = p - n * (n.dot(p - a) / n2);
  const double la = n.dot((b - q).cross(c - q)) / n2;
  const double lb = n.dot((c - q).cross(a - q)) / n2;
  const double lc = n.dot((a - q).cross(b - q)) / n2;
  if (la >= 0.0 && lb >= 0.0 && lc >= 0.0)
    return (p - q).norm();
  return std::min({ point_segment_distance(p, a, b), point_segment_distance(p, b, c),
    point_segment_distance(p, c, a) });
}

Eigen::Vector3d row3(const Eigen::MatrixXd& V, Index i)
{
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (Index k = 0; k < V.cols(); ++k)
    r(k) = V(i, k);
  return r;
}

/// Convex (collinear vertices allowed): the turns at all vertices have one sign.
bool is_convex_polygon(const Cage& c)
{
  const Index n = c.V.rows();
  bool left = false, right = false;
  for (Index i = 0; i < n; ++i)
  {
    const Index j = (i + 1) % n, k = (i + 2) % n;
    const double turn = (c.V(j, 0) - c.V(i, 0)) * (c.V(k, 1) - c.V(j, 1)) -
      (c.V(j, 1) - c.V(i, 1)) * (c.V(k, 0) - c.V(j, 0));
    left = left || turn > 0.0;
    right = right || turn < 0.0;
  }
  return !(left && right);
}

std::string sanitize(const std::string& s)
{
  std::string out;
  for (const char c : s)
    out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out;
}

} // namespace

void PrintTo(const CatalogueCage& entry, std::ostream* os)
{
  *os << entry.name << " (" << entry.cage.dimension() << "D, " << entry.cage.num_controls()
      << " vertices)";
}

// --- 2D ---------------------------------------------------------------------------------------

Cage unit_square()
{
  Cage c;
  c.V.resize(4, 2);
  c.V << 0, 0, 1, 0, 1, 1, 0, 1;
  return c;
}

Cage regular_polygon(int n, double radius)
{
  Cage c;
  c.V.resize(n, 2);
  for (int i = 0; i < n; ++i)
  {
    const double a = 2.0 * kPi * i / n;
    c.V.row(i) << radius * std::cos(a), radius * std::sin(a);
  }
  return c;
}

Cage star_polygon(int tips, double outer, double inner)
{
  Cage c;
  c.V.resize(2 * tips, 2);
  for (int i = 0; i < 2 * tips; ++i)
  {
    const double a = kPi * i / tips + 0.5 * kPi; // first tip points up
    const double r = (i % 2 == 0) ? outer : inner;
    c.V.row(i) << r * std::cos(a), r * std::sin(a);
  }
  return c;
}

Cage u_polygon()
{
  Cage c;
  c.V.resize(8, 2);
  c.V << 0, 0, 3, 0, 3, 2, 2, 2, 2, 1, 1, 1, 1, 2, 0, 2;
  return c;
}

Cage l_polygon()
{
  Cage c;
  c.V.resize(6, 2);
  c.V << 0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2;
  return c;
}

Cage read_polygon_obj(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot open " + path);
  std::vector<std::array<double, 3>> rows;
  std::string line;
  while (std::getline(in, line))
  {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag != "v")
      continue;
    std::array<double, 3> v{ 0, 0, 0 };
    if (!(s >> v[0] >> v[1]))
      throw std::runtime_error("bad vertex line in " + path + ": " + line);
    rows.push_back(v);
  }
  Cage c;
  c.V = rows_to_matrix(rows, 2);
  return c;
}

std::string shared_cage_directory()
{
  return std::string(BARYLAB_SHARED_DIR) + "/lbc/cages";
}

bool read_lbc_reference(const std::string& name, LBCReferenceRun& run)
{
  const std::string dir = std::string(BARYLAB_SHARED_DIR) + "/lbc/";
  std::ifstream mesh(dir + "reference/" + name + ".mesh.obj"),
    control(dir + "reference/" + name + ".ctrl_idx.txt"),
    weights(dir + "reference/" + name + ".weights.txt");
  const std::string cage = dir + "cages/" + name + "-control-edgeset.obj";
  if (!mesh || !control || !weights || !std::filesystem::exists(cage))
    return false;
  std::vector<std::array<double, 3>> v;
  std::vector<std::array<int, 3>> t;
  std::string line;
  while (std::getline(mesh, line))
  {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v")
    {
      std::array<double, 3> p{ 0, 0, 0 };
      s >> p[0] >> p[1];
      v.push_back(p);
    }
    else if (tag == "f")
    {
      std::array<int, 3> f{ 0, 0, 0 };
      s >> f[0] >> f[1] >> f[2];
      t.push_back({ f[0] - 1, f[1] - 1, f[2] - 1 });
    }
  }
  run.V = rows_to_matrix(v, 2);
  run.T.resize(static_cast<Eigen::Index>(t.size()), 3);
  for (std::size_t k = 0; k < t.size(); ++k)
    run.T.row(static_cast<Eigen::Index>(k)) << t[k][0], t[k][1], t[k][2];
  std::vector<int> ids;
  for (int id; control >> id;)
    ids.push_back(id);
  run.control = Eigen::Map<Eigen::VectorXi>(ids.data(), static_cast<Eigen::Index>(ids.size()));
  std::getline(weights, line); // header comment
  run.W.resize(run.V.rows(), run.control.size());
  for (Eigen::Index r = 0; r < run.W.rows(); ++r)
    for (Eigen::Index c = 0; c < run.W.cols(); ++c)
      weights >> run.W(r, c);
  run.cage = read_polygon_obj(cage);
  return static_cast<bool>(weights);
}

std::vector<CatalogueCage> builtin_cages_2d()
{
  std::vector<CatalogueCage> out;
  out.push_back({ "square", unit_square(), true, true, 1.0 });
  out.push_back(
    { "regular64", regular_polygon(64), true, true, 32.0 * std::sin(2.0 * kPi / 64.0) });
  // 5 tips, 10 vertices: area = 2 * tips triangles of area R r sin(pi / tips) / 2. The inner
  // radius 0.3 is below the pentagram's 0.382, so a tip cannot see the next tip's point: that
  // is what makes some mean value weights negative (with 0.4 they all stay positive).
  const double star_area = 5.0 * 1.0 * 0.3 * std::sin(kPi / 5.0);
  out.push_back({ "star10", star_polygon(5, 1.0, 0.3), false, true, star_area });
  out.push_back({ "u_shape", u_polygon(), false, true, 5.0 });
  out.push_back({ "l_shape", l_polygon(), false, true, 3.0 });
  out.push_back(
    { "star10_clockwise", reversed(star_polygon(5, 1.0, 0.3)), false, false, star_area });
  return out;
}

std::vector<CatalogueCage> shared_cages_2d()
{
  std::vector<CatalogueCage> out;
  const std::filesystem::path dir(shared_cage_directory());
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    return out;
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
    if (entry.is_regular_file() && entry.path().extension() == ".obj")
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const auto& file : files)
  {
    std::string name = file.stem().string();
    const std::string suffix = "-control-edgeset";
    if (name.size() > suffix.size() &&
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      name.resize(name.size() - suffix.size());
    // The README of the shared data says: closed polygons in order, clockwise.
    Cage cage = read_polygon_obj(file.string());
    const bool convex = is_convex_polygon(cage);
    out.push_back({ "lbc_" + sanitize(name), std::move(cage), convex, false, 0.0 });
  }
  return out;
}

std::vector<CatalogueCage> cages_2d()
{
  std::vector<CatalogueCage> out = builtin_cages_2d();
  for (auto& c : shared_cages_2d())
    out.push_back(std::move(c));
  return out;
}

// --- 3D ---------------------------------------------------------------------------------------

Cage unit_cube()
{
  Cage c;
  c.V.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    c.V.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  c.F.resize(12, 3);
  c.F << 0, 2, 3, 0, 3, 1, // z = 0, normal -z
    4, 5, 7, 4, 7, 6,      // z = 1, normal +z
    0, 1, 5, 0, 5, 4,      // y = 0, normal -y
    2, 6, 7, 2, 7, 3,      // y = 1, normal +y
    0, 4, 6, 0, 6, 2,      // x = 0, normal -x
    1, 3, 7, 1, 7, 5;      // x = 1, normal +x
  return c;
}

Cage octahedron()
{
  Cage c;
  c.V.resize(6, 3);
  c.V << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  c.F.resize(8, 3);
  // One face per octant; the (x, y, z) vertex order is outward when the octant has an even
  // number of negative signs, otherwise swapped.
  c.F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  return c;
}

Cage u_box()
{
  const Cage u = u_polygon();
  const int n = static_cast<int>(u.V.rows());
  Cage c;
  c.V.resize(2 * n, 3);
  for (int i = 0; i < n; ++i)
  {
    c.V.row(i) << u.V(i, 0), u.V(i, 1), 0.0;
    c.V.row(n + i) << u.V(i, 0), u.V(i, 1), 1.0;
  }
  // Counter-clockwise triangulation of the U (areas 1.5 + 1 + 0.5 + 0.5 + 1 + 0.5 = 5).
  const std::array<std::array<int, 3>, 6> cap = { { { 0, 1, 4 }, { 1, 2, 4 }, { 2, 3, 4 },
    { 0, 4, 5 }, { 0, 5, 7 }, { 5, 6, 7 } } };
  std::vector<std::array<int, 3>> faces;
  for (const auto& t : cap)
  {
    faces.push_back({ t[0], t[2], t[1] });             // bottom, normal -z
    faces.push_back({ n + t[0], n + t[1], n + t[2] }); // top, normal +z
  }
  for (int i = 0; i < n; ++i)
  { // side wall of edge i -> j: (e x z) points to the right of a CCW edge, i.e. outward
    const int j = (i + 1) % n;
    faces.push_back({ i, j, n + j });
    faces.push_back({ i, n + j, n + i });
  }
  c.F = faces_to_matrix(faces);
  return c;
}

Cage noisy_icosphere(int subdivisions, double noise, std::uint64_t seed)
{
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> verts = { { -1, t, 0 }, { 1, t, 0 }, { -1, -t, 0 }, { 1, -t, 0 },
    { 0, -1, t }, { 0, 1, t }, { 0, -1, -t }, { 0, 1, -t }, { t, 0, -1 }, { t, 0, 1 },
    { -t, 0, -1 }, { -t, 0, 1 } };
  for (auto& v : verts)
    v.normalize();
  std::vector<std::array<int, 3>> faces = { { 0, 11, 5 }, { 0, 5, 1 }, { 0, 1, 7 }, { 0, 7, 10 },
    { 0, 10, 11 }, { 1, 5, 9 }, { 5, 11, 4 }, { 11, 10, 2 }, { 10, 7, 6 }, { 7, 1, 8 }, { 3, 9, 4 },
    { 3, 4, 2 }, { 3, 2, 6 }, { 3, 6, 8 }, { 3, 8, 9 }, { 4, 9, 5 }, { 2, 4, 11 }, { 6, 2, 10 },
    { 8, 6, 7 }, { 9, 8, 1 } };
  for (int s = 0; s < subdivisions; ++s)
  {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto it = midpoint.find(key);
      if (it != midpoint.end())
        return it->second;
      verts.push_back(
        (verts[static_cast<std::size_t>(a)] + verts[static_cast<std::size_t>(b)]).normalized());
      const int id = static_cast<int>(verts.size()) - 1;
      midpoint.emplace(key, id);
      return id;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& f : faces)
    {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      finer.push_back({ f[0], ab, ca });
      finer.push_back({ f[1], bc, ab });
      finer.push_back({ f[2], ca, bc });
      finer.push_back({ ab, bc, ca });
    }
    faces = std::move(finer);
  }
  Rng rng(seed);
  Cage c;
  c.V.resize(static_cast<Index>(verts.size()), 3);
  for (std::size_t i = 0; i < verts.size(); ++i)
    c.V.row(static_cast<Index>(i)) = (1.0 + noise * rng.uniform(-1.0, 1.0)) * verts[i].transpose();
  c.F = faces_to_matrix(faces);
  return c;
}

std::vector<CatalogueCage> cages_3d()
{
  std::vector<CatalogueCage> out;
  out.push_back({ "cube", unit_cube(), true, true, 1.0 });
  out.push_back({ "octahedron", octahedron(), true, true, 4.0 / 3.0 });
  out.push_back({ "u_box", u_box(), false, true, 5.0 });
  // Radial noise of +-10% keeps it star-shaped but not convex.
  out.push_back({ "icosphere320", noisy_icosphere(2, 0.1, 20240601), false, true, 0.0 });
  out.push_back({ "cube_inward", reversed(unit_cube()), true, false, 1.0 });
  return out;
}

// --- Orientation ------------------------------------------------------------------------------

Cage reversed(const Cage& cage)
{
  Cage r = cage;
  if (cage.dimension() == 2)
    r.V = cage.V.colwise().reverse();
  else
    for (Index f = 0; f < r.F.rows(); ++f)
      std::swap(r.F(f, 1), r.F(f, 2));
  return r;
}

Index reversed_index(const Cage& cage, Index i)
{
  return cage.dimension() == 2 ? cage.V.rows() - 1 - i : i;
}

// --- Geometry ---------------------------------------------------------------------------------

double winding_number(const Cage& cage, const double* x)
{
  const Eigen::MatrixXd& V = cage.V;
  const Index n = V.rows();
  if (cage.dimension() == 2)
  {
    double angle = 0.0;
    for (Index i = 0; i < n; ++i)
    {
      const Index j = (i + 1) % n;
      const double ax = V(i, 0) - x[0], ay = V(i, 1) - x[1];
      const double bx = V(j, 0) - x[0], by = V(j, 1) - x[1];
      angle += std::atan2(ax * by - ay * bx, ax * bx + ay * by);
    }
    return angle / (2.0 * kPi);
  }
  const Eigen::Vector3d p(x[0], x[1], x[2]);
  double omega = 0.0;
  for (Index f = 0; f < cage.F.rows(); ++f)
  {
    const Eigen::Vector3d a = row3(V, cage.F(f, 0)) - p, b = row3(V, cage.F(f, 1)) - p,
                          c = row3(V, cage.F(f, 2)) - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    omega += 2.0 * std::atan2(num, den);
  }
  return omega / (4.0 * kPi);
}

double boundary_distance(const Cage& cage, const double* x)
{
  const Eigen::MatrixXd& V = cage.V;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int k = 0; k < cage.dimension(); ++k)
    p(k) = x[k];
  double d = std::numeric_limits<double>::infinity();
  if (cage.dimension() == 2)
  {
    for (Index i = 0, n = V.rows(); i < n; ++i)
      d = std::min(d, point_segment_distance(p, row3(V, i), row3(V, (i + 1) % n)));
    return d;
  }
  for (Index f = 0; f < cage.F.rows(); ++f)
    d = std::min(d,
      point_triangle_distance(
        p, row3(V, cage.F(f, 0)), row3(V, cage.F(f, 1)), row3(V, cage.F(f, 2))));
  return d;
}

std::vector<std::pair<int, int>> cage_edges(const Cage& cage)
{
  std::vector<std::pair<int, int>> edges;
  if (cage.dimension() == 2)
  {
    const int n = static_cast<int>(cage.V.rows());
    for (int i = 0; i < n; ++i)
      edges.emplace_back(i, (i + 1) % n);
    return edges;
  }
  std::set<std::pair<int, int>> unique;
  for (Index f = 0; f < cage.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
    {
      const int a = cage.F(f, k), b = cage.F(f, (k + 1) % 3);
      unique.emplace(std::min(a, b), std::max(a, b));
    }
  edges.assign(unique.begin(), unique.end());
  return edges;
}

Eigen::VectorXd inward_normal(const Cage& cage, Index f)
{
  // The normal's side is decided by the winding number of a point just off the boundary, so
  // it does not rely on the declared orientation.
  Eigen::VectorXd n, centre;
  const Eigen::MatrixXd& V = cage.V;
  if (cage.dimension() == 2)
  {
    const Index j = (f + 1) % V.rows();
    const Eigen::Vector2d e = (V.row(j) - V.row(f)).transpose();
    n = Eigen::Vector2d(-e.y(), e.x()).normalized();
    centre = 0.5 * (V.row(f) + V.row(j)).transpose();
  }
  else
  {
    const Eigen::Vector3d a = row3(V, cage.F(f, 0)), b = row3(V, cage.F(f, 1)),
                          c = row3(V, cage.F(f, 2));
    n = (b - a).cross(c - a).normalized();
    centre = (a + b + c) / 3.0;
  }
  const Eigen::VectorXd probe = centre + 1e-6 * cage.diameter() * n;
  if (std::abs(winding_number(cage, probe.data())) < 0.5)
    n = -n;
  return n;
}

// --- Sampling ---------------------------------------------------------------------------------

std::uint64_t Rng::next()
{
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double Rng::uniform()
{
  return static_cast<double>(next() >> 11) * 0x1.0p-53;
}

namespace
{
Points sample(const Cage& cage, Index count, double min_relative_distance, double box_scale,
  bool inside, std::uint64_t seed)
{
  const int dim = cage.dimension();
  const Eigen::VectorXd lo = cage.V.colwise().minCoeff().transpose();
  const Eigen::VectorXd hi = cage.V.colwise().maxCoeff().transpose();
  const Eigen::VectorXd centre = 0.5 * (lo + hi), half = 0.5 * box_scale * (hi - lo);
  const double min_distance = min_relative_distance * cage.diameter();
  Rng rng(seed);
  Points P(count, dim);
  Index found = 0;
  const Index max_tries = 10000 * (count + 1);
  for (Index tries = 0; found < count; ++tries)
  {
    if (tries >= max_tries)
      throw std::runtime_error("sampling found too few points; is the cage empty?");
    Eigen::VectorXd x(dim);
    for (int k = 0; k < dim; ++k)
      x(k) = centre(k) + half(k) * rng.uniform(-1.0, 1.0);
    const bool is_inside = std::abs(winding_number(cage, x.data())) > 0.5;
    if (is_inside != inside ||
      (min_distance > 0.0 && boundary_distance(cage, x.data()) < min_distance))
      continue;
    P.row(found++) = x.transpose();
  }
  return P;
}
} // namespace

Points sample_inside(
  const Cage& cage, Index count, double min_relative_distance, std::uint64_t seed)
{
  return sample(cage, count, min_relative_distance, 1.0, true, seed);
}

Points sample_outside(
  const Cage& cage, Index count, double min_relative_distance, double box_scale, std::uint64_t seed)
{
  return sample(cage, count, min_relative_distance, box_scale, false, seed);
}

} // namespace bary::test
