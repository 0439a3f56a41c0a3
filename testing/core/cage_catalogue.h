#pragma once
/// @file cage_catalogue.h
/// The cages every core property test runs over, and geometry helpers to sample query points.
///
/// Everything here is written independently of core's algorithms (only the Cage struct is
/// shared): the winding numbers, distances and samplers below must not borrow the code they are
/// used to test.

#include "core/common/cage.h"

#include <cstdint>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace bary::test
{

/// One entry of the catalogue.
struct CatalogueCage
{
  std::string name; ///< a valid GoogleTest parameter name ([A-Za-z0-9_])
  Cage cage;
  bool convex = false;             ///< the enclosed region is convex
  bool positively_oriented = true; ///< counter-clockwise (2D) / outward normals (3D)
  double measure = 0.0;            ///< |area| or |volume| known in closed form, 0 if unknown
};

/// GoogleTest printer: the name (instead of a byte dump) in failure messages.
void PrintTo(const CatalogueCage& entry, std::ostream* os);

// --- 2D ---------------------------------------------------------------------------------------
/// The unit square [0,1]^2, counter-clockwise.
Cage unit_square();
/// Regular polygon with @p n vertices on the circle of radius @p radius, counter-clockwise.
Cage regular_polygon(int n, double radius = 1.0);
/// Star with @p tips tips (2 * tips vertices), alternating radii @p outer and @p inner.
Cage star_polygon(int tips, double outer, double inner);
/// A "U": the 3 x 2 rectangle with the notch [1,2] x [1,2] cut out (8 vertices), CCW.
Cage u_polygon();
/// An "L": [0,2] x [0,2] minus [1,2] x [1,2] (6 vertices), CCW.
Cage l_polygon();

/// Reads a 2D polygon from an OBJ file: the x and y of its `v` lines, in order; other lines
/// (vn, g, l) are ignored. Throws std::runtime_error if the file cannot be read.
Cage read_polygon_obj(const std::string& path);
/// Folder of the LBC authors' example cages (BARYLAB_SHARED_DIR/lbc/cages).
std::string shared_cage_directory();

/// One of the LBC authors' reference runs (BARYLAB_SHARED_DIR/lbc/reference): their
/// triangulation, the mesh index of each cage vertex, their weights (#V by #C) and the cage.
struct LBCReferenceRun
{
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  Eigen::VectorXi control;
  Eigen::MatrixXd W;
  Cage cage;
};
/// Reads reference run @p name (Gil_Gecko, LBClogo, cactus, woody); false when its files are
/// absent or the weights cannot be read.
bool read_lbc_reference(const std::string& name, LBCReferenceRun& run);

/// The built-in 2D cages: square, regular 64-gon, 10-vertex star (radii 1 and 0.3), U, L and
/// the clockwise star.
std::vector<CatalogueCage> builtin_cages_2d();
/// The LBC example cages found in shared_cage_directory() (empty when the folder is absent).
std::vector<CatalogueCage> shared_cages_2d();
/// builtin_cages_2d() followed by shared_cages_2d().
std::vector<CatalogueCage> cages_2d();

// --- 3D ---------------------------------------------------------------------------------------
/// The unit cube [0,1]^3 as 12 outward triangles; vertex i is (i & 1, i >> 1 & 1, i >> 2 & 1).
Cage unit_cube();
/// The regular octahedron with vertices (+-1,0,0), (0,+-1,0), (0,0,+-1) (in that order: +x, -x,
/// +y, -y, +z, -z), 8 outward faces.
Cage octahedron();
/// u_polygon() extruded over z in [0, 1]: 16 vertices, 28 outward faces, volume 5.
Cage u_box();
/// Icosahedron subdivided @p subdivisions times (20 * 4^s faces), each vertex's radius scaled
/// by 1 + noise * U(-1, 1) from a fixed-seed generator. Outward, star-shaped about the origin.
Cage noisy_icosphere(int subdivisions, double noise, std::uint64_t seed);

/// cube (unit), octahedron, U box, icosphere (320 faces), inward cube.
std::vector<CatalogueCage> cages_3d();

// --- Orientation ------------------------------------------------------------------------------
/// The same cage with the opposite orientation: 2D reverses the vertex order (vertex i becomes
/// n-1-i), 3D flips every face (vertex order unchanged).
Cage reversed(const Cage& cage);
/// Column of reversed(cage)'s weights that belongs to vertex @p i of @p cage.
Index reversed_index(const Cage& cage, Index i);

// --- Geometry (independent of core) -----------------------------------------------------------
/// Winding number of the cage around @p x: 2D sum of signed angles / 2 pi, 3D sum of signed
/// solid angles (Van Oosterom & Strackee 1983) / 4 pi. +-1 inside, 0 outside.
double winding_number(const Cage& cage, const double* x);
/// Euclidean distance from @p x to the cage's boundary (edges in 2D, triangles in 3D).
double boundary_distance(const Cage& cage, const double* x);
/// Undirected edges (a < b) of a 3D cage, sorted; of a 2D cage, (i, i+1 mod n) in order.
std::vector<std::pair<int, int>> cage_edges(const Cage& cage);
/// Unit normal of face @p f (3D) or edge @p f (2D) pointing into the enclosed region.
Eigen::VectorXd inward_normal(const Cage& cage, Index f);

/// Deterministic generator (SplitMix64); the same numbers on every platform and compiler,
/// unlike std::uniform_real_distribution.
class Rng
{
public:
  explicit Rng(std::uint64_t seed)
    : state_(seed)
  {
  }
  std::uint64_t next();
  /// Uniform in [0, 1).
  double uniform();
  /// Uniform in [a, b).
  double uniform(double a, double b) { return a + (b - a) * uniform(); }

private:
  std::uint64_t state_;
};

/// @p count points strictly inside the cage (|winding number| > 1/2), each at least
/// min_relative_distance * diameter from the boundary: rejection sampling in the bounding box.
Points sample_inside(
  const Cage& cage, Index count, double min_relative_distance, std::uint64_t seed);
/// @p count points outside the cage, at least min_relative_distance * diameter from the
/// boundary, in the bounding box scaled by @p box_scale about its centre.
Points sample_outside(const Cage& cage, Index count, double min_relative_distance, double box_scale,
  std::uint64_t seed);

} // namespace bary::test
