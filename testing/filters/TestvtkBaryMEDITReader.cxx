// vtkBaryMEDITReader, vtkBaryTGFReader and vtkBaryDataIO's .dmat functions: libigl/TetGen formats
// used by the mesh-based methods (domain meshes, skeleton handles, poses).
#include "filters_test_utils.h"

#include "vtkBaryDataIO.h"
#include "vtkBaryMEDITReader.h"
#include "vtkBaryTGFReader.h"

#include "core/common/error.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace barylab_test;
namespace fs = std::filesystem;

namespace
{
std::string Write(const std::string& name, const std::string& text)
{
  const fs::path dir = fs::path(BARYLAB_TEST_OUTPUT_DIR) / "formats";
  fs::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

std::string Shared(const std::string& name)
{
  return std::string(BARYLAB_SHARED_DIR) + "/igl/" + name;
}

/// Reads @p path with vtkBaryDataIO and returns the error message ("" on success).
std::string ReadError(const std::string& path)
{
  try
  {
    vtkBaryDataIO::Read(path);
  }
  catch (const bary::Error& e)
  {
    return e.what();
  }
  return "";
}

const char* const kTwoTets = "MeshVersionFormatted 1\nDimension 3\n"
                             "# a comment\n"
                             "Vertices\n5\n0 0 0 1\n1 0 0 1\n0 1 0 1\n0 0 1 1\n1 1 1 2\n"
                             "Triangles\n1\n1 2 3 0\n"
                             "Tetrahedra\n2\n1 2 3 4 7\n2 3 4 5 8\nEnd\n";
} // namespace

TEST(vtkBaryMEDITReader, ReadsTetrahedraAndReferences)
{
  auto data = vtkBaryDataIO::Read(Write("two.mesh", kTwoTets));
  auto* grid = vtkUnstructuredGrid::SafeDownCast(data);
  ASSERT_NE(grid, nullptr);
  EXPECT_EQ(grid->GetNumberOfPoints(), 5);
  ASSERT_EQ(grid->GetNumberOfCells(), 2) << "boundary triangles are dropped for a volume mesh";
  EXPECT_EQ(grid->GetCellType(0), VTK_TETRA);
  vtkIdType n;
  const vtkIdType* ids;
  grid->GetCellPoints(1, n, ids);
  EXPECT_EQ(ids[0], 1);
  EXPECT_EQ(ids[3], 4) << "indices are 1-based in the file";
  vtkDataArray* ref = grid->GetCellData()->GetArray("Reference");
  ASSERT_NE(ref, nullptr);
  EXPECT_EQ(ref->GetTuple1(1), 8);
  double x[3];
  grid->GetPoint(4, x);
  EXPECT_EQ(x[0], 1.0);
  EXPECT_EQ(x[2], 1.0);
}

TEST(vtkBaryMEDITReader, TwoDimensionalTriangles)
{
  auto data = vtkBaryDataIO::Read(Write("tri.mesh",
    "MeshVersionFormatted 2 Dimension 2 Vertices 3 0 0 0 1 0 0 0 1 0 Triangles 1 1 2 3 5 End"));
  ASSERT_EQ(data->GetNumberOfCells(), 1);
  EXPECT_EQ(data->GetCellType(0), VTK_TRIANGLE);
  double x[3];
  data->GetPoint(2, x);
  EXPECT_EQ(x[1], 1.0);
  EXPECT_EQ(x[2], 0.0);
}

TEST(vtkBaryMEDITReader, ErrorsNameTheProblem)
{
  EXPECT_NE(ReadError(Write("trunc.mesh", "Dimension 3\nVertices\n3\n0 0 0 0\n1 0 0 0\n"))
              .find("vertex 3 of 3 is truncated"),
    std::string::npos);
  EXPECT_NE(ReadError(Write("index.mesh", "Dimension 3 Vertices 1 0 0 0 0 Tetrahedra 1 1 2 3 4 0"))
              .find("refers to vertex 2 but there are 1 vertices"),
    std::string::npos);
  EXPECT_NE(ReadError(Write("kw.mesh", "Dimension 3\nBananas 3\n")).find("unknown keyword 'Bananas'"),
    std::string::npos);
  EXPECT_NE(ReadError(Write("nan.mesh", "Dimension 3 Vertices 1 nan 0 0 0")).find("vertex 1"),
    std::string::npos);
}

TEST(vtkBaryMEDITReader, LibiglKnight)
{
  if (!fs::exists(Shared("decimated-knight.mesh")))
    GTEST_SKIP() << "shared data absent: " << Shared("decimated-knight.mesh");
  auto data = vtkBaryDataIO::Read(Shared("decimated-knight.mesh"));
  EXPECT_EQ(data->GetNumberOfPoints(), 1822); // the file's Vertices count
  ASSERT_GT(data->GetNumberOfCells(), 0);
  EXPECT_EQ(data->GetCellType(0), VTK_TETRA);
}

TEST(vtkBaryTGFReader, BonesAndPointHandles)
{
  // vertices 1-2-3 form two bones; vertex 4 is on no bone: a point handle
  auto data = vtkBaryDataIO::Read(
    Write("s.tgf", "1 0 0 0\n2 1 0 0\n3 2 0 0\n4 5 5 5\n#\n1 2\n2 3 0 0 0\n#\n"));
  auto* poly = vtkPolyData::SafeDownCast(data);
  ASSERT_NE(poly, nullptr);
  EXPECT_EQ(poly->GetNumberOfPoints(), 4);
  ASSERT_EQ(poly->GetNumberOfLines(), 2);
  ASSERT_EQ(poly->GetNumberOfVerts(), 1);
  vtkIdType n;
  const vtkIdType* ids;
  poly->GetLines()->GetCellAtId(1, n, ids);
  EXPECT_EQ(ids[0], 1);
  EXPECT_EQ(ids[1], 2);
  poly->GetVerts()->GetCellAtId(0, n, ids);
  EXPECT_EQ(ids[0], 3);
}

TEST(vtkBaryTGFReader, Errors)
{
  EXPECT_NE(ReadError(Write("bad.tgf", "1 0 0 0\n2 1 0 0\n#\n1 3\n")).find("edge (1, 3)"),
    std::string::npos);
  EXPECT_NE(ReadError(Write("word.tgf", "hello world\n")).find("expected numbers"), std::string::npos);
}

TEST(vtkBaryTGFReader, LibiglKnightSkeleton)
{
  if (!fs::exists(Shared("decimated-knight.tgf")))
    GTEST_SKIP() << "shared data absent";
  auto data = vtkBaryDataIO::ReadPolyData(Shared("decimated-knight.tgf"));
  EXPECT_EQ(data->GetNumberOfPoints(), 8);
  EXPECT_EQ(data->GetNumberOfLines(), 7);
  EXPECT_EQ(data->GetNumberOfVerts(), 0) << "every knight joint lies on a bone";
}

TEST(vtkBaryDataIODMAT, RoundTripIsExactAndColumnMajor)
{
  Eigen::MatrixXd M(3, 2);
  M << 0.1, -2.5e-300, 1.0 / 3.0, 4, 5e300, -0.0;
  const std::string path = (fs::path(BARYLAB_TEST_OUTPUT_DIR) / "formats" / "m.dmat").string();
  fs::create_directories(fs::path(path).parent_path());
  vtkBaryDataIO::WriteDMAT(M, path);
  EXPECT_EQ(vtkBaryDataIO::ReadDMAT(path), M);
  // the header is "columns rows" and values go column by column
  std::ifstream in(path);
  int cols, rows;
  double first, second;
  in >> cols >> rows >> first >> second;
  EXPECT_EQ(cols, 2);
  EXPECT_EQ(rows, 3);
  EXPECT_EQ(first, 0.1);
  EXPECT_EQ(second, 1.0 / 3.0);
}

TEST(vtkBaryDataIODMAT, Errors)
{
  auto code_of = [](const std::string& p) {
    try
    {
      vtkBaryDataIO::ReadDMAT(p);
    }
    catch (const bary::Error& e)
    {
      return std::make_pair(e.code(), std::string(e.what()));
    }
    return std::make_pair(bary::ErrorCode::Internal, std::string("did not throw"));
  };
  auto [c1, m1] = code_of(Write("short.dmat", "2 2\n1 2 3\n"));
  EXPECT_EQ(c1, bary::ErrorCode::Io);
  EXPECT_NE(m1.find("value 4 of 4"), std::string::npos) << m1;
  auto [c2, m2] = code_of(Write("nan.dmat", "1 1\nnan\n"));
  EXPECT_EQ(c2, bary::ErrorCode::NonFinite) << m2;
  EXPECT_NE(m2.find("value 1 is not finite"), std::string::npos) << m2;
  auto [c3, m3] = code_of(Write("head.dmat", "x y\n"));
  EXPECT_NE(m3.find("columns rows"), std::string::npos) << m3;
  auto [c4, m4] = code_of("/nonexistent/file.dmat");
  EXPECT_EQ(c4, bary::ErrorCode::Io);
}

TEST(vtkBaryDataIODMAT, LibiglHandPose)
{
  if (!fs::exists(Shared("hand-pose.dmat")))
    GTEST_SKIP() << "shared data absent";
  const Eigen::MatrixXd pose = vtkBaryDataIO::ReadDMAT(Shared("hand-pose.dmat"));
  ASSERT_EQ(pose.rows(), 80); // one quaternion per bone, 20 bones
  ASSERT_EQ(pose.cols(), 1);
  for (int b = 0; b < 20; ++b) // unit quaternions
    EXPECT_NEAR(pose.block(4 * b, 0, 4, 1).norm(), 1.0, 1e-6) << "bone " << b;
}
