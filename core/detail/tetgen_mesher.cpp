#include "core/detail/tetgen_mesher.h"

#include "core/common/error.h"

#include <tetgen.h>

#include <mutex>
#include <new>
#include <vector>

namespace bary::detail
{
namespace
{

std::mutex& tetgen_mutex()
{
  static std::mutex m;
  return m;
}

std::string describe_tetgen_error(int code)
{
  switch (code)
  {
    case 1: return "out of memory";
    case 2: return "internal error";
    case 3: return "a self-intersection of the surface was detected";
    case 4: return "a very small input feature was detected (below TetGen's 1e-8 relative tolerance)";
    case 5: return "two very close input facets were detected";
    case 10: return "input error (invalid input or switches that do not go together)";
    default: return "unknown error";
  }
}

} // namespace

TetgenOutput tetgen_tetrahedralize(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
  const Eigen::MatrixXd& addin, const std::string& switches)
{
  if (V.cols() != 3 || F.cols() != 3 || (addin.size() != 0 && addin.cols() != 3))
    throw Error(ErrorCode::SizeMismatch, "TetGen needs 3D points and triangles");

  // tetgenio frees its arrays with delete[] in its destructor. The extra points are appended to
  // the PLC's points as isolated vertices: TetGen 1.5.0's 'i' (insert an addin point list)
  // crashed on some cages and silently dropped points under 'Y'.
  tetgenio in, out;
  const Index np = V.rows() + addin.rows();
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(np);
  in.pointlist = new REAL[static_cast<std::size_t>(3 * np)];
  for (Index i = 0; i < np; ++i)
    for (int k = 0; k < 3; ++k)
      in.pointlist[3 * i + k] = i < V.rows() ? V(i, k) : addin(i - V.rows(), k);
  in.numberoffacets = static_cast<int>(F.rows());
  in.facetlist = new tetgenio::facet[static_cast<std::size_t>(F.rows())];
  in.facetmarkerlist = new int[static_cast<std::size_t>(F.rows())];
  for (Index f = 0; f < F.rows(); ++f)
  {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k)
      facet.polygonlist[0].vertexlist[k] = F(f, k);
    in.facetmarkerlist[f] = static_cast<int>(f) + 1; // 0 means "no marker" to TetGen
  }

  std::vector<char> sw(switches.begin(), switches.end());
  sw.push_back('\0');
  {
    std::lock_guard<std::mutex> lock(tetgen_mutex());
    try
    {
      tetrahedralize(sw.data(), &in, &out);
    }
    catch (int code) // TETLIBRARY: terminatetetgen() throws its exit code
    {
      const std::string message = "TetGen failed with error " + std::to_string(code) + " (" +
        describe_tetgen_error(code) + ") on switches \"" + switches + "\"";
      if (code == 3 || code == 4 || code == 5)
        throw Error(ErrorCode::InvalidCage,
          message + "; check the cage for faces that touch or nearly touch");
      if (code == 10)
        throw Error(ErrorCode::InvalidArgument, message);
      throw Error(ErrorCode::Internal, message + "; please report it with the cage");
    }
  }

  if (out.numberofcorners != 4 && out.numberoftetrahedra > 0)
    throw Error(ErrorCode::Internal,
      "TetGen returned elements with " + std::to_string(out.numberofcorners) +
        " corners (expected linear tetrahedra)");
  TetgenOutput result;
  result.V.resize(out.numberofpoints, 3);
  for (int i = 0; i < out.numberofpoints; ++i)
    for (int k = 0; k < 3; ++k)
      result.V(i, k) = out.pointlist[3 * i + k];
  result.T.resize(out.numberoftetrahedra, 4);
  for (int t = 0; t < out.numberoftetrahedra; ++t)
    for (int k = 0; k < 4; ++k)
      result.T(t, k) = out.tetrahedronlist[4 * t + k];
  result.boundary_faces.resize(out.numberoftrifaces, 3);
  result.boundary_face_input.setConstant(out.numberoftrifaces, -1);
  for (int f = 0; f < out.numberoftrifaces; ++f)
  {
    for (int k = 0; k < 3; ++k)
      result.boundary_faces(f, k) = out.trifacelist[3 * f + k];
    if (out.trifacemarkerlist && out.trifacemarkerlist[f] >= 1 &&
      out.trifacemarkerlist[f] <= F.rows())
      result.boundary_face_input(f) = out.trifacemarkerlist[f] - 1;
  }
  return result;
}

} // namespace bary::detail
