#include "core/coordinates/bbw_handles.h"

#include "core/common/error.h"
#include "core/detail/closest_point.h"
#include "core/detail/format.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace bary
{
namespace
{
constexpr double pi = 3.14159265358979323846;

/// Closest point of the segment (a, b) to p: its barycentric coordinates (1 - t, t) in @p bary
/// and the distance.
double segment_closest(const Eigen::VectorXd& p, const Eigen::VectorXd& a,
  const Eigen::VectorXd& b, Eigen::Vector3d& bary)
{
  const double t = detail::closest_on_segment(p, a, b);
  bary = Eigen::Vector3d(1.0 - t, t, 0.0);
  return (p - a - t * (b - a)).norm();
}

/// Closest point of the triangle (a, b, c) to p: its barycentric coordinates in @p bary and the
/// distance.
double triangle_closest(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
  const Eigen::Vector3d& b, const Eigen::Vector3d& c, Eigen::Vector3d& bary)
{
  bary = detail::closest_on_triangle(p, a, b, c);
  return (p - (bary(0) * a + bary(1) * b + bary(2) * c)).norm();
}

/// Distance of p to face f of F over C, and the face's barycentric coordinates there.
double face_closest(const Eigen::VectorXd& p, const Eigen::MatrixXd& C, const Eigen::MatrixXi& F,
  Index f, Eigen::Vector3d& bary)
{
  if (F.cols() == 2)
    return segment_closest(p, C.row(F(f, 0)).transpose(), C.row(F(f, 1)).transpose(), bary);
  return triangle_closest(Eigen::Vector3d(p), Eigen::Vector3d(C.row(F(f, 0)).transpose()),
    Eigen::Vector3d(C.row(F(f, 1)).transpose()), Eigen::Vector3d(C.row(F(f, 2)).transpose()),
    bary);
}

/// Generalized winding number of the closed polygon (edges) / closed triangle surface F at p.
double winding_number(const Eigen::VectorXd& p, const Eigen::MatrixXd& C, const Eigen::MatrixXi& F)
{
  double total = 0;
  for (Index f = 0; f < F.rows(); ++f)
  {
    if (F.cols() == 2)
    {
      const Eigen::Vector2d a = (C.row(F(f, 0)).transpose() - p).head<2>(),
                            b = (C.row(F(f, 1)).transpose() - p).head<2>();
      total += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    }
    else
    {
      // Van Oosterom & Strackee: the solid angle of the triangle seen from p.
      const Eigen::Vector3d a = C.row(F(f, 0)).transpose() - p, b = C.row(F(f, 1)).transpose() - p,
                            c = C.row(F(f, 2)).transpose() - p;
      const double la = a.norm(), lb = b.norm(), lc = c.norm();
      const double numerator = a.dot(b.cross(c));
      const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
      total += 2.0 * std::atan2(numerator, denominator);
    }
  }
  return total / (F.cols() == 2 ? 2.0 * pi : 4.0 * pi);
}
} // namespace

BBWHandles mixed_bbw_handles(const Eigen::MatrixXd& V, const Skeleton& skeleton,
  const std::vector<std::vector<int>>& vertex_regions, double tolerance)
{
  const Index nv = V.rows();
  if (nv == 0)
    throw Error(ErrorCode::EmptyInput, "the mesh has no vertices");
  const bool has_skeleton = skeleton.handle_count() > 0;
  if (!has_skeleton && vertex_regions.empty())
    throw Error(ErrorCode::EmptyInput,
      "no handle: give point handles, bones, cage faces or regions");
  if (has_skeleton)
  {
    validate_skeleton(skeleton);
    if (skeleton.C.cols() != V.cols())
      throw Error(ErrorCode::SizeMismatch,
        "the handles are " + std::to_string(skeleton.C.cols()) + "D but the mesh vertices are " +
          std::to_string(V.cols()) + "D");
  }
  if (!(tolerance > 0.0))
  {
    const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
    tolerance = 1e-6 * (diagonal > 0.0 ? diagonal : 1.0);
  }
  BBWHandles handles;
  if (skeleton.P.size() > 0 || skeleton.BE.rows() > 0)
    handles = handles_from_skeleton(V, skeleton.C, skeleton.P, skeleton.BE, tolerance);
  const Index np = skeleton.P.size(), nb = skeleton.BE.rows();
  const Eigen::VectorXi cage = has_skeleton ? skeleton.cage_joints() : Eigen::VectorXi();
  const Index ncage = cage.size();
  const auto nregions = static_cast<Index>(skeleton.regions.size());
  const Index first_cage = np + nb, first_region = first_cage + ncage,
              first_vertex_region = first_region + nregions;
  const Index m = first_vertex_region + static_cast<Index>(vertex_regions.size());

  // owner[i]: which handle fixes mesh vertex i (-1 none); names for the overlap errors.
  std::vector<Index> owner(static_cast<std::size_t>(nv), -1);
  auto handle_name = [&](Index j) -> std::string {
    if (j < np)
      return "point handle " + std::to_string(j) + " (joint " + std::to_string(skeleton.P(j)) + ")";
    if (j < first_cage)
      return "bone " + std::to_string(j - np);
    if (j < first_region)
      return "cage vertex handle " + std::to_string(j - first_cage) + " (joint " +
        std::to_string(cage(j - first_cage)) + ")";
    if (j < first_vertex_region)
      return "region " + std::to_string(j - first_region);
    return "vertex region " + std::to_string(j - first_vertex_region);
  };
  for (Index p = 0; p < handles.point_vertex.size(); ++p)
    owner[static_cast<std::size_t>(handles.point_vertex(p))] = p;
  for (std::size_t b = 0; b < handles.bone_vertices.size(); ++b)
    for (int i : handles.bone_vertices[b])
      owner[static_cast<std::size_t>(i)] = np + static_cast<Index>(b);
  // owner_kind: the first handle of a kind that may share a vertex within itself (a cage's
  // faces share vertices; point handles and bones share joints, checked by
  // bbw_boundary_conditions): 0 points and bones, 1 cage, 2 + r region r.
  auto kind = [&](Index j) -> Index {
    return j < first_cage ? 0 : j < first_region ? 1 : 2 + (j - first_region);
  };
  std::vector<int> rows_vertex;
  std::vector<Eigen::RowVectorXd> rows;
  std::vector<Index> row_of(static_cast<std::size_t>(nv), -1);
  auto claim = [&](Index i, Index j, const std::string& where) {
    Index& o = owner[static_cast<std::size_t>(i)];
    if (o >= 0 && kind(o) != kind(j))
      throw Error(ErrorCode::InvalidArgument,
        "mesh vertex " + std::to_string(i) + " is fixed by both " + handle_name(o) + " and " +
          handle_name(j) + where + ": handles must be disjoint (§2)",
        "move the handles apart");
    if (o < 0)
      o = j;
  };

  // Cage faces (Eq. 4): linear hat functions of the face's joints at the closest point.
  std::vector<Index> cage_column(static_cast<std::size_t>(has_skeleton ? skeleton.C.rows() : 0), -1);
  for (Index k = 0; k < ncage; ++k)
    cage_column[static_cast<std::size_t>(cage(k))] = first_cage + k;
  std::vector<char> cage_touched(static_cast<std::size_t>(ncage), 0);
  for (Index f = 0; f < skeleton.CF.rows(); ++f)
    for (Index i = 0; i < nv; ++i)
    {
      Eigen::Vector3d bary;
      if (face_closest(V.row(i).transpose(), skeleton.C, skeleton.CF, f, bary) > tolerance)
        continue;
      const Index first_joint_column = cage_column[static_cast<std::size_t>(skeleton.CF(f, 0))];
      claim(i, first_joint_column, " (on cage face " + std::to_string(f) + ")");
      if (row_of[static_cast<std::size_t>(i)] >= 0)
        continue; // on several faces (an edge or vertex of the cage): the same linear values
      Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(m);
      for (Index k = 0; k < skeleton.CF.cols(); ++k)
      {
        const Index column = cage_column[static_cast<std::size_t>(skeleton.CF(f, k))];
        row(column) += bary(k);
        if (bary(k) > 0)
          cage_touched[static_cast<std::size_t>(column - first_cage)] = 1;
      }
      row_of[static_cast<std::size_t>(i)] = static_cast<Index>(rows.size());
      rows_vertex.push_back(static_cast<int>(i));
      rows.push_back(std::move(row));
    }
  for (Index k = 0; k < ncage; ++k)
    if (!cage_touched[static_cast<std::size_t>(k)])
      throw Error(ErrorCode::InvalidArgument,
        handle_name(first_cage + k) + " is fixed at no mesh vertex: none of its cage faces "
          "passes within " + detail::format_number(tolerance) + " of a mesh vertex",
        "mesh the domain with the cage faces sampled (give a closed surface / polygon domain), "
        "or remove the cage vertex");

  auto add_region_vertex = [&](Index i, Index j, const std::string& where) {
    claim(i, j, where);
    if (row_of[static_cast<std::size_t>(i)] >= 0)
      return;
    Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(m);
    row(j) = 1.0;
    row_of[static_cast<std::size_t>(i)] = static_cast<Index>(rows.size());
    rows_vertex.push_back(static_cast<int>(i));
    rows.push_back(std::move(row));
  };
  for (Index r = 0; r < nregions; ++r)
  {
    const Eigen::MatrixXi& F = skeleton.regions[static_cast<std::size_t>(r)];
    const Index j = first_region + r;
    Index count = 0;
    for (Index i = 0; i < nv; ++i)
    {
      const Eigen::VectorXd p = V.row(i).transpose();
      bool in = std::abs(winding_number(p, skeleton.C, F)) >= 0.5;
      for (Index f = 0; !in && f < F.rows(); ++f)
      {
        Eigen::Vector3d bary;
        in = face_closest(p, skeleton.C, F, f, bary) <= tolerance;
      }
      if (in)
      {
        add_region_vertex(i, j, "");
        ++count;
      }
    }
    if (count == 0)
      throw Error(ErrorCode::InvalidArgument,
        handle_name(j) + " holds no mesh vertex (none inside it or within " +
          detail::format_number(tolerance) + " of its boundary)",
        "enlarge the region or refine the mesh there");
  }
  for (std::size_t r = 0; r < vertex_regions.size(); ++r)
  {
    const Index j = first_vertex_region + static_cast<Index>(r);
    if (vertex_regions[r].empty())
      throw Error(ErrorCode::EmptyInput, handle_name(j) + " lists no mesh vertex");
    for (int i : vertex_regions[r])
    {
      if (i < 0 || i >= nv)
        throw Error(ErrorCode::InvalidArgument,
          handle_name(j) + " lists mesh vertex " + std::to_string(i) + ", outside [0, " +
            std::to_string(nv) + ")");
      add_region_vertex(i, j, "");
    }
  }

  handles.extra_handles = m - first_cage;
  handles.fixed_vertices.resize(static_cast<Index>(rows.size()));
  handles.fixed_values.resize(static_cast<Index>(rows.size()), m);
  for (std::size_t k = 0; k < rows.size(); ++k)
  {
    handles.fixed_vertices(static_cast<Index>(k)) = rows_vertex[k];
    handles.fixed_values.row(static_cast<Index>(k)) = rows[k];
  }
  return handles;
}

Eigen::VectorXd shape_preservation_per_element(
  const Eigen::MatrixXi& T, const Eigen::VectorXd& rho, Index vertex_count)
{
  if (rho.size() != vertex_count)
    throw Error(ErrorCode::SizeMismatch,
      "the shape-preservation brush has " + std::to_string(rho.size()) +
        " values, expected one per domain vertex (" + std::to_string(vertex_count) + ")");
  for (Index i = 0; i < rho.size(); ++i)
  {
    if (!std::isfinite(rho(i)))
      throw Error(ErrorCode::NonFinite,
        "the shape-preservation brush is NaN or infinite at vertex " + std::to_string(i));
    if (rho(i) < 0.0)
      throw Error(ErrorCode::InvalidArgument,
        "the shape-preservation brush is negative at vertex " + std::to_string(i) + " (" +
          detail::format_number(rho(i)) + "); it must be >= 0");
  }
  Eigen::VectorXd element(T.rows());
  for (Index t = 0; t < T.rows(); ++t)
  {
    double sum = 0;
    for (Index k = 0; k < T.cols(); ++k)
    {
      const int i = T(t, k);
      if (i < 0 || i >= vertex_count)
        throw Error(ErrorCode::InvalidArgument,
          "element " + std::to_string(t) + " refers to vertex " + std::to_string(i) +
            ", outside [0, " + std::to_string(vertex_count) + ")");
      sum += rho(i);
    }
    element(t) = T.cols() > 0 ? sum / static_cast<double>(T.cols()) : 0.0;
  }
  return element;
}

} // namespace bary
