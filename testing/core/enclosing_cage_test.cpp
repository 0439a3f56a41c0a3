// enclosing_cage: a cage strictly enclosing the model, checked exactly and independently of the
// generator's own checks with CGAL (Side_of_triangle_mesh for every model vertex,
// PMP::do_intersect between model and cage, PMP::does_self_intersect, closed / manifold /
// outward; 2D: bounded_side_2, segment intersections, Polygon_2::is_simple), then used by the
// methods: validate_cage, TetGen / CGAL meshing of its interior, mean value coordinates of the
// model's points (partition of unity and linear reproduction, 1e-9).

#include "core/common/cage.h"
#include "core/common/error.h"
#include "core/coordinates/mean_value_coordinates.h"
#include "core/meshing/domain_mesh.h"
#include "core/meshing/enclosing_cage.h"

#include "igl_formats.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/intersections.h>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace bary
{
namespace
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

struct Model
{
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
};

Model read_off(const std::string& path)
{
  std::ifstream in(path);
  std::string tag;
  Index nv = 0, nf = 0, ne = 0;
  in >> tag >> nv >> nf >> ne;
  Model m;
  m.V.resize(nv, 3);
  m.F.resize(nf, 3);
  for (Index i = 0; i < nv; ++i)
    in >> m.V(i, 0) >> m.V(i, 1) >> m.V(i, 2);
  for (Index f = 0; f < nf; ++f)
  {
    int three = 0;
    in >> three >> m.F(f, 0) >> m.F(f, 1) >> m.F(f, 2);
  }
  if (!in || tag != "OFF")
    throw std::runtime_error("cannot read " + path);
  return m;
}

// A triangle mesh in the plane z = 0 from an .obj: vertices (x, y), faces "f a b c" (1-based).
Model read_obj_2d(const std::string& path)
{
  std::ifstream in(path);
  std::vector<std::array<double, 2>> v;
  std::vector<std::array<int, 3>> f;
  std::string line;
  while (std::getline(in, line))
  {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v")
    {
      double x = 0, y = 0;
      s >> x >> y;
      v.push_back({ x, y });
    }
    else if (tag == "f")
    {
      std::array<int, 3> t{};
      for (int& k : t)
      {
        std::string w;
        s >> w;
        k = std::stoi(w) - 1;
      }
      f.push_back(t);
    }
  }
  Model m;
  m.V.resize(Index(v.size()), 2);
  m.F.resize(Index(f.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    m.V.row(Index(i)) << v[i][0], v[i][1];
  for (std::size_t i = 0; i < f.size(); ++i)
    m.F.row(Index(i)) << f[i][0], f[i][1], f[i][2];
  if (v.empty() || f.empty())
    throw std::runtime_error("cannot read " + path);
  return m;
}

std::string data(const std::string& name)
{
  return std::string(BARYLAB_DATA_DIR) + "/" + name;
}

Mesh to_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F)
{
  Mesh m;
  std::vector<Mesh::Vertex_index> vi;
  for (Index i = 0; i < V.rows(); ++i)
    vi.push_back(m.add_vertex(K::Point_3(V(i, 0), V(i, 1), V(i, 2))));
  for (Index f = 0; f < F.rows(); ++f)
    if (m.add_face(vi[F(f, 0)], vi[F(f, 1)], vi[F(f, 2)]) == Mesh::null_face())
      ADD_FAILURE() << "face " << f << " is not manifold";
  return m;
}

// The independent 3D check. Returns the number of failed properties (0: all hold).
int check_enclosure_3d(const Model& model, const Cage& cage)
{
  int failures = 0;
  const Mesh c = to_mesh(cage.V, cage.F);
  const Mesh m = to_mesh(model.V, model.F);
  if (!CGAL::is_closed(c) || !CGAL::is_triangle_mesh(c))
  {
    ADD_FAILURE() << "the cage is not a closed triangle mesh";
    return 1;
  }
  if (PMP::does_self_intersect(c))
  {
    ++failures;
    ADD_FAILURE() << "the cage intersects itself";
  }
  if (!PMP::is_outward_oriented(c))
  {
    ++failures;
    ADD_FAILURE() << "the cage is not outward oriented";
  }
  const CGAL::Side_of_triangle_mesh<Mesh, K> inside(c);
  Index outside = 0;
  for (Index i = 0; i < model.V.rows(); ++i)
    outside += inside(K::Point_3(model.V(i, 0), model.V(i, 1), model.V(i, 2))) !=
      CGAL::ON_BOUNDED_SIDE;
  if (outside > 0)
  {
    ++failures;
    ADD_FAILURE() << outside << " model vertices are not strictly inside the cage";
  }
  if (PMP::do_intersect(m, c))
  {
    ++failures;
    ADD_FAILURE() << "a model triangle meets the cage";
  }
  return failures;
}

// The independent 2D check (exact predicates): model vertices strictly inside, no model edge
// (of its triangles, or its segments when F has 2 columns) meeting a cage edge, a simple
// counter-clockwise polygon.
int check_enclosure_2d(const Model& model, const Cage& cage)
{
  using P2 = K::Point_2;
  std::vector<P2> poly;
  for (Index i = 0; i < cage.V.rows(); ++i)
    poly.emplace_back(cage.V(i, 0), cage.V(i, 1));
  int failures = 0;
  if (!CGAL::is_simple_2(poly.begin(), poly.end(), K()))
  {
    ADD_FAILURE() << "the cage polygon is not simple";
    return 1;
  }
  if (CGAL::orientation_2(poly.begin(), poly.end(), K()) != CGAL::COUNTERCLOCKWISE)
  {
    ++failures;
    ADD_FAILURE() << "the cage polygon is not counter-clockwise";
  }
  Index outside = 0;
  for (Index i = 0; i < model.V.rows(); ++i)
    outside += CGAL::bounded_side_2(poly.begin(), poly.end(), P2(model.V(i, 0), model.V(i, 1)),
                 K()) != CGAL::ON_BOUNDED_SIDE;
  if (outside > 0)
  {
    ++failures;
    ADD_FAILURE() << outside << " model vertices are not strictly inside the cage";
  }
  Index crossings = 0;
  const Index corners = model.F.cols(), sides = corners == 3 ? 3 : 1;
  for (Index f = 0; f < model.F.rows(); ++f)
    for (Index k = 0; k < sides; ++k)
    {
      const Index a = model.F(f, k), b = model.F(f, (k + 1) % corners);
      const K::Segment_2 e(P2(model.V(a, 0), model.V(a, 1)), P2(model.V(b, 0), model.V(b, 1)));
      for (std::size_t j = 0; j < poly.size(); ++j)
        crossings += CGAL::do_intersect(e, K::Segment_2(poly[j], poly[(j + 1) % poly.size()]));
    }
  if (crossings > 0)
  {
    ++failures;
    ADD_FAILURE() << crossings << " model edge / cage edge intersections";
  }
  return failures;
}

// Mean value coordinates of the model's vertices: partition of unity and linear reproduction.
void check_coordinates(const Cage& cage, const Eigen::MatrixXd& X)
{
  const DenseWeights W = mean_value_coordinates(cage, X);
  ASSERT_EQ(W.rows(), X.rows());
  ASSERT_EQ(W.cols(), cage.V.rows());
  const double unity = (W.rowwise().sum().array() - 1.0).abs().maxCoeff();
  const double reproduction = (W * cage.V - X).cwiseAbs().maxCoeff() / cage.diameter();
  EXPECT_LT(unity, 1e-9);
  EXPECT_LT(reproduction, 1e-9);
}

// Distances from the cage's vertices to the model, by brute force over the model's triangles
// (Eigen, independent of the generator's AABB tree), for the reported figures.
void check_reported_distances(const Model& model, const EnclosingCageResult& r)
{
  const Index dim = model.V.cols();
  auto lifted = [&](Index i) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    p.head(dim) = model.V.row(i).transpose();
    return p;
  };
  double max_d = 0.0, sum = 0.0;
  for (Index v = 0; v < r.cage.V.rows(); ++v)
  {
    Eigen::Vector3d q = Eigen::Vector3d::Zero();
    q.head(dim) = r.cage.V.row(v).transpose();
    double best = std::numeric_limits<double>::infinity();
    for (Index f = 0; f < model.F.rows(); ++f)
    {
      const K::Triangle_3 t(K::Point_3(lifted(model.F(f, 0)).x(), lifted(model.F(f, 0)).y(), lifted(model.F(f, 0)).z()),
        K::Point_3(lifted(model.F(f, 1)).x(), lifted(model.F(f, 1)).y(), lifted(model.F(f, 1)).z()),
        K::Point_3(lifted(model.F(f, 2)).x(), lifted(model.F(f, 2)).y(), lifted(model.F(f, 2)).z()));
      best = std::min(best, CGAL::squared_distance(t, K::Point_3(q.x(), q.y(), q.z())));
    }
    max_d = std::max(max_d, std::sqrt(best));
    sum += std::sqrt(best);
  }
  EXPECT_NEAR(r.max_distance, max_d, 1e-9 * r.diagonal);
  EXPECT_NEAR(r.mean_distance, sum / double(r.cage.V.rows()), 1e-9 * r.diagonal);
  EXPECT_GT(r.max_distance, 0.0);
}

struct Case3
{
  const char* file;
  Index target;
};

class EnclosingCage3D : public ::testing::TestWithParam<Case3>
{
};

TEST_P(EnclosingCage3D, EnclosesStrictlyAndIsUsable)
{
  const Model model = read_off(data(GetParam().file));
  EnclosingCageOptions options;
  options.target_vertices = GetParam().target;
  const EnclosingCageResult r = enclosing_cage(model.V, model.F, options);
  // The target is met exactly when reached (one vertex per collapse).
  ASSERT_TRUE(r.reached_target) << r.stop_reason;
  EXPECT_EQ(r.cage.V.rows(), GetParam().target);
  EXPECT_EQ(r.cage.F.rows(), 2 * GetParam().target - 4); // genus 0: F = 2V - 4
  EXPECT_EQ(check_enclosure_3d(model, r.cage), 0);
  EXPECT_NO_THROW(validate_cage(r.cage));
  EXPECT_TRUE(is_positively_oriented(r.cage));
  // The interior meshes (harmonic, BBW and LBC coordinates' TetGen meshing).
  SurfaceMeshOptions mesh;
  mesh.target_cells = 2000;
  DomainMesh dm;
  ASSERT_NO_THROW(dm = mesh_closed_surface(r.cage, mesh));
  EXPECT_GT(dm.T.rows(), 0);
  check_coordinates(r.cage, model.V);
  // The reported figures against independent computations (CGAL's volumes, brute force).
  const Mesh c = to_mesh(r.cage.V, r.cage.F), m = to_mesh(model.V, model.F);
  const double vc = PMP::volume(c), vm = PMP::volume(m);
  EXPECT_NEAR(r.cage_measure, vc, 1e-9 * vc);
  EXPECT_NEAR(r.model_measure, vm, 1e-9 * vm);
  EXPECT_GT(r.measure_ratio, 1.0);
  check_reported_distances(model, r);
  // Tightness, loosely: every cage vertex within 3 margins of the model.
  EXPECT_LT(r.max_distance, 3.0 * r.margin);
  std::printf("[ info ] %s: %lld vertices, volume ratio %.3f, max distance %.4f x diagonal, "
              "%.2f s\n",
    GetParam().file, static_cast<long long>(r.cage.V.rows()), r.measure_ratio,
    r.max_distance / r.diagonal, r.seconds);
}

INSTANTIATE_TEST_SUITE_P(BundledModels, EnclosingCage3D,
  ::testing::Values(Case3{ "model3d.off", 100 }, Case3{ "heart.off", 60 },
    Case3{ "starfish.off", 150 }),
  [](const auto& param_info) {
    std::string name = param_info.param.file;
    return name.substr(0, name.find('.'));
  });

TEST(EnclosingCage, TwoDimensionalModel)
{
  const Model model = read_obj_2d(data("model2d.obj"));
  EnclosingCageOptions options;
  options.target_vertices = 20;
  const EnclosingCageResult r = enclosing_cage(model.V, model.F, options);
  ASSERT_TRUE(r.reached_target) << r.stop_reason;
  EXPECT_EQ(r.cage.V.rows(), 20);
  EXPECT_EQ(r.cage.V.cols(), 2);
  EXPECT_EQ(r.cage.F.rows(), 0);
  EXPECT_EQ(check_enclosure_2d(model, r.cage), 0);
  EXPECT_NO_THROW(validate_cage(r.cage));
  DomainMesh dm;
  ASSERT_NO_THROW(dm = mesh_polygon(r.cage));
  EXPECT_GT(dm.T.rows(), 0);
  check_coordinates(r.cage, model.V);
  double area = 0.0; // the model's area, independently
  for (Index f = 0; f < model.F.rows(); ++f)
  {
    const Eigen::Vector2d a = model.V.row(model.F(f, 0)), b = model.V.row(model.F(f, 1)),
                          c = model.V.row(model.F(f, 2));
    area += 0.5 * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
  }
  EXPECT_NEAR(r.model_measure, area, 1e-12 * area);
  EXPECT_NEAR(r.cage_measure, enclosed_measure(r.cage), 1e-12 * area);
  check_reported_distances(model, r);
}

TEST(EnclosingCage, PolygonModelGivenBySegments)
{
  // A star-shaped (non-convex) polygon as its edges.
  const int n = 16;
  Eigen::MatrixXd V(n, 2);
  Eigen::MatrixXi E(n, 2);
  for (int i = 0; i < n; ++i)
  {
    const double t = 2.0 * 3.141592653589793 * i / n, r = i % 2 ? 0.4 : 1.0;
    V.row(i) << r * std::cos(t), r * std::sin(t);
    E.row(i) << i, (i + 1) % n;
  }
  EnclosingCageOptions options;
  options.target_vertices = 10;
  options.margin = 0.05;
  const EnclosingCageResult r = enclosing_cage(V, E, options);
  EXPECT_EQ(r.cage.V.rows(), 10) << r.stop_reason;
  Model model; // the checker takes the edges as they are
  model.V = V;
  model.F = E;
  EXPECT_EQ(check_enclosure_2d(model, r.cage), 0);
  EXPECT_NO_THROW(validate_cage(r.cage));
  // The area a closed polygon bounds (shoelace), against the cage-area function.
  Cage star;
  star.V = V;
  EXPECT_NEAR(r.model_measure, enclosed_measure(star), 1e-12);
}

TEST(EnclosingCage, TheCheckerCanFail)
{
  // The generated cage shrunk by 0.8 about its centroid no longer encloses the kidney: the
  // independent check reports it (and validate_cage alone would not).
  const Model model = read_off(data("model3d.off"));
  EnclosingCageOptions options;
  options.target_vertices = 60;
  EnclosingCageResult r = enclosing_cage(model.V, model.F, options);
  const Eigen::RowVector3d centre = r.cage.V.colwise().mean();
  Cage shrunk = r.cage;
  shrunk.V = (shrunk.V.rowwise() - centre) * 0.8;
  shrunk.V.rowwise() += centre;
  EXPECT_NO_THROW(validate_cage(shrunk));
  const Mesh c = to_mesh(shrunk.V, shrunk.F), m = to_mesh(model.V, model.F);
  EXPECT_TRUE(PMP::do_intersect(m, c));
  const CGAL::Side_of_triangle_mesh<Mesh, K> inside(c);
  Index outside = 0;
  for (Index i = 0; i < model.V.rows(); ++i)
    outside += inside(K::Point_3(model.V(i, 0), model.V(i, 1), model.V(i, 2))) !=
      CGAL::ON_BOUNDED_SIDE;
  EXPECT_GT(outside, 0);
}

TEST(EnclosingCage, Deterministic)
{
  const Model model = read_off(data("starfish.off"));
  EnclosingCageOptions options;
  options.target_vertices = 120;
  const EnclosingCageResult a = enclosing_cage(model.V, model.F, options);
  const EnclosingCageResult b = enclosing_cage(model.V, model.F, options);
  EXPECT_TRUE(a.cage.V == b.cage.V);
  EXPECT_TRUE(a.cage.F == b.cage.F);
  EXPECT_EQ(a.collapses, b.collapses);
}

TEST(EnclosingCage, GivenMarginIsUsedAndASmallerOneIsTighter)
{
  // Without tightening the cage follows the offset curve: a smaller margin, a smaller cage.
  const Model model = read_obj_2d(data("model2d.obj"));
  const double diagonal = (model.V.colwise().maxCoeff() - model.V.colwise().minCoeff()).norm();
  EnclosingCageOptions options;
  options.target_vertices = 24;
  options.tighten_rounds = 0;
  options.margin = 0.02 * diagonal;
  const EnclosingCageResult tight = enclosing_cage(model.V, model.F, options);
  EXPECT_EQ(tight.margin, options.margin);
  EXPECT_EQ(tight.tighten_moves, 0);
  EXPECT_EQ(check_enclosure_2d(model, tight.cage), 0);
  options.margin = 0.0; // automatic: 5 % of the diagonal
  const EnclosingCageResult loose = enclosing_cage(model.V, model.F, options);
  EXPECT_NEAR(loose.margin, 0.05 * diagonal, 1e-15 * diagonal);
  EXPECT_LT(tight.cage_measure, loose.cage_measure);
  EXPECT_LT(tight.max_distance, loose.max_distance);
  // Every vertex lies about a margin from the model: within [margin - h sqrt(2), 3 margin].
  EXPECT_GT(loose.mean_distance, loose.margin - loose.cell_size * std::sqrt(2.0));
}

TEST(EnclosingCage, TighteningShrinksTheCageAndKeepsItEnclosing)
{
  const Model model = read_off(data("heart.off"));
  EnclosingCageOptions options;
  options.target_vertices = 60;
  options.margin_fraction = 0.1; // a coarser grid than the default: a faster test
  options.tighten_rounds = 0;
  const EnclosingCageResult plain = enclosing_cage(model.V, model.F, options);
  options.tighten_rounds = 4; // the default
  const EnclosingCageResult tightened = enclosing_cage(model.V, model.F, options);
  EXPECT_GT(tightened.tighten_moves, 0);
  EXPECT_LT(tightened.cage_measure, plain.cage_measure);
  EXPECT_LT(tightened.mean_distance, plain.mean_distance);
  // No vertex comes closer to the model than the clearance (brute force over the triangles).
  double nearest = std::numeric_limits<double>::infinity();
  for (Index v = 0; v < tightened.cage.V.rows(); ++v)
  {
    const K::Point_3 q(tightened.cage.V(v, 0), tightened.cage.V(v, 1), tightened.cage.V(v, 2));
    for (Index f = 0; f < model.F.rows(); ++f)
    {
      auto corner = [&](int k) {
        return K::Point_3(model.V(model.F(f, k), 0), model.V(model.F(f, k), 1), model.V(model.F(f, k), 2));
      };
      nearest = std::min(nearest, std::sqrt(CGAL::squared_distance(K::Triangle_3(corner(0), corner(1), corner(2)), q)));
    }
  }
  EXPECT_GE(nearest, (1.0 - 1e-9) * options.clearance * tightened.margin);
  EXPECT_EQ(check_enclosure_3d(model, tightened.cage), 0);
  EXPECT_EQ(tightened.cage.V.rows(), plain.cage.V.rows());
  EXPECT_TRUE(tightened.cage.F == plain.cage.F) << "tightening moves vertices only";
}

TEST(EnclosingCage, TargetBelowWhatIsReachable)
{
  // 2D, 3 vertices: a triangle may not fit around the model within its constraints; either
  // the target is reached or the result says why not, and is valid either way.
  const Model model = read_obj_2d(data("model2d.obj"));
  EnclosingCageOptions options;
  options.target_vertices = 3;
  const EnclosingCageResult r = enclosing_cage(model.V, model.F, options);
  EXPECT_GE(r.cage.V.rows(), 3);
  EXPECT_EQ(r.reached_target, r.cage.V.rows() == 3);
  if (!r.reached_target)
  {
    EXPECT_EQ(r.stop_reason, "no valid collapse left");
  }
  EXPECT_EQ(check_enclosure_2d(model, r.cage), 0);
  EXPECT_NO_THROW(validate_cage(r.cage));
}

TEST(EnclosingCage, OpenSurfaceIsEnclosedAndHasNoVolume)
{
  // The kidney without its first 200 triangles: an open surface (a triangle soup is enclosed
  // triangle by triangle); its volume is undefined, so the ratio is NaN.
  const Model closed = read_off(data("model3d.off"));
  Model open;
  open.V = closed.V;
  open.F = closed.F.bottomRows(closed.F.rows() - 200);
  EnclosingCageOptions options;
  options.target_vertices = 50;
  options.margin_fraction = 0.1;
  const EnclosingCageResult r = enclosing_cage(open.V, open.F, options);
  ASSERT_TRUE(r.reached_target) << r.stop_reason;
  EXPECT_TRUE(std::isnan(r.model_measure));
  EXPECT_TRUE(std::isnan(r.measure_ratio));
  EXPECT_GT(r.cage_measure, 0.0);
  // Every vertex inside (including those of the removed triangles), no triangle meeting it.
  const Mesh c = to_mesh(r.cage.V, r.cage.F);
  const CGAL::Side_of_triangle_mesh<Mesh, K> inside(c);
  for (Index i = 0; i < open.V.rows(); ++i)
    ASSERT_EQ(inside(K::Point_3(open.V(i, 0), open.V(i, 1), open.V(i, 2))), CGAL::ON_BOUNDED_SIDE) << i;
  std::vector<K::Triangle_3> triangles;
  for (Index f = 0; f < open.F.rows(); ++f)
  {
    auto corner = [&](int k) {
      return K::Point_3(open.V(open.F(f, k), 0), open.V(open.F(f, k), 1), open.V(open.F(f, k), 2));
    };
    triangles.emplace_back(corner(0), corner(1), corner(2));
  }
  Index crossings = 0;
  for (Index f = 0; f < r.cage.F.rows(); ++f)
  {
    auto corner = [&](int k) {
      return K::Point_3(r.cage.V(r.cage.F(f, k), 0), r.cage.V(r.cage.F(f, k), 1), r.cage.V(r.cage.F(f, k), 2));
    };
    const K::Triangle_3 t(corner(0), corner(1), corner(2));
    for (const auto& m : triangles)
      crossings += CGAL::do_intersect(t, m);
  }
  EXPECT_EQ(crossings, 0);
  EXPECT_NO_THROW(validate_cage(r.cage));
}

TEST(EnclosingCage, SmallModelOnACoarseGrid)
{
  // A tetrahedron with a margin of 20 % of its diagonal: a few hundred offset vertices, so the
  // whole 3D path (grid, marching tetrahedra, collapses, tightening) runs in every build,
  // sanitizers included (the bundled models' cases run in the Release pass only).
  Model tet;
  tet.V.resize(4, 3);
  tet.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  tet.F.resize(4, 3);
  tet.F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  EnclosingCageOptions options;
  options.target_vertices = 8;
  options.margin_fraction = 0.2;
  const EnclosingCageResult r = enclosing_cage(tet.V, tet.F, options);
  ASSERT_TRUE(r.reached_target) << r.stop_reason;
  EXPECT_EQ(r.cage.V.rows(), 8);
  EXPECT_EQ(r.cage.F.rows(), 12);
  EXPECT_EQ(check_enclosure_3d(tet, r.cage), 0);
  EXPECT_NO_THROW(validate_cage(r.cage));
  EXPECT_NEAR(r.model_measure, 1.0 / 6.0, 1e-15);
  EXPECT_GT(r.measure_ratio, 1.0);
  check_coordinates(r.cage, tet.V);
}

TEST(EnclosingCage, BadInput)
{
  Model tet;
  tet.V.resize(4, 3);
  tet.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  tet.F.resize(4, 3);
  tet.F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  EnclosingCageOptions o;
  o.target_vertices = 8;
  o.margin_fraction = 0.2; // a coarse grid: fast
  auto code = [](auto&& fn) {
    try
    {
      fn();
    }
    catch (const Error& e)
    {
      EXPECT_FALSE(e.message().empty());
      return e.code();
    }
    return ErrorCode::Internal;
  };
  EXPECT_NO_THROW(enclosing_cage(tet.V, tet.F, o));
  EXPECT_EQ(code([&] { enclosing_cage(Eigen::MatrixXd(0, 3), tet.F, o); }), ErrorCode::EmptyInput);
  EXPECT_EQ(code([&] { enclosing_cage(tet.V, Eigen::MatrixXi(0, 3), o); }), ErrorCode::EmptyInput);
  Model nan = tet;
  nan.V(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(code([&] { enclosing_cage(nan.V, nan.F, o); }), ErrorCode::NonFinite);
  Model out = tet;
  out.F(1, 2) = 7;
  EXPECT_EQ(code([&] { enclosing_cage(out.V, out.F, o); }), ErrorCode::SizeMismatch);
  EXPECT_EQ(code([&] { enclosing_cage(tet.V, tet.F.leftCols(2), o); }), ErrorCode::SizeMismatch);
  EnclosingCageOptions small = o;
  small.target_vertices = 3;
  EXPECT_EQ(code([&] { enclosing_cage(tet.V, tet.F, small); }), ErrorCode::InvalidArgument);
  small.target_vertices = 2;
  EXPECT_EQ(code([&] { enclosing_cage(tet.V.leftCols(2), tet.F, small); }),
    ErrorCode::InvalidArgument);
  for (double margin : { -1.0, std::numeric_limits<double>::quiet_NaN(),
         std::numeric_limits<double>::infinity() })
  {
    EnclosingCageOptions bad = o;
    bad.margin = margin;
    EXPECT_EQ(code([&] { enclosing_cage(tet.V, tet.F, bad); }), ErrorCode::InvalidArgument)
      << margin;
  }
  EnclosingCageOptions coarse = o;
  coarse.resolution = 1.0; // h sqrt(3) > margin: no enclosure guarantee
  EXPECT_EQ(code([&] { enclosing_cage(tet.V, tet.F, coarse); }), ErrorCode::InvalidArgument);
  EnclosingCageOptions huge = o;
  huge.margin = 1e-4; // (1 / 5e-5)^3 grid nodes
  EXPECT_EQ(code([&] { enclosing_cage(tet.V, tet.F, huge); }), ErrorCode::InvalidArgument);
  Model point = tet;
  point.V.setZero();
  EXPECT_EQ(code([&] { enclosing_cage(point.V, point.F, o); }), ErrorCode::InvalidArgument);
  // Two parts farther apart than twice the margin: one cage cannot be one offset surface.
  Model two;
  two.V.resize(8, 3);
  two.V.topRows(4) = tet.V;
  two.V.bottomRows(4) = tet.V.rowwise() + Eigen::RowVector3d(10, 0, 0);
  two.F.resize(8, 3);
  two.F.topRows(4) = tet.F;
  two.F.bottomRows(4) = tet.F.array() + 4;
  EnclosingCageOptions tight = o;
  tight.margin = 0.5;
  EXPECT_EQ(code([&] { enclosing_cage(two.V, two.F, tight); }), ErrorCode::InvalidArgument);
  int calls = 0;
  EXPECT_EQ(code([&] {
    enclosing_cage(tet.V, tet.F, o, [&](double) { return ++calls < 2; });
  }),
    ErrorCode::Cancelled);
}

// The closed meshes of BARYLAB_SHARED_DIR/igl (about 1 s each in Release; skipped when absent).

// The boundary triangles of a tetrahedral mesh, outward.
Model tet_boundary(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T)
{
  std::map<std::array<int, 3>, std::pair<int, std::array<int, 3>>> faces;
  for (Index t = 0; t < T.rows(); ++t)
  {
    std::array<int, 4> q{ T(t, 0), T(t, 1), T(t, 2), T(t, 3) };
    const Eigen::Vector3d a = V.row(q[0]), b = V.row(q[1]), c = V.row(q[2]), d = V.row(q[3]);
    if ((b - a).cross(c - a).dot(d - a) < 0.0)
      std::swap(q[1], q[2]);
    for (const auto& f : { std::array<int, 3>{ q[0], q[2], q[1] }, { q[0], q[1], q[3] },
           { q[0], q[3], q[2] }, { q[1], q[2], q[3] } })
    {
      std::array<int, 3> key = f;
      std::sort(key.begin(), key.end());
      auto& slot = faces[key];
      ++slot.first;
      slot.second = f;
    }
  }
  std::vector<std::array<int, 3>> kept;
  for (const auto& [key, value] : faces)
    if (value.first == 1)
      kept.push_back(value.second);
  // Only the vertices the boundary uses.
  std::vector<int> remap(static_cast<std::size_t>(V.rows()), -1);
  Model m;
  std::vector<int> order;
  for (auto& f : kept)
    for (int& v : f)
    {
      if (remap[v] < 0)
      {
        remap[v] = int(order.size());
        order.push_back(v);
      }
      v = remap[v];
    }
  m.V.resize(Index(order.size()), 3);
  for (std::size_t i = 0; i < order.size(); ++i)
    m.V.row(Index(i)) = V.row(order[i]);
  m.F.resize(Index(kept.size()), 3);
  for (std::size_t i = 0; i < kept.size(); ++i)
    m.F.row(Index(i)) << kept[i][0], kept[i][1], kept[i][2];
  return m;
}

class EnclosingCageIgl : public ::testing::TestWithParam<const char*>
{
};

TEST_P(EnclosingCageIgl, EnclosesStrictlyAndIsUsable)
{
  const std::string dir = std::string(BARYLAB_SHARED_DIR) + "/igl/";
  const std::string name = GetParam();
  const std::string path = dir + name + (name == "hand" ? ".mesh" : ".off");
  if (!std::ifstream(path))
    GTEST_SKIP() << path << " not found";
  Model model;
  if (name == "hand")
  {
    const test::MeditMesh mesh = test::read_medit_mesh(path);
    model = tet_boundary(mesh.V, mesh.T);
  }
  else
    model = read_off(path);
  EnclosingCageOptions options;
  options.target_vertices = 200;
  const EnclosingCageResult r = enclosing_cage(model.V, model.F, options);
  ASSERT_TRUE(r.reached_target) << r.stop_reason;
  EXPECT_EQ(r.cage.V.rows(), 200);
  EXPECT_EQ(check_enclosure_3d(model, r.cage), 0);
  EXPECT_NO_THROW(validate_cage(r.cage));
  SurfaceMeshOptions mesh;
  mesh.target_cells = 2000;
  EXPECT_NO_THROW(mesh_closed_surface(r.cage, mesh));
  check_coordinates(r.cage, model.V);
  std::printf("[ info ] %s: %lld vertices, %lld faces, volume ratio %.3f, max distance %.4f x "
              "diagonal, %.2f s\n",
    name.c_str(), static_cast<long long>(r.cage.V.rows()), static_cast<long long>(r.cage.F.rows()),
    r.measure_ratio, r.max_distance / r.diagonal, r.seconds);
}

INSTANTIATE_TEST_SUITE_P(
  SharedMeshes, EnclosingCageIgl, ::testing::Values("bunny", "cheburashka", "fertility", "hand"));

} // namespace
} // namespace bary
