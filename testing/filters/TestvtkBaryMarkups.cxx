// Tests of 3D Slicer's markups through vtkBaryDataIO (vtkBaryMarkupsReader / Writer):
// hand-written Slicer-style .mrk.json and .fcsv files in LPS and in RAS read to the same LPS
// points (the expected values are written out by hand here, RAS negated by hand); write -> read
// round trips keep every bit of the coordinates and the labels; each malformed file is a
// bary::Error naming the file, the point or line and the problem; failed writes leave no file.
#include "filters_test_utils.h"

#include "vtkBaryDataIO.h"
#include "vtkBaryFileReader.h"
#include "vtkBaryMarkupsReader.h"

#include "core/common/error.h"

#include "vtkPointData.h"
#include "vtkStringArray.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace
{
using namespace barylab_test;
namespace fs = std::filesystem;

fs::path Scratch()
{
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::path(BARYLAB_TEST_OUTPUT_DIR) / "filters_markups" /
    (std::string(test->test_suite_name()) + "." + test->name());
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

std::string ReadText(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// The physical points of the hand-written files, in LPS, and their labels.
const double kLPS[3][3] = { { 12.5, -30.25, 101.0 }, { -7.75, 4.0, -0.125 },
  { 0.0, 88.5, 64.0625 } };
const char* const kLabels[3] = { "dome", "hilum, left", "tip \"A\"" };

const char* const kJsonLPS = R"({"@schema": "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#",
"markups": [{"type": "Fiducial", "coordinateSystem": "LPS", "coordinateUnits": "mm",
  "controlPoints": [
    {"id": "1", "label": "dome", "position": [12.5, -30.25, 101.0], "positionStatus": "defined"},
    {"id": "2", "label": "hilum, left", "position": [-7.75, 4.0, -0.125], "positionStatus": "defined"},
    {"id": "3", "label": "tip \"A\"", "description": "caudal", "position": [0.0, 88.5, 64.0625],
     "orientation": [-1.0, -0.0, -0.0, -0.0, -1.0, -0.0, 0.0, 0.0, 1.0], "selected": true,
     "locked": false, "visibility": true, "positionStatus": "defined"}
  ]}]}
)";

// the same points in RAS (x and y negated by hand); no positionStatus (defined by default)
const char* const kJsonRAS = R"({"@schema": "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.0.json#",
"markups": [{"type": "Fiducial", "coordinateSystem": "RAS", "controlPoints": [
    {"label": "dome", "position": [-12.5, 30.25, 101.0]},
    {"label": "hilum, left", "position": [7.75, -4.0, -0.125]},
    {"label": "tip \"A\"", "position": [-0.0, -88.5, 64.0625]}]}]}
)";

const char* const kFcsvRAS = "# Markups fiducial file version = 4.10\n"
                             "# CoordinateSystem = 0\n"
                             "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n"
                             "vtkMRMLMarkupsFiducialNode_0,-12.5,30.25,101,0,0,0,1,1,1,0,dome,,\n"
                             "vtkMRMLMarkupsFiducialNode_1,7.75,-4,-0.125,0,0,0,1,1,1,0,\"hilum, left\",,\r\n"
                             "vtkMRMLMarkupsFiducialNode_2,0,-88.5,64.0625,0,0,0,1,1,1,0,\"tip \"\"A\"\"\",caudal,vtkMRMLScalarVolumeNode1\n";

// LPS, columns in another order (the header names them), no trailing columns
const char* const kFcsvLPS = "# Markups fiducial file version = 4.11\n"
                             "# CoordinateSystem = LPS\n"
                             "# columns = label,z,y,x\n"
                             "dome,101,-30.25,12.5\n"
                             "\n"
                             "\"hilum, left\",-0.125,4,-7.75\n"
                             "\"tip \"\"A\"\"\",64.0625,88.5,0\n";

void ExpectPoints(vtkDataSet* data, const std::string& what)
{
  ASSERT_NE(data, nullptr) << what;
  ASSERT_EQ(data->GetNumberOfPoints(), 3) << what;
  EXPECT_EQ(data->GetNumberOfCells(), 3) << what << ": one vertex cell per point";
  auto* labels = vtkStringArray::SafeDownCast(data->GetPointData()->GetAbstractArray("Label"));
  ASSERT_NE(labels, nullptr) << what;
  for (vtkIdType i = 0; i < 3; ++i)
  {
    double x[3];
    data->GetPoint(i, x);
    for (int k = 0; k < 3; ++k) // decimal fractions of 1/16: exact, and -0 == 0
      EXPECT_EQ(x[k], kLPS[i][k]) << what << " point " << i << " axis " << k;
    EXPECT_EQ(labels->GetValue(i), kLabels[i]) << what << " point " << i;
  }
}

/// The bary::Error of reading @p path (fails the test when the read succeeds).
bary::Error ReadError(const std::string& path)
{
  try
  {
    vtkBaryDataIO::Read(path);
  }
  catch (const bary::Error& e)
  {
    return e;
  }
  ADD_FAILURE() << path << " was read";
  return bary::Error(bary::ErrorCode::Internal, "read");
}
} // namespace

TEST(vtkBaryMarkups, SlicerFilesInLPSAndRASReadToTheSameLPSPoints)
{
  const fs::path dir = Scratch();
  const std::string files[4] = { WriteText(dir / "lps.mrk.json", kJsonLPS),
    WriteText(dir / "ras.MRK.JSON", kJsonRAS), WriteText(dir / "ras.fcsv", kFcsvRAS),
    WriteText(dir / "lps.fcsv", kFcsvLPS) };
  for (const std::string& f : files)
  {
    EXPECT_TRUE(vtkBaryDataIO::CanRead(f)) << f;
    ExpectPoints(vtkBaryDataIO::Read(f), f);
  }
  // ids and descriptions where the file has them
  auto json = vtkBaryDataIO::Read(files[0]);
  auto* ids = vtkStringArray::SafeDownCast(json->GetPointData()->GetAbstractArray("Id"));
  auto* desc = vtkStringArray::SafeDownCast(json->GetPointData()->GetAbstractArray("Description"));
  ASSERT_TRUE(ids && desc);
  EXPECT_EQ(ids->GetValue(1), "2");
  EXPECT_EQ(desc->GetValue(2), "caudal");
  EXPECT_EQ(desc->GetValue(0), "");
  auto fcsv = vtkBaryDataIO::Read(files[2]);
  ids = vtkStringArray::SafeDownCast(fcsv->GetPointData()->GetAbstractArray("Id"));
  ASSERT_NE(ids, nullptr);
  EXPECT_EQ(ids->GetValue(2), "vtkMRMLMarkupsFiducialNode_2");
  // no ids in the RAS JSON: no Id array
  EXPECT_EQ(vtkBaryDataIO::Read(files[1])->GetPointData()->GetAbstractArray("Id"), nullptr);
  // a pipeline source reads them too
  vtkNew<vtkBaryFileReader> reader;
  reader->SetFileName(files[3].c_str());
  ASSERT_EQ(RunPipeline(reader), 1);
  ExpectPoints(vtkDataSet::SafeDownCast(reader->GetOutputDataObject(0)), "vtkBaryFileReader");
}

TEST(vtkBaryMarkups, SeveralMarkupsAreReadInFileOrder)
{
  const fs::path dir = Scratch();
  const std::string f = WriteText(dir / "two.mrk.json", R"({"markups": [
    {"type": "Fiducial", "coordinateSystem": "RAS", "controlPoints": [{"label": "a", "position": [1, 2, 3]}]},
    {"type": "Line", "controlPoints": []},
    {"type": "Curve", "coordinateSystem": "LPS", "controlPoints": [{"label": "b", "position": [4, 5, 6]},
      {"label": "c", "position": [7, 8, 9]}]}]})");
  auto data = vtkBaryDataIO::Read(f);
  ASSERT_EQ(data->GetNumberOfPoints(), 3);
  const double expected[3][3] = { { -1, -2, 3 }, { 4, 5, 6 }, { 7, 8, 9 } };
  for (vtkIdType i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(data->GetPoint(i)[k], expected[i][k]);
}

TEST(vtkBaryMarkups, WriteThenReadKeepsEveryBitAndTheLabels)
{
  const fs::path dir = Scratch();
  // coordinates that need 17 digits, tiny and huge magnitudes, a negative zero
  auto cloud = MakePointCloud({ { 0.1, -2.0 / 3.0, 1e-300 }, { 123456.78901234567, -0.0, 5e300 },
    { std::nextafter(1.0, 2.0), -std::nextafter(1.0, 0.0), 3.141592653589793 } });
  vtkNew<vtkStringArray> labels;
  labels->SetName("Label");
  for (const char* l : { "plain", "comma, and \"quotes\"", " spaced \\ back\xc3\xa9" })
    labels->InsertNextValue(l);
  cloud->GetPointData()->AddArray(labels);
  for (const char* name : { "out.mrk.json", "out.fcsv" })
  {
    const std::string path = (dir / name).string();
    EXPECT_TRUE(vtkBaryDataIO::CanWrite(path));
    vtkBaryDataIO::Write(cloud, path);
    auto back = vtkBaryDataIO::Read(path);
    ASSERT_EQ(back->GetNumberOfPoints(), 3) << name;
    auto* read = vtkStringArray::SafeDownCast(back->GetPointData()->GetAbstractArray("Label"));
    ASSERT_NE(read, nullptr) << name;
    for (vtkIdType i = 0; i < 3; ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        const double a = cloud->GetPoint(i)[k], b = back->GetPoint(i)[k];
        EXPECT_EQ(a, b) << name << " point " << i << " axis " << k;
        EXPECT_EQ(std::signbit(a), std::signbit(b)) << name << " point " << i << " axis " << k;
      }
      EXPECT_EQ(read->GetValue(i), labels->GetValue(i)) << name << " point " << i;
    }
    const std::string text = ReadText(path);
    if (name[4] == 'm')
    {
      // the form 3D Slicer 5 writes (the JSON is parsed independently in the CLI test)
      for (const char* key : { "markups-schema-v1.0.3.json#\"", "\"type\": \"Fiducial\"",
             "\"coordinateSystem\": \"LPS\"", "\"coordinateUnits\": \"mm\"",
             "\"positionStatus\": \"defined\"" })
        EXPECT_NE(text.find(key), std::string::npos) << key;
    }
    else
    {
      EXPECT_EQ(text.rfind("# Markups fiducial file version = 4.11\n# CoordinateSystem = LPS\n"
                           "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n",
                  0),
        0u);
      EXPECT_NE(text.find(",\"comma, and \"\"quotes\"\"\","), std::string::npos);
    }
  }
  // no files but the two outputs (the temporary files are gone)
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2);
}

TEST(vtkBaryMarkups, AnyPointSetIsWrittenWithDefaultLabels)
{
  const fs::path dir = Scratch();
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(1, 2, 3);
  points->InsertNextPoint(-4, 5.5, 0);
  grid->SetPoints(points);
  const std::string path = (dir / "grid.mrk.json").string();
  vtkBaryDataIO::Write(grid, path);
  auto back = vtkBaryDataIO::Read(path);
  ASSERT_EQ(back->GetNumberOfPoints(), 2);
  EXPECT_EQ(back->GetPoint(1)[1], 5.5);
  auto* labels = vtkStringArray::SafeDownCast(back->GetPointData()->GetAbstractArray("Label"));
  auto* ids = vtkStringArray::SafeDownCast(back->GetPointData()->GetAbstractArray("Id"));
  ASSERT_TRUE(labels && ids);
  EXPECT_EQ(labels->GetValue(0), "F-1");
  EXPECT_EQ(labels->GetValue(1), "F-2");
  EXPECT_EQ(ids->GetValue(1), "2");
}

TEST(vtkBaryMarkups, ExtensionsAreRecognised)
{
  EXPECT_TRUE(vtkBaryDataIO::CanRead("a/b.mrk.json"));
  EXPECT_TRUE(vtkBaryDataIO::CanRead("B.Mrk.Json"));
  EXPECT_TRUE(vtkBaryDataIO::CanRead("c.FCSV"));
  EXPECT_FALSE(vtkBaryDataIO::CanRead("summary.json"));
  EXPECT_FALSE(vtkBaryDataIO::CanWrite("summary.json"));
  EXPECT_TRUE(vtkBaryDataIO::CanWrite("x.mrk.json"));
  EXPECT_TRUE(vtkBaryDataIO::CanWrite("x.fcsv"));
  EXPECT_TRUE(vtkBaryMarkupsReader::IsMarkupsFile("x.fcsv"));
  EXPECT_FALSE(vtkBaryMarkupsReader::IsMarkupsFile(nullptr));
}

TEST(vtkBaryMarkups, MalformedFilesAreClearErrors)
{
  const fs::path dir = Scratch();
  struct Case
  {
    const char* name;
    const char* text;
    bary::ErrorCode code;
    std::vector<const char*> says; ///< in the message, besides the file name
  };
  const std::string point = R"({"label": "ok", "position": [1, 2, 3]})";
  const std::vector<Case> cases = {
    { "truncated.mrk.json", R"({"markups": [{"controlPoints": [{"position": [1, 2)",
      bary::ErrorCode::Io, { "not valid JSON", "line 1" } },
    { "nan-literal.mrk.json", R"({"markups": [{"controlPoints": [{"position": [NaN, 2, 3]}]}]})",
      bary::ErrorCode::Io, { "not valid JSON" } },
    { "array.mrk.json", "[1, 2, 3]", bary::ErrorCode::Io, { "not an object" } },
    { "no-markups.mrk.json", R"({"@schema": "x", "points": []})", bary::ErrorCode::Io,
      { "no \"markups\" list" } },
    { "empty-markups.mrk.json", R"({"markups": []})", bary::ErrorCode::Io, { "holds no markups" } },
    { "no-points.mrk.json", R"({"markups": [{"type": "Fiducial", "controlPoints": []}]})",
      bary::ErrorCode::Io, { "no control points" } },
    { "no-position.mrk.json",
      R"({"markups": [{"controlPoints": [{"label": "ok", "position": [1, 2, 3]}, {"label": "B"}]}]})",
      bary::ErrorCode::Io, { "markup 0, control point 1 ('B') has no position" } },
    { "preview.mrk.json",
      R"({"markups": [{"controlPoints": [{"label": "A", "position": [1, 2, 3], "positionStatus": "preview"}]}]})",
      bary::ErrorCode::Io, { "control point 0 ('A')", "positionStatus is \"preview\"", "order" } },
    { "undefined.mrk.json",
      R"({"markups": [{"controlPoints": [{"label": "ok", "position": [1, 2, 3]}]},
          {"controlPoints": [{"label": "U", "position": [0, 0, 0], "positionStatus": "undefined"}]}]})",
      bary::ErrorCode::Io, { "markup 1, control point 1 ('U')", "\"undefined\"" } },
    { "two-numbers.mrk.json", R"({"markups": [{"controlPoints": [{"position": [1, 2]}]}]})",
      bary::ErrorCode::Io, { "control point 0", "[1,2]", "not three numbers" } },
    { "string-number.mrk.json", R"({"markups": [{"controlPoints": [{"position": [1, "2", 3]}]}]})",
      bary::ErrorCode::Io, { "not three numbers" } },
    // JSON has no NaN or infinity: a number beyond double's range is refused by the parser
    { "overflow.mrk.json", R"({"markups": [{"controlPoints": [{"position": [1, 1e999, 3]}]}]})",
      bary::ErrorCode::Io, { "not valid JSON", "1e999" } },
    { "bad-utf8.mrk.json", "{\"markups\": [{\"controlPoints\": [{\"label\": \"\xff\"}]}]}",
      bary::ErrorCode::Io, { "not valid JSON", "\\xff" } },
    { "ijk.mrk.json", R"({"markups": [{"coordinateSystem": "IJK", "controlPoints": [{"position": [1, 2, 3]}]}]})",
      bary::ErrorCode::Io, { "markup 0", "unknown coordinate system \"IJK\"" } },
    { "microns.mrk.json", R"({"markups": [{"coordinateUnits": "um", "controlPoints": [{"position": [1, 2, 3]}]}]})",
      bary::ErrorCode::Io, { "units \"um\"" } },
    { "nan.fcsv", "# CoordinateSystem = LPS\nF,1,2,3,0,0,0,1,1,1,0,a,,\nG,nan,2,3,0,0,0,1,1,1,0,b,,\n",
      bary::ErrorCode::NonFinite, { "line 3", "control point 1 ('b')", "x is not finite" } },
    { "short.fcsv", "# CoordinateSystem = RAS\nF,1,2\n", bary::ErrorCode::Io,
      { "line 2", "3 comma-separated fields", "4 needed" } },
    { "word.fcsv", "# CoordinateSystem = 1\n\nF,1,two,3,0,0,0,1,1,1,0,a,,\n", bary::ErrorCode::Io,
      { "line 3", "y 'two' is not a number" } },
    { "ijk.fcsv", "# Markups fiducial file version = 4.11\n# CoordinateSystem = 2\nF,1,2,3\n",
      bary::ErrorCode::Io, { "line 2", "unknown coordinate system '2'" } },
    { "quote.fcsv", "F,1,2,3,0,0,0,1,1,1,0,\"open,,\n", bary::ErrorCode::Io,
      { "line 1", "unterminated quote" } },
    { "no-z.fcsv", "# columns = id,x,y,label\nF,1,2,a\n", bary::ErrorCode::Io,
      { "line 1", "does not name x, y and z" } },
    { "headers-only.fcsv", "# Markups fiducial file version = 4.11\n# CoordinateSystem = LPS\n",
      bary::ErrorCode::Io, { "no control points" } },
  };
  for (const Case& c : cases)
  {
    const std::string path = WriteText(dir / c.name, c.text);
    const bary::Error e = ReadError(path);
    const std::string message = e.what();
    EXPECT_EQ(e.code(), c.code) << c.name << ": " << message;
    EXPECT_NE(message.find("'" + path + "'"), std::string::npos) << message;
    for (const char* s : c.says)
      EXPECT_NE(message.find(s), std::string::npos) << c.name << ": '" << s << "' not in: " << message;
  }
}

TEST(vtkBaryMarkups, FailedWritesLeaveNoFile)
{
  const fs::path dir = Scratch();
  auto cloud = MakePointCloud({ { 1, 2, 3 }, { 4, std::numeric_limits<double>::quiet_NaN(), 6 } });
  auto empty = MakePointCloud({});
  for (const char* name : { "nan.mrk.json", "nan.fcsv" })
  {
    try
    {
      vtkBaryDataIO::Write(cloud, (dir / name).string());
      ADD_FAILURE() << name << " was written";
    }
    catch (const bary::Error& e)
    {
      EXPECT_EQ(e.code(), bary::ErrorCode::Io);
      EXPECT_NE(std::string(e.what()).find("point 1 has a non-finite coordinate"), std::string::npos)
        << e.what();
    }
  }
  EXPECT_THROW(vtkBaryDataIO::Write(empty, (dir / "empty.mrk.json").string()), bary::Error);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0);
}
