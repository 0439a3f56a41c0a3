#include "igl_formats.h"

#include <cctype>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace bary::test
{
namespace
{

std::ifstream open(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot open " + path);
  return in;
}

[[noreturn]] void fail(const std::string& path, const std::string& what)
{
  throw std::runtime_error(path + ": " + what);
}

template<class T>
T next(std::istream& in, const std::string& path, const char* what)
{
  T value{};
  if (!(in >> value))
    fail(path, std::string("cannot read ") + what);
  return value;
}

/// Reads @p rows lines of @p cols integers (1-based in the file) followed by a reference
/// number into 0-based rows of a matrix.
Eigen::MatrixXi read_elements(std::istream& in, const std::string& path, Eigen::Index rows, int cols,
  const char* what)
{
  Eigen::MatrixXi M(rows, cols);
  for (Eigen::Index r = 0; r < rows; ++r)
  {
    for (int c = 0; c < cols; ++c)
      M(r, c) = next<int>(in, path, what) - 1;
    next<long long>(in, path, what); // reference number
  }
  return M;
}

} // namespace

MeditMesh read_medit_mesh(const std::string& path)
{
  std::ifstream in = open(path);
  MeditMesh mesh;
  int dimension = 3;
  std::string keyword;
  while (in >> keyword)
  {
    if (keyword == "End")
      break;
    if (keyword == "MeshVersionFormatted")
      next<int>(in, path, "the mesh version");
    else if (keyword == "Dimension")
      dimension = next<int>(in, path, "the dimension");
    else if (keyword == "Vertices")
    {
      const auto n = next<Eigen::Index>(in, path, "the vertex count");
      mesh.V.resize(n, dimension);
      for (Eigen::Index i = 0; i < n; ++i)
      {
        for (int k = 0; k < dimension; ++k)
          mesh.V(i, k) = next<double>(in, path, "a vertex coordinate");
        next<long long>(in, path, "a vertex reference");
      }
    }
    else if (keyword == "Tetrahedra")
      mesh.T = read_elements(in, path, next<Eigen::Index>(in, path, "the tetrahedron count"), 4,
        "a tetrahedron");
    else if (keyword == "Triangles")
      mesh.F = read_elements(in, path, next<Eigen::Index>(in, path, "the triangle count"), 3,
        "a triangle");
    else if (keyword == "Edges")
      read_elements(in, path, next<Eigen::Index>(in, path, "the edge count"), 2, "an edge");
    else if (keyword[0] == '#')
      std::getline(in, keyword); // comment
    else
      fail(path, "unknown section \"" + keyword + "\"");
  }
  if (mesh.V.rows() == 0)
    fail(path, "no Vertices section");
  return mesh;
}

TgfSkeleton read_tgf(const std::string& path)
{
  std::ifstream in = open(path);
  std::vector<Eigen::Vector3d> joints;
  std::vector<Eigen::Vector2i> edges;
  std::string line;
  int section = 0; // 0: vertices, 1: edges, 2: after the second '#'
  int line_number = 0;
  while (std::getline(in, line))
  {
    ++line_number;
    std::istringstream s(line);
    std::string first;
    if (!(s >> first))
      continue; // blank
    if (first[0] == '#')
    {
      ++section;
      continue;
    }
    if (section == 0)
    {
      Eigen::Vector3d p;
      if (!(s >> p.x() >> p.y() >> p.z()))
        fail(path, "line " + std::to_string(line_number) + ": cannot read a joint position");
      joints.push_back(p);
    }
    else if (section == 1)
    {
      int b = 0;
      if (!(s >> b))
        fail(path, "line " + std::to_string(line_number) + ": cannot read an edge");
      edges.emplace_back(std::stoi(first) - 1, b - 1);
    }
  }
  TgfSkeleton skeleton;
  skeleton.C.resize(static_cast<Eigen::Index>(joints.size()), 3);
  for (std::size_t i = 0; i < joints.size(); ++i)
    skeleton.C.row(static_cast<Eigen::Index>(i)) = joints[i].transpose();
  skeleton.E.resize(static_cast<Eigen::Index>(edges.size()), 2);
  for (std::size_t i = 0; i < edges.size(); ++i)
    skeleton.E.row(static_cast<Eigen::Index>(i)) = edges[i].transpose();
  return skeleton;
}

Eigen::MatrixXd read_dmat(const std::string& path)
{
  std::ifstream in = open(path);
  const auto cols = next<Eigen::Index>(in, path, "the column count");
  const auto rows = next<Eigen::Index>(in, path, "the row count");
  Eigen::MatrixXd M(rows, cols);
  for (Eigen::Index c = 0; c < cols; ++c)
    for (Eigen::Index r = 0; r < rows; ++r)
      M(r, c) = next<double>(in, path, "a matrix entry");
  return M;
}

ObjMesh read_obj(const std::string& path)
{
  std::ifstream in = open(path);
  std::vector<double> v;
  std::vector<int> f;
  std::string line;
  while (std::getline(in, line))
  {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v")
    {
      double x, y, z;
      if (!(s >> x >> y >> z))
        throw std::runtime_error(path + ": bad vertex line: " + line);
      v.insert(v.end(), { x, y, z });
    }
    else if (tag == "f")
    {
      std::vector<int> ids;
      std::string token;
      while (s >> token)
      {
        const int i = std::stoi(token.substr(0, token.find('/')));
        ids.push_back(i > 0 ? i - 1 : static_cast<int>(v.size() / 3) + i); // negative: relative
      }
      if (ids.size() < 3)
        throw std::runtime_error(path + ": bad face line: " + line);
      for (std::size_t k = 1; k + 1 < ids.size(); ++k)
        f.insert(f.end(), { ids[0], ids[k], ids[k + 1] });
    }
  }
  ObjMesh mesh;
  mesh.V = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
    v.data(), static_cast<Eigen::Index>(v.size() / 3), 3);
  mesh.F = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(
    f.data(), static_cast<Eigen::Index>(f.size() / 3), 3);
  return mesh;
}

} // namespace bary::test
