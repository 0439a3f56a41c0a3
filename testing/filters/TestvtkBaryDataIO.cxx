// Tests of vtkBaryDataIO (read/write by extension, errors as bary::Error, atomic writes) and of
// vtkBaryOFFReader / vtkBaryOFFWriter on hand-written files.
#include "filters_test_utils.h"

#include "vtkBaryConversion.h"
#include "vtkBaryDataIO.h"
#include "vtkBaryFileReader.h"
#include "vtkBaryFileWriter.h"
#include "vtkBaryOFFReader.h"
#include "vtkBaryOFFWriter.h"

#include "core/common/error.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkXMLPolyDataWriter.h"
#include "vtkImageData.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <set>

namespace
{
using namespace barylab_test;
namespace fs = std::filesystem;

/// A fresh, empty folder @p name under BARYLAB_TEST_OUTPUT_DIR, inside a folder of the running
/// test's own (ctest may run the tests of this file in parallel).
fs::path Scratch(const std::string& name)
{
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string owner = std::string(test->test_suite_name()) + "." + test->name();
  std::replace(owner.begin(), owner.end(), '/', '_');
  const fs::path dir = fs::path(BARYLAB_TEST_OUTPUT_DIR) / "filters_io" / owner / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string WriteText(const fs::path& path, const std::string& text)
{
  std::ofstream out(path, std::ios::binary);
  out << text;
  return path.string();
}

std::set<std::string> ListFolder(const fs::path& dir)
{
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    names.insert(entry.path().filename().string());
  return names;
}

/// A small closed triangle mesh (an irregular octahedron, 6 points, 8 triangles) with
/// coordinates that need all 17 digits, and a 3-component "Weights" point-data array.
vtkSmartPointer<vtkPolyData> SmallMesh()
{
  auto mesh = MakePointCloud({ { 1.1234567890123457, 0.0123456789012345, -0.0314159265358979 },
    { -0.9876543210987654, 0.0271828182845905, 0.0141421356237310 },
    { 0.0161803398874989, 1.2345678901234567, 0.0173205080756888 },
    { 0.0223606797749979, -1.1111111111111112, -0.0101010101010101 },
    { -0.0333333333333333, 0.0444444444444444, 0.9090909090909091 },
    { 0.0555555555555556, -0.0666666666666667, -1.0101010101010102 } });
  const vtkIdType faces[8][3] = { { 0, 2, 4 }, { 2, 1, 4 }, { 1, 3, 4 }, { 3, 0, 4 }, { 2, 0, 5 },
    { 1, 2, 5 }, { 3, 1, 5 }, { 0, 3, 5 } };
  vtkNew<vtkCellArray> polys;
  for (const auto& f : faces)
    polys->InsertNextCell(3, f);
  mesh->SetPolys(polys);
  vtkNew<vtkDoubleArray> weights;
  weights->SetName("Weights");
  weights->SetNumberOfComponents(3);
  weights->SetNumberOfTuples(6);
  for (int p = 0; p < 6; ++p)
    for (int k = 0; k < 3; ++k)
      weights->SetComponent(p, k, 1.0 / (3.0 + p + 7 * k) - 0.01 * k);
  mesh->GetPointData()->AddArray(weights);
  return mesh;
}

vtkSmartPointer<vtkUnstructuredGrid> ToGrid(vtkPolyData* mesh)
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(mesh->GetPoints());
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    vtkIdType size;
    const vtkIdType* ids;
    mesh->GetPolys()->GetCellAtId(c, size, ids);
    grid->InsertNextCell(VTK_TRIANGLE, size, ids);
  }
  grid->GetPointData()->ShallowCopy(mesh->GetPointData());
  return grid;
}

/// Max difference between the corners of triangle c of @p a and of @p b, over all triangles
/// (robust to readers that renumber or merge points, such as STL's).
double MaxCornerDifference(vtkDataSet* a, vtkDataSet* b)
{
  EXPECT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells());
  double worst = 0.0;
  vtkNew<vtkIdList> ia, ib;
  for (vtkIdType c = 0; c < std::min(a->GetNumberOfCells(), b->GetNumberOfCells()); ++c)
  {
    a->GetCellPoints(c, ia);
    b->GetCellPoints(c, ib);
    EXPECT_EQ(ia->GetNumberOfIds(), ib->GetNumberOfIds()) << "cell " << c;
    for (vtkIdType k = 0; k < std::min(ia->GetNumberOfIds(), ib->GetNumberOfIds()); ++k)
    {
      double x[3], y[3];
      a->GetPoint(ia->GetId(k), x);
      b->GetPoint(ib->GetId(k), y);
      for (int d = 0; d < 3; ++d)
        worst = std::max(worst, std::abs(x[d] - y[d]));
    }
  }
  return worst;
}

/// Expects vtkBaryDataIO::Read(path) to throw bary::Error with one of @p codes, naming the file
/// and mentioning @p needle.
void ExpectReadThrows(
  const std::string& path, std::vector<bary::ErrorCode> codes, const std::string& needle)
{
  try
  {
    vtkBaryDataIO::Read(path);
    ADD_FAILURE() << "Read('" << path << "') succeeded";
  }
  catch (const bary::Error& e)
  {
    EXPECT_NE(std::find(codes.begin(), codes.end(), e.code()), codes.end())
      << "code " << bary::to_string(e.code()) << ": " << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos)
      << "the message must name the file: " << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
      << "the message should mention '" << needle << "': " << e.what();
  }
}

/// Expects vtkBaryDataIO::Write to throw bary::Error(Io) with a message containing @p needle.
void ExpectWriteThrows(vtkDataSet* data, const std::string& path, const std::string& needle)
{
  try
  {
    vtkBaryDataIO::Write(data, path);
    ADD_FAILURE() << "Write('" << path << "') succeeded";
  }
  catch (const bary::Error& e)
  {
    EXPECT_EQ(e.code(), bary::ErrorCode::Io) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
      << "the message should mention '" << needle << "': " << e.what();
  }
}

// ---------------------------------------------------------------------------------------------
// Round trips
// ---------------------------------------------------------------------------------------------

struct RoundTrip
{
  const char* Extension;
  double Tolerance; ///< on coordinates
  bool KeepsWeights;
};

void PrintTo(const RoundTrip& format, std::ostream* os)
{
  *os << format.Extension;
}

class vtkBaryDataIORoundTrip : public ::testing::TestWithParam<RoundTrip>
{
};

TEST_P(vtkBaryDataIORoundTrip, WriteThenRead)
{
  const RoundTrip rt = GetParam();
  const fs::path dir = Scratch(std::string("roundtrip") + rt.Extension);
  const std::string path = (dir / (std::string("mesh") + rt.Extension)).string();
  auto mesh = SmallMesh();
  vtkSmartPointer<vtkDataSet> data = mesh;
  if (std::string(rt.Extension) == ".vtu")
    data = ToGrid(mesh);
  ASSERT_NO_THROW(vtkBaryDataIO::Write(data, path));
  EXPECT_EQ(ListFolder(dir), std::set<std::string>{ "mesh" + std::string(rt.Extension) })
    << "no temporary file may be left behind";

  vtkSmartPointer<vtkDataSet> back;
  ASSERT_NO_THROW(back = vtkBaryDataIO::Read(path));
  ASSERT_NE(back, nullptr);
  EXPECT_EQ(back->GetNumberOfCells(), 8);
  EXPECT_EQ(back->GetNumberOfPoints(), 6);
  EXPECT_LE(MaxCornerDifference(data, back), rt.Tolerance);
  if (std::string(rt.Extension) == ".vtu")
    EXPECT_NE(vtkUnstructuredGrid::SafeDownCast(back), nullptr) << back->GetClassName();
  else
    EXPECT_NE(vtkPolyData::SafeDownCast(back), nullptr) << back->GetClassName();
  if (rt.KeepsWeights)
  {
    vtkDataArray* in = GetWeights(mesh);
    vtkDataArray* out = GetWeights(back);
    ASSERT_NE(out, nullptr) << "the Weights array must survive " << rt.Extension;
    ASSERT_EQ(out->GetNumberOfComponents(), 3);
    ASSERT_EQ(out->GetNumberOfTuples(), 6);
    for (vtkIdType p = 0; p < 6; ++p)
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(out->GetComponent(p, k), in->GetComponent(p, k)) << "exactly";
    // Points too: these formats store doubles.
    for (vtkIdType p = 0; p < 6; ++p)
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(back->GetPoint(p)[k], data->GetPoint(p)[k]);
  }
}

INSTANTIATE_TEST_SUITE_P(AllFormats, vtkBaryDataIORoundTrip,
  ::testing::Values(RoundTrip{ ".vtp", 0.0, true }, RoundTrip{ ".vtu", 0.0, true },
    RoundTrip{ ".vtk", 0.0, true }, RoundTrip{ ".obj", 1e-6, false },
    RoundTrip{ ".stl", 1e-6, false }, RoundTrip{ ".ply", 1e-6, false },
    RoundTrip{ ".off", 0.0, false }),
  [](const ::testing::TestParamInfo<RoundTrip>& format)
  { return std::string(format.param.Extension + 1); });

TEST(vtkBaryDataIO, ImageDataToLegacyVtk)
{
  const fs::path dir = Scratch("image");
  vtkNew<vtkImageData> image;
  image->SetDimensions(3, 2, 2);
  image->SetSpacing(0.5, 0.25, 2.0);
  image->SetOrigin(-1, 0, 1);
  const std::string path = (dir / "image.vtk").string();
  ASSERT_NO_THROW(vtkBaryDataIO::Write(image, path));
  auto back = vtkBaryDataIO::Read(path);
  ASSERT_NE(vtkImageData::SafeDownCast(back), nullptr) << back->GetClassName();
  EXPECT_EQ(back->GetNumberOfPoints(), 12);
  EXPECT_EQ(back->GetPoint(11)[0], 0.0);
  EXPECT_EQ(back->GetPoint(11)[1], 0.25);
  EXPECT_EQ(back->GetPoint(11)[2], 3.0);
}

TEST(vtkBaryDataIO, SurfaceToVtuIsConverted)
{
  // Any data set converts losslessly to an unstructured grid.
  const fs::path dir = Scratch("surface_vtu");
  const std::string path = (dir / "mesh.vtu").string();
  auto mesh = SmallMesh();
  ASSERT_NO_THROW(vtkBaryDataIO::Write(mesh, path));
  auto back = vtkBaryDataIO::Read(path);
  ASSERT_NE(vtkUnstructuredGrid::SafeDownCast(back), nullptr) << back->GetClassName();
  EXPECT_EQ(back->GetNumberOfCells(), 8);
  EXPECT_EQ(back->GetCellType(0), VTK_TRIANGLE);
  EXPECT_EQ(MaxCornerDifference(mesh, back), 0.0);
  vtkDataArray* W = GetWeights(back);
  ASSERT_NE(W, nullptr);
  EXPECT_EQ(W->GetNumberOfComponents(), 3);
  EXPECT_EQ(W->GetComponent(5, 2), GetWeights(mesh)->GetComponent(5, 2));
  EXPECT_EQ(ListFolder(dir), std::set<std::string>{ "mesh.vtu" });
}

TEST(vtkBaryDataIO, OverwriteReplacesTheFile)
{
  const fs::path dir = Scratch("overwrite");
  const std::string path = (dir / "m.off").string();
  vtkBaryDataIO::Write(SmallMesh(), path);
  vtkBaryDataIO::Write(MakeCube(), path);
  auto back = vtkBaryDataIO::Read(path);
  EXPECT_EQ(back->GetNumberOfPoints(), 8);
  EXPECT_EQ(ListFolder(dir), std::set<std::string>{ "m.off" });
}

TEST(vtkBaryDataIO, BundledDataReads)
{
  auto model = vtkBaryDataIO::ReadPolyData(DataPath("model3d.off"));
  EXPECT_EQ(model->GetNumberOfPoints(), 2562);
  EXPECT_EQ(model->GetNumberOfPolys(), 5120);
  auto cage = vtkBaryDataIO::ReadPolyData(DataPath("cage3d.obj"));
  EXPECT_EQ(cage->GetNumberOfPoints(), 72);
  EXPECT_EQ(cage->GetNumberOfPolys(), 140);
  auto cage2d = vtkBaryDataIO::ReadPolyData(DataPath("cage2d.obj"));
  EXPECT_EQ(cage2d->GetNumberOfPoints(), 20);
  EXPECT_EQ(cage2d->GetNumberOfPolys(), 0);
}

// ---------------------------------------------------------------------------------------------
// Read errors
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryDataIO, ReadMissingFile)
{
  const std::string path = (Scratch("missing") / "nothing_here.vtp").string();
  ExpectReadThrows(path, { bary::ErrorCode::Io }, "no such file");
}

TEST(vtkBaryDataIO, ReadUnknownExtension)
{
  const fs::path dir = Scratch("unknown");
  const std::string path = WriteText(dir / "mesh.xyz", "1 2 3\n");
  ExpectReadThrows(path, { bary::ErrorCode::Io }, "unknown file extension");
  ExpectReadThrows(WriteText(dir / "noext", "1 2 3\n"), { bary::ErrorCode::Io }, "extension");
  EXPECT_FALSE(vtkBaryDataIO::CanRead(path));
}

TEST(vtkBaryDataIO, ReadEmptyFile)
{
  ExpectReadThrows(
    DataPath("bad/empty.obj"), { bary::ErrorCode::Io, bary::ErrorCode::EmptyInput }, "empty");
  const fs::path dir = Scratch("empty");
  for (const char* ext : { ".vtp", ".off", ".stl", ".ply", ".vtk", ".vtu" })
    ExpectReadThrows(WriteText(dir / (std::string("e") + ext), ""),
      { bary::ErrorCode::Io, bary::ErrorCode::EmptyInput }, "empty");
}

TEST(vtkBaryDataIO, ReadGarbage)
{
  ExpectReadThrows(DataPath("bad/garbage.off"), { bary::ErrorCode::Io }, "garbage.off");
  const fs::path dir = Scratch("garbage");
  const std::string text = "this is, not a mesh\n\x7f\t1e999999 0x1p3\n";
  for (const char* ext : { ".vtp", ".vtu", ".vtk", ".ply", ".off" })
    ExpectReadThrows(WriteText(dir / (std::string("g") + ext), text),
      { bary::ErrorCode::Io, bary::ErrorCode::EmptyInput }, std::string("g") + ext);
}

TEST(vtkBaryDataIO, ReadNaNObj)
{
  // vtkOBJReader read "nan" as a number; vtkBaryOBJReader refuses it, naming the line.
  ExpectReadThrows(DataPath("bad/nan_cage.obj"), { bary::ErrorCode::NonFinite }, "line 7");
}

TEST(vtkBaryDataIO, ReadRefusesWhatVTKReadsUnsafely)
{
  // Each of these crashed or silently gave garbage downstream (issue 17): they are refused at
  // the read, naming the file and the problem in one line.
  const fs::path dir = Scratch("unsafe");
  const std::string head = "# vtk DataFile Version 3.0\nbad\nASCII\nDATASET POLYDATA\n";
  // a cell naming a point that does not exist
  ExpectReadThrows(WriteText(dir / "cell.vtk",
                     head + "POINTS 3 double\n0 0 0\n1 0 0\n0 1 0\nPOLYGONS 1 4\n3 0 1 7\n"),
    { bary::ErrorCode::InvalidArgument }, "cell 0 names point 7, but the file has 3 points");
  // the same in a .vtp written by VTK itself, then edited
  {
    auto mesh = SmallMesh();
    mesh->GetPolys()->ReplaceCellAtId(3, { 0, 1, 99 });
    const std::string path = (dir / "cell.vtp").string();
    vtkNew<vtkXMLPolyDataWriter> writer;
    writer->SetInputData(mesh);
    writer->SetFileName(path.c_str());
    writer->SetDataModeToAscii();
    ASSERT_EQ(writer->Write(), 1);
    ExpectReadThrows(path, { bary::ErrorCode::InvalidArgument }, "cell 3 names point 99");
  }
  // an array shorter than the points (heap corruption in 'fields' before)
  ExpectReadThrows(WriteText(dir / "short.vtk",
                     head + "POINTS 3 double\n0 0 0\n1 0 0\n0 1 0\nPOINT_DATA 3\n"
                            "SCALARS Weights double 2\nLOOKUP_TABLE default\n0.5 0.5\n0.5 0.5\n"),
    { bary::ErrorCode::Io }, "line 14: the file ends where SCALARS 'Weights' values should be");
  // fewer points than declared (uninitialised coordinates before)
  ExpectReadThrows(WriteText(dir / "few.vtk", head + "POINTS 6 double\n0 0 0\n1 0 0\n0 1 0\n"),
    { bary::ErrorCode::Io }, "few.vtk");
  // "nan" in an ASCII array: VTK warned and read zeros; it is read as NaN, as in a binary file
  // (BaryLab's --outside nan writes such weights)
  {
    auto nan = vtkBaryDataIO::Read(WriteText(dir / "nan.vtk",
      head + "POINTS 2 double\n0 0 0\n1 0 0\nPOINT_DATA 2\n"
             "SCALARS Weights double 1\nLOOKUP_TABLE default\nnan\n0.5\n"));
    vtkDataArray* w = nan->GetPointData()->GetArray("Weights");
    ASSERT_NE(w, nullptr);
    EXPECT_TRUE(std::isnan(w->GetComponent(0, 0)));
    EXPECT_EQ(w->GetComponent(1, 0), 0.5);
  }
  // "nan" as an index: a .tgf bone (SIGSEGV before) and a MEDIT tetrahedron (vertex -1 before)
  ExpectReadThrows(WriteText(dir / "nan.tgf", "1 0 0 0\n2 1 0 0\n#\n1 nan\n#\n"),
    { bary::ErrorCode::Io }, "edge (1, nan) does not join two of the 2 vertices");
  ExpectReadThrows(WriteText(dir / "half.tgf", "1 0 0 0\n2 1 0 0\n#\n1 1.5\n#\n"),
    { bary::ErrorCode::Io }, "whole numbers");
  ExpectReadThrows(WriteText(dir / "nan.mesh",
                     "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 1\n1 0 0 1\n"
                     "0 1 0 1\n0 0 1 1\nTetrahedra\n1\n1 2 3 nan 1\nEnd\n"),
    { bary::ErrorCode::Io }, "refers to vertex nan");
  // a non-finite coordinate in a format whose reader accepts it
  ExpectReadThrows(WriteText(dir / "inf.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 inf 0\n3 0 1 2\n"),
    { bary::ErrorCode::NonFinite, bary::ErrorCode::Io }, "inf.off");
}

TEST(vtkBaryDataIO, ReadFileWithoutPoints)
{
  const std::string path = WriteText(Scratch("nopoints") / "none.off", "OFF\n0 0 0\n");
  ExpectReadThrows(path, { bary::ErrorCode::EmptyInput }, "no points");
}

TEST(vtkBaryDataIO, ReadFolderNamedLikeAFile)
{
  const fs::path dir = Scratch("folder");
  fs::create_directories(dir / "mesh.vtp");
  ExpectReadThrows((dir / "mesh.vtp").string(), { bary::ErrorCode::Io }, "regular file");
}

TEST(vtkBaryDataIO, ReadPolyDataRejectsOtherTypes)
{
  const fs::path dir = Scratch("readpoly");
  const std::string path = (dir / "grid.vtu").string();
  vtkBaryDataIO::Write(ToGrid(SmallMesh()), path);
  try
  {
    vtkBaryDataIO::ReadPolyData(path);
    ADD_FAILURE() << "ReadPolyData accepted an unstructured grid";
  }
  catch (const bary::Error& e)
  {
    EXPECT_NE(std::string(e.what()).find("vtkUnstructuredGrid"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(vtkBaryDataIO, Extension)
{
  EXPECT_EQ(vtkBaryDataIO::Extension("a/b/mesh.VTP"), ".vtp");
  EXPECT_EQ(vtkBaryDataIO::Extension("a.b/mesh"), "");
  EXPECT_EQ(vtkBaryDataIO::Extension("mesh.tar.off"), ".off");
  EXPECT_EQ(vtkBaryDataIO::Extension("mesh"), "");
  EXPECT_TRUE(vtkBaryDataIO::CanRead("x.Off"));
  EXPECT_TRUE(vtkBaryDataIO::CanRead("x.stl"));
  EXPECT_FALSE(vtkBaryDataIO::CanRead("x.msh"));
  for (const char* ext : { ".vtp", ".vtu", ".vtk", ".obj", ".stl", ".ply", ".off" })
    EXPECT_TRUE(vtkBaryDataIO::CanWrite(std::string("dir/x") + ext)) << ext;
  EXPECT_FALSE(vtkBaryDataIO::CanWrite("x.png"));
  EXPECT_FALSE(vtkBaryDataIO::CanWrite("x"));
}

// ---------------------------------------------------------------------------------------------
// Write errors
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryDataIO, WriteToMissingFolderThrowsAndLeavesNothing)
{
  const fs::path dir = Scratch("nofolder");
  const fs::path target = dir / "does" / "not" / "exist" / "mesh.vtp";
  ExpectWriteThrows(SmallMesh(), target.string(), target.string());
  EXPECT_FALSE(fs::exists(target));
  EXPECT_FALSE(fs::exists(dir / "does"));
  EXPECT_TRUE(ListFolder(dir).empty());
}

TEST(vtkBaryDataIO, FailedWriteLeavesNoTemporaryFiles)
{
  // The target is an existing folder: the temporary file can be written beside it, but the
  // final rename fails. Nothing but the folder may remain.
  const fs::path dir = Scratch("failedwrite");
  auto mesh = SmallMesh();
  for (const char* ext : { ".vtp", ".vtk", ".obj", ".stl", ".ply", ".off" })
  {
    const fs::path target = dir / (std::string("target") + ext);
    fs::create_directories(target);
    ExpectWriteThrows(mesh, target.string(), target.string());
    EXPECT_TRUE(fs::is_directory(target));
    EXPECT_TRUE(fs::is_empty(target));
    fs::remove(target);
    EXPECT_TRUE(ListFolder(dir).empty()) << ext << ": a temporary file was left behind";
  }
}

TEST(vtkBaryDataIO, FailedWriteKeepsThePreviousFile)
{
  const fs::path dir = Scratch("keep");
  const std::string path = (dir / "mesh.obj").string();
  vtkBaryDataIO::Write(SmallMesh(), path);
  const auto size = fs::file_size(path);
  ExpectWriteThrows(ToGrid(SmallMesh()), path, ".obj");
  EXPECT_EQ(fs::file_size(path), size);
  EXPECT_EQ(vtkBaryDataIO::Read(path)->GetNumberOfCells(), 8);
  EXPECT_EQ(ListFolder(dir), std::set<std::string>{ "mesh.obj" });
}

TEST(vtkBaryDataIO, WrongTypeForExtension)
{
  const fs::path dir = Scratch("wrongtype");
  ExpectWriteThrows(ToGrid(SmallMesh()), (dir / "grid.vtp").string(), ".vtu");
  vtkNew<vtkImageData> image;
  image->SetDimensions(2, 2, 2);
  ExpectWriteThrows(image, (dir / "image.off").string(), "vtkImageData");
  ExpectWriteThrows(SmallMesh(), (dir / "mesh.xyz").string(), "unknown file extension");
  ExpectWriteThrows(nullptr, (dir / "null.vtp").string(), "null.vtp");
  EXPECT_TRUE(ListFolder(dir).empty());
}

TEST(vtkBaryDataIO, CheckWritableSaysWhatWriteWouldWithoutWriting)
{
  const fs::path dir = Scratch("checkwritable");
  const vtkSmartPointer<vtkDataSet> grid = ToGrid(SmallMesh());
  vtkNew<vtkImageData> image;
  image->SetDimensions(2, 2, 2);
  // every surface-only format refuses a volume mesh and an image, with Write's message
  for (const char* ext : { ".vtp", ".obj", ".stl", ".ply", ".off" })
    for (vtkDataSet* data : { static_cast<vtkDataSet*>(grid), static_cast<vtkDataSet*>(image) })
    {
      const std::string path = (dir / (std::string("out") + ext)).string();
      std::string checked, written;
      try
      {
        vtkBaryDataIO::CheckWritable(data, path);
      }
      catch (const bary::Error& e)
      {
        checked = e.what();
      }
      try
      {
        vtkBaryDataIO::Write(data, path);
      }
      catch (const bary::Error& e)
      {
        written = e.what();
      }
      EXPECT_NE(checked.find("holds surfaces only"), std::string::npos) << ext << ": " << checked;
      EXPECT_EQ(checked, written) << ext;
    }
  // what the formats hold is accepted, nothing is written
  EXPECT_NO_THROW(vtkBaryDataIO::CheckWritable(SmallMesh(), (dir / "s.vtp").string()));
  EXPECT_NO_THROW(vtkBaryDataIO::CheckWritable(SmallMesh(), (dir / "s.off").string()));
  EXPECT_NO_THROW(vtkBaryDataIO::CheckWritable(grid, (dir / "g.vtu").string()));
  EXPECT_NO_THROW(vtkBaryDataIO::CheckWritable(grid, (dir / "g.vtk").string()));
  EXPECT_NO_THROW(vtkBaryDataIO::CheckWritable(grid, (dir / "g.fcsv").string())); // its points
  EXPECT_NO_THROW(vtkBaryDataIO::CheckWritable(image, (dir / "i.vtu").string()));
  EXPECT_THROW(vtkBaryDataIO::CheckWritable(grid, (dir / "g.xyz").string()), bary::Error);
  EXPECT_THROW(vtkBaryDataIO::CheckWritable(nullptr, (dir / "n.vtu").string()), bary::Error);
  EXPECT_TRUE(ListFolder(dir).empty());
}

// ---------------------------------------------------------------------------------------------
// OFF reader on hand-written files
// ---------------------------------------------------------------------------------------------

struct OFFRead
{
  vtkNew<vtkBaryOFFReader> Reader;
  vtkNew<ErrorObserver> Observer;
  int Status = 0;

  explicit OFFRead(const std::string& path)
  {
    this->Observer->Attach(this->Reader);
    this->Reader->SetFileName(path.c_str());
    this->Status = RunPipeline(this->Reader);
  }
  vtkPolyData* Output() { return this->Reader->GetOutput(); }
};

const char* const kSquare = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";

TEST(vtkBaryOFFReader, CountsOnTheHeaderLine)
{
  const fs::path dir = Scratch("off_header");
  OFFRead r(WriteText(dir / "a.off", std::string("OFF 4 2 0\n") + kSquare + "3 0 1 2\n3 0 2 3\n"));
  ASSERT_EQ(r.Status, 1) << r.Observer->AllErrors();
  EXPECT_EQ(r.Output()->GetNumberOfPoints(), 4);
  EXPECT_EQ(r.Output()->GetNumberOfPolys(), 2);
  EXPECT_EQ(r.Output()->GetPoint(2)[0], 1.0);
  EXPECT_EQ(r.Output()->GetPoint(2)[1], 1.0);
}

TEST(vtkBaryOFFReader, Comments)
{
  const fs::path dir = Scratch("off_comments");
  OFFRead r(WriteText(dir / "a.off",
    "# a comment before the header\nOFF\n# counts next\n4 2 0 # vertices faces edges\n\n"
    "0 0 0 # v0\n1 0 0\n# between vertices\n1 1 0\n0 1 0\n3 0 1 2 # f0\n\n3 0 2 3\n"));
  ASSERT_EQ(r.Status, 1) << r.Observer->AllErrors();
  EXPECT_EQ(r.Output()->GetNumberOfPoints(), 4);
  EXPECT_EQ(r.Output()->GetNumberOfPolys(), 2);
}

TEST(vtkBaryOFFReader, NoHeader)
{
  const fs::path dir = Scratch("off_noheader");
  OFFRead r(WriteText(dir / "a.off", std::string("4 1\n") + kSquare + "4 0 1 2 3\n"));
  ASSERT_EQ(r.Status, 1) << r.Observer->AllErrors();
  EXPECT_EQ(r.Output()->GetNumberOfPoints(), 4);
  ASSERT_EQ(r.Output()->GetNumberOfPolys(), 1);
  EXPECT_EQ(r.Output()->GetPolys()->GetCellSize(0), 4);
}

TEST(vtkBaryOFFReader, ColouredOFF)
{
  const fs::path dir = Scratch("off_coff");
  OFFRead r(WriteText(dir / "a.off",
    "COFF\n3 1 0\n0.5 0 0 255 0 0 255\n1 0.25 0 0 255 0 255\n0 1 2 0 0 255 255\n"
    "3 0 1 2 128 128 128\n"));
  ASSERT_EQ(r.Status, 1) << r.Observer->AllErrors();
  ASSERT_EQ(r.Output()->GetNumberOfPoints(), 3);
  EXPECT_EQ(r.Output()->GetPoint(0)[0], 0.5);
  EXPECT_EQ(r.Output()->GetPoint(1)[1], 0.25);
  EXPECT_EQ(r.Output()->GetPoint(2)[2], 2.0);
  ASSERT_EQ(r.Output()->GetNumberOfPolys(), 1);
  vtkIdType size;
  const vtkIdType* ids;
  r.Output()->GetPolys()->GetCellAtId(0, size, ids);
  ASSERT_EQ(size, 3);
  EXPECT_EQ(ids[0], 0);
  EXPECT_EQ(ids[1], 1);
  EXPECT_EQ(ids[2], 2);
}

TEST(vtkBaryOFFReader, QuadsAndTwoIndexFaces)
{
  const fs::path dir = Scratch("off_mixed");
  OFFRead r(WriteText(dir / "a.off",
    std::string("OFF\n5 3 0\n") + kSquare + "0.5 0.5 1\n4 0 1 2 3\n2 3 4\n3 0 1 4\n"));
  ASSERT_EQ(r.Status, 1) << r.Observer->AllErrors();
  EXPECT_EQ(r.Output()->GetNumberOfPoints(), 5);
  ASSERT_EQ(r.Output()->GetNumberOfPolys(), 2);
  EXPECT_EQ(r.Output()->GetPolys()->GetCellSize(0), 4);
  EXPECT_EQ(r.Output()->GetPolys()->GetCellSize(1), 3);
  ASSERT_EQ(r.Output()->GetNumberOfLines(), 1);
  vtkIdType size;
  const vtkIdType* ids;
  r.Output()->GetLines()->GetCellAtId(0, size, ids);
  ASSERT_EQ(size, 2);
  EXPECT_EQ(ids[0], 3);
  EXPECT_EQ(ids[1], 4);
}

/// Reads @p text and expects a failure whose message contains every string of @p needles and
/// an empty output.
void ExpectOFFError(
  const std::string& name, const std::string& text, const std::vector<std::string>& needles)
{
  const fs::path dir = Scratch("off_errors");
  OFFRead r(WriteText(dir / (name + ".off"), text));
  EXPECT_EQ(r.Status, 0) << name;
  EXPECT_FALSE(r.Observer->Errors.empty()) << name;
  for (const auto& needle : needles)
    EXPECT_TRUE(r.Observer->HasError(needle)) << name << ": expected '" << needle << "' in:\n"
                                              << r.Observer->AllErrors();
  EXPECT_EQ(r.Output()->GetNumberOfPoints(), 0) << name << ": the output must stay empty";
  EXPECT_EQ(r.Output()->GetNumberOfCells(), 0) << name;
}

TEST(vtkBaryOFFReader, TruncatedFile)
{
  ExpectOFFError(
    "truncated_vertices", "OFF\n4 2 0\n0 0 0\n1 0 0\n", { "line ", "2 of 4 vertices" });
  ExpectOFFError("truncated_faces", std::string("OFF\n4 2 0\n") + kSquare + "3 0 1 2\n",
    { "line ", "1 of 2 faces" });
  // A short vertex line: the message gives its line number (line 5).
  ExpectOFFError("short_vertex", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1\n0 1 0\n3 0 1 2\n3 0 2 3\n",
    { "line 5", "vertex 2" });
  ExpectOFFError("short_face", std::string("OFF\n4 2 0\n") + kSquare + "3 0 1 2\n3 0 2\n",
    { "line 8", "face 1" });
}

TEST(vtkBaryOFFReader, OutOfRangeIndex)
{
  ExpectOFFError("out_of_range", std::string("OFF\n4 2 0\n") + kSquare + "3 0 1 2\n3 0 2 4\n",
    { "line 8", "vertex 4" });
  ExpectOFFError("negative_index", std::string("OFF\n4 1 0\n") + kSquare + "3 0 -1 2\n",
    { "line 7", "vertex -1" });
}

TEST(vtkBaryOFFReader, NonFiniteVertex)
{
  ExpectOFFError(
    "nan", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", { "line 4", "vertex 1", "non-finite" });
  ExpectOFFError(
    "inf", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 -inf 0\n3 0 1 2\n", { "line 5", "vertex 2", "non-finite" });
  ExpectOFFError("overflow", "OFF\n3 1 0\n0 0 1e999\n1 0 0\n0 1 0\n3 0 1 2\n",
    { "line 3", "vertex 0", "'1e999' is beyond the range of double precision" });
  ExpectOFFError(
    "comma", "OFF\n3 1 0\n0 0 0\n1,5 0 0\n0 1 0\n3 0 1 2\n", { "line 4", "'1,5' is not a number" });
}

TEST(vtkBaryOFFReader, NumberSyntax)
{
  const fs::path dir = Scratch("off_numbers");
  OFFRead r(
    WriteText(dir / "a.off", "OFF\n3 1 0\n+0.5 -0 1e-3\n1.25E+1 .5 -7.\n0 1 1e-400\n3 0 1 2\n"));
  ASSERT_EQ(r.Status, 1) << r.Observer->AllErrors();
  EXPECT_EQ(r.Output()->GetPoint(0)[0], 0.5);
  EXPECT_EQ(r.Output()->GetPoint(0)[2], 1e-3);
  EXPECT_EQ(r.Output()->GetPoint(1)[0], 12.5);
  EXPECT_EQ(r.Output()->GetPoint(1)[1], 0.5);
  EXPECT_EQ(r.Output()->GetPoint(1)[2], -7.0);
  EXPECT_EQ(r.Output()->GetPoint(2)[2], 0.0)
    << "an underflowing number is a tiny number, not an error";
}

TEST(vtkBaryOFFReader, BadHeaderAndCounts)
{
  ExpectOFFError("empty", "", { "empty" });
  ExpectOFFError("comments_only", "# nothing\n\n# here\n", { "empty" });
  ExpectOFFError("variant", "XOFF\n3 1 0\n", { "line 1", "XOFF" });
  ExpectOFFError("no_counts", "OFF\n", { "counts" });
  ExpectOFFError("negative", "OFF\n-3 1 0\n", { "line 2" });
  ExpectOFFError("words", "OFFF\nthree vertices\n", { "line 1" });
}

TEST(vtkBaryOFFReader, HugeCountsInATruncatedFile)
{
  // A corrupt counts line must give the truncation error, not an attempt to allocate memory
  // for 10^11 points.
  ExpectOFFError(
    "huge", "OFF\n100000000000 1 0\n0 0 0\n", { "line ", "1 of 100000000000 vertices" });
  ExpectOFFError("huge_faces", "OFF\n3 100000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    { "line ", "1 of 100000000000 faces" });
  ExpectOFFError("huge_face", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1000000000000 0 1 2\n",
    { "line 6", "fewer than 1000000000000" });
}

TEST(vtkBaryOFFReader, MissingFile)
{
  vtkNew<vtkBaryOFFReader> reader;
  vtkNew<ErrorObserver> observer;
  observer->Attach(reader);
  const std::string path = (Scratch("off_missing") / "none.off").string();
  reader->SetFileName(path.c_str());
  EXPECT_EQ(RunPipeline(reader), 0);
  EXPECT_TRUE(observer->HasError(path)) << observer->AllErrors();
  vtkNew<vtkBaryOFFReader> unnamed;
  vtkNew<ErrorObserver> observer2;
  observer2->Attach(unnamed);
  EXPECT_EQ(RunPipeline(unnamed), 0);
  EXPECT_TRUE(observer2->HasError("file name")) << observer2->AllErrors();
}

// ---------------------------------------------------------------------------------------------
// OFF writer
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryOFFWriter, WritesHeaderCountsAndZeroBasedFaces)
{
  const fs::path dir = Scratch("off_writer");
  const std::string path = (dir / "cube.off").string();
  vtkNew<vtkBaryOFFWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(MakeCube());
  ASSERT_EQ(writer->Write(), 1);
  std::ifstream in(path);
  std::string header;
  long long nv, nf, ne;
  in >> header >> nv >> nf >> ne;
  EXPECT_EQ(header, "OFF");
  EXPECT_EQ(nv, 8);
  EXPECT_EQ(nf, 12);
  double x[3];
  for (int i = 0; i < 8; ++i)
    in >> x[0] >> x[1] >> x[2];
  EXPECT_EQ(x[0], -1.0); // the last corner is (-1, 1, 1)
  EXPECT_EQ(x[1], 1.0);
  int k, a, b, c;
  in >> k >> a >> b >> c;
  EXPECT_EQ(k, 3);
  EXPECT_EQ(a, 0); // the first face is {0, 3, 2}
  EXPECT_EQ(b, 3);
  EXPECT_EQ(c, 2);
}

TEST(vtkBaryOFFWriter, UnwritablePathIsAnError)
{
  vtkNew<vtkBaryOFFWriter> writer;
  vtkNew<ErrorObserver> observer;
  writer->AddObserver(vtkCommand::ErrorEvent, observer);
  const std::string path = (Scratch("off_writer_bad") / "no" / "cube.off").string();
  writer->SetFileName(path.c_str());
  writer->SetInputData(MakeCube());
  writer->Write();
  EXPECT_NE(writer->GetErrorCode(), 0ul);
  EXPECT_TRUE(observer->HasError(path)) << observer->AllErrors();
}


// --- issue 17: .obj in double precision, sizes checked before VTK allocates, one-line errors ---

TEST(vtkBaryOBJReader, DoublePrecisionAndEveryCellKind)
{
  const fs::path dir = Scratch("obj_double");
  const std::string path = WriteText(dir / "cells.obj",
    "# comment\nv 0.1 -0.4 1e300\nv 1 0 0 1.0\nv 0 1 0 0.5 0.5 0.5\nv 1 1 1e-400\n"
    "vt 0 0\nvn 0 0 1\ng group\ns off\n"
    "f 1/1/1 2//1 3\nf -4 -3 -1\nl 1 2 3 1\np 4\n");
  auto data = vtkBaryDataIO::ReadPolyData(path);
  ASSERT_EQ(data->GetNumberOfPoints(), 4);
  // exactly the decimal's nearest double (vtkOBJReader stored floats: 0.1 -> 0.100000001,
  // 1e300 -> 3.4e38)
  EXPECT_EQ(data->GetPoint(0)[0], 0.1);
  EXPECT_EQ(data->GetPoint(0)[1], -0.4);
  EXPECT_EQ(data->GetPoint(0)[2], 1e300);
  EXPECT_EQ(data->GetPoint(3)[2], 0.0); // underflow reads as 0, as strtod does
  EXPECT_EQ(data->GetNumberOfVerts(), 1);
  EXPECT_EQ(data->GetNumberOfLines(), 1);
  EXPECT_EQ(data->GetNumberOfPolys(), 2);
  vtkIdType n;
  const vtkIdType* ids;
  data->GetPolys()->GetCellAtId(1, n, ids); // negative indices count back
  ASSERT_EQ(n, 3);
  EXPECT_EQ(ids[0], 0);
  EXPECT_EQ(ids[1], 1);
  EXPECT_EQ(ids[2], 3);
}

TEST(vtkBaryOBJReader, RefusesWhatDoubleCannotHoldAndIndicesThatNameNoVertex)
{
  const fs::path dir = Scratch("obj_bad");
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  ExpectReadThrows(WriteText(dir / "huge.obj", "v 1e999 0 0\n" + v),
    { bary::ErrorCode::NonFinite }, "line 1: vertex coordinate '1e999' is beyond the range");
  // a 32-bit wrap-around made 4294967301 vertex 5 (vtkOBJReader)
  ExpectReadThrows(WriteText(dir / "wrap.obj", v + "v 1 1 0\nv 2 2 0\nf 1 2 4294967301\n"),
    { bary::ErrorCode::Io }, "line 6: vertex index 4294967301 but the file has 5 vertices");
  ExpectReadThrows(WriteText(dir / "zero.obj", v + "f 0 1 2\n"), { bary::ErrorCode::Io },
    "vertex index 0");
  ExpectReadThrows(WriteText(dir / "back.obj", v + "f -1 -2 -4\n"), { bary::ErrorCode::Io },
    "counts back past the first vertex");
  ExpectReadThrows(WriteText(dir / "two.obj", "v 1 2\n"), { bary::ErrorCode::Io },
    "needs three coordinates, it has 2");
  ExpectReadThrows(WriteText(dir / "face2.obj", v + "f 1 2\n"), { bary::ErrorCode::Io },
    "a face needs at least 3 vertices");
  ExpectReadThrows(WriteText(dir / "word.obj", v + "f 1 2 x\n"), { bary::ErrorCode::Io },
    "'x' is not a vertex index");
  ExpectReadThrows(WriteText(dir / "text.obj", "v 0 \x01\xff 0\n"), { bary::ErrorCode::Io },
    "'\\x01\\xff' is not a number");
}

TEST(vtkBaryDataIO, SizesAFileCannotHoldAreRefusedBeforeAllocating)
{
  const fs::path dir = Scratch("sizes");
  // legacy: a few bytes announcing 10^11 points (std::bad_alloc or the machine's memory before)
  ExpectReadThrows(WriteText(dir / "points.vtk", "# vtk DataFile Version 3.0\nx\nASCII\n"
                                                 "DATASET POLYDATA\nPOINTS 99999999999 float\n0 0 0\n"),
    { bary::ErrorCode::Io }, "line 5: the number of points 99999999999 is more than the file can hold");
  ExpectReadThrows(WriteText(dir / "scalars.vtk",
                     "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n"
                     "0 0 0\nPOINT_DATA 1\nSCALARS w float 2000000000\nLOOKUP_TABLE default\n0\n"),
    { bary::ErrorCode::Io }, "the scalars' components 2000000000 is more than the file can hold");
  // XML: a header count no file of this size holds, even compressed
  {
    auto mesh = SmallMesh();
    const std::string path = (dir / "count.vtp").string();
    vtkNew<vtkXMLPolyDataWriter> writer;
    writer->SetInputData(mesh);
    writer->SetFileName(path.c_str());
    writer->SetDataModeToAscii();
    ASSERT_EQ(writer->Write(), 1);
    std::ifstream in(path);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    const std::size_t at = text.find("NumberOfPoints=\"");
    ASSERT_NE(at, std::string::npos);
    const std::size_t end = text.find('"', at + 16);
    WriteText(path, text.substr(0, at + 16) + "99999999999" + text.substr(end));
    ExpectReadThrows(path, { bary::ErrorCode::Io }, "announces NumberOfPoints=99999999999");
    WriteText(path, text.substr(0, at + 16) + "1e3" + text.substr(end));
    ExpectReadThrows(path, { bary::ErrorCode::Io }, "NumberOfPoints=\"1e3\" is not a count");
  }
  // .dmat: a header of 10^18 values (std::bad_alloc, "a -9223372036854775808 by 1 matrix"),
  // and 0 columns by 6e29 rows (no values, but a cast of 6e29 to a matrix size: found by
  // libFuzzer's UBSan)
  for (const char* header : { "1000000000 1000000000\n1\n2\n", "0 600000000000000000000000000000\n" })
  {
    try
    {
      vtkBaryDataIO::ReadDMAT(WriteText(dir / "big.dmat", header));
      ADD_FAILURE() << "an impossible .dmat header was accepted: " << header;
    }
    catch (const bary::Error& e)
    {
      EXPECT_NE(std::string(e.what()).find("more values than a file of"), std::string::npos) << e.what();
    }
  }
  // MEDIT: a count beyond long long was cast to it (UBSan, found by libFuzzer)
  ExpectReadThrows(WriteText(dir / "count.mesh", "MeshVersionFormatted 1\nVertices\n5e95\n0 0 0 1\n"),
    { bary::ErrorCode::Io }, "expected the number of vertices after 'Vertices'");
  // ... and a reference number beyond int was cast to int
  ExpectReadThrows(WriteText(dir / "ref.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n"
                                               "0 0 0 1\n1 0 0 1\n0 1 0 1\n0 0 1 1\n"
                                               "Tetrahedra\n1\n1 2 3 4 1e68\nEnd\n"),
    { bary::ErrorCode::Io }, "Tetrahedra entry 1 has reference number 1e+68, not a whole number");
  // binary STL: a 4-billion-triangle count in a 134-byte file (VTK allocated for it first)
  {
    std::string stl(80, ' ');
    stl += std::string("\xff\xff\xff\xfe", 4);
    stl += std::string(50, '\x01');
    ExpectReadThrows(WriteText(dir / "count.stl", stl), { bary::ErrorCode::Io },
      "cannot hold the 4278190079 triangles its header announces");
  }
}

/// A .vtp with appended, zlib-compressed, base64-encoded data (VTK's options; vtkBaryDataIO
/// writes raw LZ4, whose blocks have the same header), whose first data
/// array's compression header (three 32-bit words: blocks, block size, last block size) is
/// changed by @p edit.
std::string CompressedWithHeader(const fs::path& path, const std::function<void(std::uint32_t*)>& edit)
{
  auto mesh = SmallMesh();
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(mesh);
  writer->SetFileName(path.string().c_str());
  writer->SetDataModeToAppended();
  writer->SetCompressorTypeToZLib();
  writer->SetHeaderTypeToUInt32();
  writer->EncodeAppendedDataOn();
  EXPECT_EQ(writer->Write(), 1);
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t data = text.find('_', text.find("<AppendedData")) + 1;
  // 12 bytes <-> 16 base64 characters, no padding
  static const std::string b64 =
    "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  unsigned char bytes[12];
  for (int g = 0; g < 4; ++g)
  {
    unsigned v = 0;
    for (int k = 0; k < 4; ++k)
      v = (v << 6) | static_cast<unsigned>(b64.find(text[data + 4 * g + k]));
    bytes[3 * g] = static_cast<unsigned char>(v >> 16);
    bytes[3 * g + 1] = static_cast<unsigned char>(v >> 8);
    bytes[3 * g + 2] = static_cast<unsigned char>(v);
  }
  std::uint32_t words[3] = { 0, 0, 0 };
  for (int w = 0; w < 3; ++w)
    for (int b = 3; b >= 0; --b)
      words[w] = (words[w] << 8) | bytes[4 * w + b];
  edit(words);
  for (int w = 0; w < 3; ++w)
    for (int b = 0; b < 4; ++b)
      bytes[4 * w + b] = static_cast<unsigned char>(words[w] >> (8 * b));
  std::string encoded;
  for (int g = 0; g < 4; ++g)
  {
    const unsigned v = (bytes[3 * g] << 16) | (bytes[3 * g + 1] << 8) | bytes[3 * g + 2];
    for (int k = 3; k >= 0; --k)
      encoded += b64[(v >> (6 * k)) & 63];
  }
  text.replace(data, 16, encoded);
  return WriteText(path, text);
}

TEST(vtkBaryDataIO, CompressionHeadersVTKTrustsAreChecked)
{
  const fs::path dir = Scratch("compression");
  // the file as written reads (so the edits below are what is refused)
  ASSERT_NO_THROW(vtkBaryDataIO::Read(CompressedWithHeader(dir / "ok.vtp", [](std::uint32_t*) {})));
  // no blocks but a partial last block: VTK's total size underflowed and it read block 0 of an
  // empty table (SIGSEGV, found by the fuzzer)
  ExpectReadThrows(CompressedWithHeader(dir / "underflow.vtp", [](std::uint32_t* w) { w[0] = 0; }),
    { bary::ErrorCode::Io }, "invalid compression header");
  // a block size of 0 divides by zero
  ExpectReadThrows(CompressedWithHeader(dir / "zero.vtp", [](std::uint32_t* w) { w[1] = 0; }),
    { bary::ErrorCode::Io }, "invalid compression header (block size 0");
  // a last block larger than the others reads past the block table
  ExpectReadThrows(CompressedWithHeader(dir / "last.vtp", [](std::uint32_t* w) { w[1] = 8; }),
    { bary::ErrorCode::Io }, "invalid compression header (block size 8");
  // more blocks than the file holds
  ExpectReadThrows(CompressedWithHeader(dir / "blocks.vtp", [](std::uint32_t* w) { w[0] = 400000000; }),
    { bary::ErrorCode::Io }, "announces 400000000 compressed blocks");
}

TEST(vtkBaryDataIO, CellsVTKCannotBuildAreRefusedNotCrashedOn)
{
  // a line with one point: vtkPolyData's cell map threw inside VTK and left no cells, and the
  // next cell access crashed (found by the fuzzer)
  const fs::path dir = Scratch("cellsizes");
  const std::string path = WriteText(dir / "line1.vtp",
    "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\">\n<PolyData>\n"
    "<Piece NumberOfPoints=\"2\" NumberOfLines=\"1\">\n<Points>\n"
    "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0"
    "</DataArray>\n</Points>\n<Lines>\n"
    "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">1</DataArray>\n"
    "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">1</DataArray>\n"
    "</Lines>\n</Piece>\n</PolyData>\n</VTKFile>\n");
  ExpectReadThrows(path, { bary::ErrorCode::Io }, "cell 0 (a line) has 1 points, fewer than the 2");
  // an unstructured grid cell whose type needs more points than it has
  const std::string head = "# vtk DataFile Version 3.0\nx\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                           "POINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  ExpectReadThrows(WriteText(dir / "tet3.vtk", head + "CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n10\n"),
    { bary::ErrorCode::Io }, "cell 0 of VTK cell type 10 has 3 points, not 4");
  ExpectReadThrows(WriteText(dir / "type.vtk", head + "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n200\n"),
    { bary::ErrorCode::Io }, "VTK cell type 200, which BaryLab does not read");
}

TEST(vtkBaryPLYReader, HeadersAndBodiesAreCheckedNotTrusted)
{
  const fs::path dir = Scratch("ply");
  // ASCII, with properties that are read past (normals, a colour list, an unknown element)
  auto data = vtkBaryDataIO::ReadPolyData(WriteText(dir / "ok.ply",
    "ply\nformat ascii 1.0\ncomment c\nelement vertex 4\nproperty double x\nproperty float y\n"
    "property float z\nproperty float nx\nelement face 2\nproperty list uchar int vertex_indices\n"
    "property list uchar float texcoord\nelement edge 1\nproperty int vertex1\nproperty int vertex2\n"
    "element other 1\nproperty short s\nend_header\n"
    "0.1 0 0 1\n1 0 0 1\n0 1 0 1\n1 1 0 1\n3 0 1 2 2 0.5 0.5\n4 0 1 3 2 0\n2 3\n7\n"));
  EXPECT_EQ(data->GetNumberOfPoints(), 4);
  EXPECT_EQ(data->GetPoint(0)[0], 0.1);
  EXPECT_EQ(data->GetNumberOfPolys(), 2);
  EXPECT_EQ(data->GetNumberOfLines(), 1);
  // a binary header that is the file's last line, without a newline: the body started one byte
  // past the end (heap-buffer-overflow in BaryLab's reader, found by libFuzzer)
  ExpectReadThrows(WriteText(dir / "eof.ply",
    "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
    "property float z\nend_header"), { bary::ErrorCode::Io }, "announces 1 entries, more than the 0 bytes left hold");
  ExpectReadThrows(WriteText(dir / "count.ply",
    "ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\nproperty float y\n"
    "property float z\nend_header\n0 0 0\n"), { bary::ErrorCode::Io },
    "line 3: element 'vertex' announces 99999999999 entries, more than the");
  ExpectReadThrows(WriteText(dir / "type.ply",
    "ply\nformat ascii 1.0\nelement vertex 1\nproperty flaot x\nend_header\n0\n"),
    { bary::ErrorCode::Io }, "line 4: unknown property type in 'property flaot x'");
}

TEST(vtkBaryDataIO, NumberListsAndPseudoEdgesAreReadStrictly)
{
  const fs::path dir = Scratch("lists");
  EXPECT_EQ(vtkBaryDataIO::ReadNumbers(WriteText(dir / "w.txt", "1 +2.5 # c\n\n3e-1\n")),
    (std::vector<double>{ 1.0, 2.5, 0.3 }));
  for (const char* bad : { "1 2,5\n", "1 1e999\n", "0x10\n" })
  {
    EXPECT_THROW(vtkBaryDataIO::ReadNumbers(WriteText(dir / "bad.txt", bad)), bary::Error) << bad;
  }
  EXPECT_THROW(vtkBaryDataIO::ReadNumbers(WriteText(dir / "nan.txt", "1 nan\n")), bary::Error);
  const Eigen::MatrixXi E = vtkBaryDataIO::ReadPseudoEdges(WriteText(dir / "e.txt", "# c\n0 1\n\n2 1 # c\n"));
  ASSERT_EQ(E.rows(), 2);
  EXPECT_EQ(E(1, 0), 2);
  // an index that overflowed an int made operator>> fail and the line was skipped silently
  for (const char* bad : { "99999999999 1\n", "0 1 2\n", "0\n", "-1 2\n", "0 1.5\n" })
  {
    try
    {
      vtkBaryDataIO::ReadPseudoEdges(WriteText(dir / "bad.txt", bad));
      ADD_FAILURE() << "accepted '" << bad << "'";
    }
    catch (const bary::Error& e)
    {
      EXPECT_NE(std::string(e.what()).find("line 1"), std::string::npos) << e.what();
    }
  }
}

// ---------------------------------------------------------------------------------------------
// vtkBaryFileReader / vtkBaryFileWriter: vtkBaryDataIO as pipeline algorithms (errors as VTK
// error events: what VTK's Python wrapping can report)
// ---------------------------------------------------------------------------------------------

TEST(vtkBaryFileReader, OutputIsWhatDataIOReadsOfTheFilesType)
{
  const fs::path dir = Scratch("file_reader");
  const std::string vtu = (dir / "mesh.vtu").string();
  const std::string off = (dir / "mesh.off").string();
  vtkBaryDataIO::Write(ToGrid(SmallMesh()), vtu);
  vtkBaryDataIO::Write(SmallMesh(), off);
  vtkNew<vtkBaryFileReader> reader;
  vtkNew<ErrorObserver> observer;
  observer->Attach(reader);
  for (const std::string& path : { vtu, off, vtu })
  {
    reader->SetFileName(path.c_str());
    ASSERT_EQ(RunPipeline(reader), 1) << observer->AllErrors();
    vtkDataObject* output = reader->GetOutputDataObject(0);
    const vtkSmartPointer<vtkDataSet> expected = vtkBaryDataIO::Read(path);
    ASSERT_NE(output, nullptr);
    EXPECT_STREQ(output->GetClassName(), expected->GetClassName()) << path;
    auto* data = vtkDataSet::SafeDownCast(output);
    ASSERT_NE(data, nullptr);
    EXPECT_EQ(data->GetNumberOfCells(), 8);
    EXPECT_EQ(MaxCornerDifference(expected, data), 0.0) << path;
    EXPECT_EQ(GetWeights(data) != nullptr, path == vtu) << "point data as the file holds it";
  }
  EXPECT_TRUE(vtkBaryFileReader::CanReadFile("x.MESH"));
  EXPECT_FALSE(vtkBaryFileReader::CanReadFile("x.xyz"));
  EXPECT_FALSE(vtkBaryFileReader::CanReadFile(nullptr));
}

TEST(vtkBaryFileReader, UnreadableFilesAreErrorEventsNamingTheFile)
{
  const fs::path dir = Scratch("file_reader_errors");
  const std::string missing = (dir / "missing.obj").string();
  const std::string garbage = WriteText(dir / "broken.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n");
  const std::string unknown = WriteText(dir / "points.xyz", "0 0 0\n");
  for (const std::string& path : { missing, garbage, unknown })
  {
    vtkNew<vtkBaryFileReader> reader;
    vtkNew<ErrorObserver> observer;
    observer->Attach(reader);
    reader->SetFileName(path.c_str());
    EXPECT_EQ(RunPipeline(reader), 0) << path;
    EXPECT_TRUE(observer->HasError(fs::path(path).filename().string())) << observer->AllErrors();
    EXPECT_EQ(reader->GetErrorCode(), vtkBaryConversion::ToVTKErrorCode(bary::ErrorCode::Io))
      << path;
  }
}

TEST(vtkBaryFileWriter, WritesByExtensionAndReportsFailures)
{
  const fs::path dir = Scratch("file_writer");
  const std::string path = (dir / "mesh.vtp").string();
  vtkNew<vtkBaryFileWriter> writer;
  vtkNew<ErrorObserver> observer;
  writer->AddObserver(vtkCommand::ErrorEvent, observer);
  writer->SetInputData(SmallMesh());
  writer->SetFileName(path.c_str());
  ASSERT_EQ(writer->Write(), 1) << observer->AllErrors();
  const vtkSmartPointer<vtkDataSet> back = vtkBaryDataIO::Read(path);
  EXPECT_EQ(MaxCornerDifference(SmallMesh(), back), 0.0);
  ASSERT_NE(GetWeights(back), nullptr);
  EXPECT_EQ(GetWeights(back)->GetComponent(5, 2), GetWeights(SmallMesh())->GetComponent(5, 2));

  const fs::path target = dir / "no_such_folder" / "mesh.vtp";
  writer->SetFileName(target.string().c_str());
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_TRUE(observer->HasError("no_such_folder")) << observer->AllErrors();
  EXPECT_FALSE(fs::exists(target));
  EXPECT_TRUE(vtkBaryFileWriter::CanWriteFile("a.off"));
  EXPECT_FALSE(vtkBaryFileWriter::CanWriteFile("a.mesh"));
}

TEST(BaryError, MessagesAreOnePrintableLine)
{
  const bary::Error e(bary::ErrorCode::Io, "a\nb\tc\x01\xff\xc3\xa9", "d\re");
  EXPECT_EQ(std::string(e.what()), "a b c\\x01\\xff\xc3\xa9; d e");
  EXPECT_EQ(e.message(), "a b c\\x01\\xff\xc3\xa9");
}

} // namespace
