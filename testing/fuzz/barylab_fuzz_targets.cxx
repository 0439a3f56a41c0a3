#include "barylab_fuzz_targets.h"

#include "vtkBaryConversion.h"
#include "vtkBaryDataIO.h"
#include "vtkBaryOFFWriter.h"
#include "vtkBarySplineData.h"

#include "core/common/error.h"
#include "core/deformation/skeleton.h"

#include "vtkCellArray.h"
#include "vtkDataSet.h"
#include "vtkDataSetWriter.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkOutputWindow.h"
#include "vtkPLYWriter.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkRectilinearGrid.h"
#include "vtkSTLWriter.h"
#include "vtkSmartPointer.h"
#include "vtkStructuredGrid.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLPolyDataWriter.h"
#include "vtkXMLUnstructuredGridWriter.h"

#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <unistd.h>

namespace barylab
{
namespace fuzz
{
namespace
{
std::vector<Target>& registry();

std::string slurp(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// What every successful read is used for: each point, each cell's ids, every array value,
/// so a reader's lazily wrong output shows here under the sanitizers.
void touch(vtkDataSet* data)
{
  double bounds[6];
  data->GetBounds(bounds);
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c)
    data->GetCellPoints(c, ids);
  vtkPointData* pd = data->GetPointData();
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
    if (vtkDataArray* a = pd->GetArray(i))
    {
      double range[2];
      for (int k = 0; k < a->GetNumberOfComponents(); ++k)
        a->GetRange(range, k);
    }
}

void read_data(const std::string& path, const std::uint8_t*, std::size_t)
{
  touch(vtkBaryDataIO::Read(path));
}

/// A spline grid (barylab spline's .vtu): read, then taken apart as a spline and its 2.5D
/// surfaces (vtkBarySplineData::FromGrid validates the cells, numbering and arrays).
void read_spline(const std::string& path, const std::uint8_t*, std::size_t)
{
  const vtkSmartPointer<vtkDataSet> data = vtkBaryDataIO::Read(path);
  auto* grid = vtkUnstructuredGrid::SafeDownCast(data);
  if (!grid)
    throw bary::Error(bary::ErrorCode::InvalidArgument, "not an unstructured grid");
  const vtkBarySpline spline = vtkBarySplineData::FromGrid(grid);
  touch(vtkBarySplineData::ToGrid(spline));
}

void read_dmat(const std::string& path, const std::uint8_t*, std::size_t)
{
  vtkBaryDataIO::ReadDMAT(path);
}

void read_numbers(const std::string& path, const std::uint8_t*, std::size_t)
{
  vtkBaryDataIO::ReadNumbers(path);
}

void read_pseudo_edges(const std::string& path, const std::uint8_t*, std::size_t)
{
  vtkBaryDataIO::ReadPseudoEdges(path);
}

/// The bundled 2D skeleton (9 joints, 8 bones): poses are read against it.
const bary::Skeleton& skeleton()
{
  static const bary::Skeleton s = vtkBaryConversion::ToSkeleton(
    vtkBaryDataIO::ReadPolyData(std::string(BARYLAB_DATA_DIR) + "/skeleton2d.tgf"), 2);
  return s;
}

/// A 3D chain of three bones: quaternion poses need a 3D skeleton.
const bary::Skeleton& skeleton3d()
{
  static const bary::Skeleton s = [] {
    bary::Skeleton k;
    k.C.resize(4, 3);
    k.C << 0, 0, 0, 0, 1, 0, 0, 2, 0, 1, 2, 0;
    k.BE.resize(3, 2);
    k.BE << 0, 1, 1, 2, 2, 3;
    return k;
  }();
  return s;
}

void read_pose(const std::string& path, const std::uint8_t*, std::size_t)
{
  vtkBaryDataIO::ReadPose(path, skeleton().handle_count(), &skeleton());
}

void read_pose_dmat(const std::string& path, const std::uint8_t*, std::size_t)
{
  vtkBaryDataIO::ReadPose(path, skeleton3d().handle_count(), &skeleton3d());
}

// --- seeds --------------------------------------------------------------------------------

std::string scratch_file(const std::string& extension)
{
  char name[] = "/tmp/barylab-seed-XXXXXX";
  const int fd = mkstemp(name);
  if (fd >= 0)
    close(fd);
  std::remove(name);
  return std::string(name) + extension;
}

template <class Writer>
std::string write_with(vtkDataObject* data, const std::string& extension,
  void (*configure)(Writer*) = nullptr)
{
  const std::string path = scratch_file(extension);
  vtkNew<Writer> w;
  w->SetInputData(data);
  w->SetFileName(path.c_str());
  if (configure)
    configure(w);
  w->Write();
  std::string bytes = slurp(path);
  std::remove(path.c_str());
  return bytes;
}

/// The bundled 3D cage (72 points, 140 triangles) with a 3-component "Weights" and an integer
/// point array; the 2D cage as a closed polyline with a vertex cell.
vtkSmartPointer<vtkPolyData> surface(const std::string& data_dir)
{
  vtkSmartPointer<vtkPolyData> cage = vtkBaryDataIO::ReadPolyData(data_dir + "/cage3d.obj");
  vtkNew<vtkDoubleArray> w;
  w->SetName("Weights");
  w->SetNumberOfComponents(3);
  vtkNew<vtkIntArray> ids;
  ids->SetName("CageLocation");
  for (vtkIdType i = 0; i < cage->GetNumberOfPoints(); ++i)
  {
    w->InsertNextTuple3(0.25, 0.5, 0.25 + 1e-3 * static_cast<double>(i));
    ids->InsertNextValue(static_cast<int>(i % 3));
  }
  cage->GetPointData()->AddArray(w);
  cage->GetPointData()->AddArray(ids);
  return cage;
}

vtkSmartPointer<vtkPolyData> polygon(const std::string& data_dir)
{
  vtkSmartPointer<vtkPolyData> cage = vtkBaryDataIO::ReadPolyData(data_dir + "/cage2d.obj");
  vtkNew<vtkCellArray> lines, verts;
  std::vector<vtkIdType> loop;
  for (vtkIdType i = 0; i < cage->GetNumberOfPoints(); ++i)
    loop.push_back(i);
  loop.push_back(0);
  lines->InsertNextCell(static_cast<vtkIdType>(loop.size()), loop.data());
  const vtkIdType zero = 0;
  verts->InsertNextCell(1, &zero);
  cage->SetLines(lines);
  cage->SetVerts(verts);
  return cage;
}

/// Two tetrahedra sharing a face, with a point array.
vtkSmartPointer<vtkUnstructuredGrid> tetrahedra()
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  const double x[5][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 0.4, 0.4, -1 } };
  for (const auto& p : x)
    points->InsertNextPoint(p);
  grid->SetPoints(points);
  const vtkIdType a[4] = { 0, 1, 2, 3 }, b[4] = { 0, 2, 1, 4 };
  grid->InsertNextCell(VTK_TETRA, 4, a);
  grid->InsertNextCell(VTK_TETRA, 4, b);
  vtkNew<vtkFloatArray> s;
  s->SetName("Weights");
  s->SetNumberOfComponents(2);
  for (int i = 0; i < 5; ++i)
    s->InsertNextTuple2(0.1 * i, 1 - 0.1 * i);
  grid->GetPointData()->AddArray(s);
  return grid;
}

std::vector<vtkSmartPointer<vtkDataSet>> structured()
{
  std::vector<vtkSmartPointer<vtkDataSet>> out;
  vtkNew<vtkFloatArray> s;
  s->SetName("Weights");
  for (int i = 0; i < 8; ++i)
    s->InsertNextValue(0.125f * static_cast<float>(i));
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(2, 2, 2);
  image->GetPointData()->SetScalars(s);
  out.push_back(image);
  auto rect = vtkSmartPointer<vtkRectilinearGrid>::New();
  rect->SetDimensions(2, 2, 2);
  for (int axis = 0; axis < 3; ++axis)
  {
    vtkNew<vtkDoubleArray> c;
    c->InsertNextValue(0.0);
    c->InsertNextValue(1.0 + axis);
    if (axis == 0)
      rect->SetXCoordinates(c);
    else if (axis == 1)
      rect->SetYCoordinates(c);
    else
      rect->SetZCoordinates(c);
  }
  rect->GetPointData()->AddArray(s);
  out.push_back(rect);
  auto sgrid = vtkSmartPointer<vtkStructuredGrid>::New();
  sgrid->SetDimensions(2, 2, 2);
  vtkNew<vtkPoints> points;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        points->InsertNextPoint(i, j + 0.1 * i, k);
  sgrid->SetPoints(points);
  sgrid->GetPointData()->AddArray(s);
  out.push_back(sgrid);
  return out;
}

template <class XMLWriter>
void xml_seeds(vtkDataObject* data, const std::string& ext, std::vector<std::string>& seeds)
{
  seeds.push_back(write_with<XMLWriter>(data, ext, [](XMLWriter* w) { w->SetDataModeToAscii(); }));
  seeds.push_back(write_with<XMLWriter>(data, ext, [](XMLWriter* w) {
    w->SetDataModeToBinary();
    w->SetCompressorTypeToNone();
  }));
  seeds.push_back(write_with<XMLWriter>(data, ext, [](XMLWriter* w) {
    w->SetDataModeToBinary();
    w->SetCompressorTypeToZLib();
  }));
  seeds.push_back(write_with<XMLWriter>(data, ext, [](XMLWriter* w) {
    w->SetDataModeToAppended();
    w->EncodeAppendedDataOff();
    w->SetCompressorTypeToNone();
  }));
  seeds.push_back(write_with<XMLWriter>(data, ext, [](XMLWriter* w) {
    w->SetDataModeToAppended();
    w->SetCompressorTypeToLZ4();
    w->SetHeaderTypeToUInt32();
  }));
  // what vtkBaryDataIO::Write writes: appended raw, LZ4
  seeds.push_back(write_with<XMLWriter>(data, ext, [](XMLWriter* w) {
    w->SetDataModeToAppended();
    w->EncodeAppendedDataOff();
    w->SetCompressorTypeToLZ4();
  }));
}

const char* const kLegacy42 = "# vtk DataFile Version 4.2\n"
                              "two triangles\n"
                              "ASCII\n"
                              "DATASET POLYDATA\n"
                              "POINTS 4 float\n"
                              "0 0 0 1 0 0 0 1 0 1 1 0\n"
                              "POLYGONS 2 8\n"
                              "3 0 1 2\n"
                              "3 1 3 2\n"
                              "POINT_DATA 4\n"
                              "SCALARS Weights double 2\n"
                              "LOOKUP_TABLE default\n"
                              "1 0 0.5 0.5 0 1 0.25 0.75\n"
                              "FIELD FieldData 1\n"
                              "CageLocation 1 4 int\n"
                              "0 0 2 1\n";

const char* const kMedit = "MeshVersionFormatted 1\n"
                           "Dimension 3\n"
                           "Vertices\n5\n"
                           "0 0 0 1\n1 0 0 1\n0 1 0 1\n0 0 1 1\n0.4 0.4 -1 2\n"
                           "Edges\n1\n1 2 0\n"
                           "Triangles\n2\n1 2 3 0\n2 3 4 0\n"
                           "Tetrahedra\n2\n1 2 3 4 1\n1 3 2 5 1\n"
                           "End\n";

const char* const kEdgeset = "# an LBC-style 2D cage: vertices with normals, one closed line\n"
                             "v -10 398 0\nv 400 398 0\nv 810 398 0\nv 810 -10 0\n"
                             "vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\n"
                             "g line\nl 1 2 3 4 1\n"
                             "f 1/1/1 2//2 -1/3/3\np 1 2\n";

std::vector<std::string> make_seeds(const Target& t, const std::string& data_dir)
{
  std::vector<std::string> seeds;
  const std::string& e = t.extension;
  if (e == ".vtp")
  {
    xml_seeds<vtkXMLPolyDataWriter>(surface(data_dir), e, seeds);
    xml_seeds<vtkXMLPolyDataWriter>(polygon(data_dir), e, seeds);
  }
  else if (t.name == "spline")
  {
    // The identity spline of degree 5 on a 2 x 1 grid of squares, as a 2.5D prism with a pinned
    // border point, in every XML variant.
    Eigen::MatrixXd V(6, 2);
    V << 0, 0, 1, 0, 2, 0, 0, 1, 1, 1, 2, 1;
    Eigen::MatrixXi T(4, 3);
    T << 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4;
    auto net = std::make_shared<bary::SplineNet>(V, T, 5);
    vtkBarySpline spline;
    spline.xy.emplace(bary::TriangularSpline::identity(net));
    spline.bottom.emplace(bary::TriangularSpline::constant(net, -0.1));
    spline.top.emplace(bary::TriangularSpline::constant(net, 0.1));
    spline.prism_bottom = -0.1;
    spline.prism_top = 0.1;
    spline.pinned = { 0 };
    xml_seeds<vtkXMLUnstructuredGridWriter>(vtkBarySplineData::ToGrid(spline), e, seeds);
  }
  else if (e == ".vtu")
  {
    xml_seeds<vtkXMLUnstructuredGridWriter>(tetrahedra(), e, seeds);
  }
  else if (e == ".vtk")
  {
    std::vector<vtkSmartPointer<vtkDataSet>> sets = structured();
    sets.insert(sets.begin(), { surface(data_dir), polygon(data_dir), tetrahedra() });
    for (vtkDataSet* d : sets)
      for (int binary = 0; binary < 2; ++binary)
        seeds.push_back(write_with<vtkDataSetWriter>(d, e, binary
            ? +[](vtkDataSetWriter* w) { w->SetFileTypeToBinary(); }
            : +[](vtkDataSetWriter* w) { w->SetFileTypeToASCII(); }));
    seeds.push_back(kLegacy42);
  }
  else if (e == ".obj")
  {
    for (const char* f : { "/cage3d.obj", "/cage2d.obj", "/heart_controls.obj",
           "/bad/quad_cage.obj", "/bad/nan_cage.obj" })
      seeds.push_back(slurp(data_dir + f));
    seeds.push_back(kEdgeset);
  }
  else if (e == ".stl")
  {
    vtkSmartPointer<vtkPolyData> s = surface(data_dir);
    seeds.push_back(write_with<vtkSTLWriter>(s, e, [](vtkSTLWriter* w) { w->SetFileTypeToASCII(); }));
    seeds.push_back(write_with<vtkSTLWriter>(s, e, [](vtkSTLWriter* w) { w->SetFileTypeToBinary(); }));
  }
  else if (e == ".ply")
  {
    vtkSmartPointer<vtkPolyData> s = surface(data_dir);
    seeds.push_back(write_with<vtkPLYWriter>(s, e, [](vtkPLYWriter* w) { w->SetFileTypeToASCII(); }));
    seeds.push_back(write_with<vtkPLYWriter>(s, e, [](vtkPLYWriter* w) {
      w->SetFileTypeToBinary();
      w->SetDataByteOrderToLittleEndian();
    }));
    seeds.push_back(write_with<vtkPLYWriter>(s, e, [](vtkPLYWriter* w) {
      w->SetFileTypeToBinary();
      w->SetDataByteOrderToBigEndian();
    }));
  }
  else if (e == ".off")
  {
    seeds.push_back(write_with<vtkBaryOFFWriter>(surface(data_dir), e));
    seeds.push_back(slurp(data_dir + "/bad/garbage.off"));
    seeds.push_back("COFF 4 2 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n"
                    "1 1 0 9 9 9 255\n3 0 1 2 1 0 0\n2 1 3\n");
  }
  else if (e == ".mesh")
    seeds.push_back(kMedit);
  else if (e == ".tgf")
  {
    seeds.push_back(slurp(data_dir + "/skeleton2d.tgf"));
    seeds.push_back("1 0 0 0\n2 0 1 0\n3 1 1 1\n4 2 0 0\n#\n1 2 1 0 0\n2 3\n#\n");
  }
  else if (e == ".mrk.json")
  {
    for (const char* f : { "/organ_landmarks.mrk.json", "/organ_landmarks_moved.mrk.json" })
      seeds.push_back(slurp(data_dir + f));
    seeds.push_back(R"({"markups": [{"type": "Curve", "coordinateSystem": "RAS", "controlPoints": [)"
                    R"({"label": "a, \"b\"", "position": [1e-300, -0.0, 5e300]},)"
                    R"({"position": [1, 2, 3], "positionStatus": "defined"}]}, {"controlPoints": []}]})");
  }
  else if (e == ".fcsv")
  {
    seeds.push_back(slurp(data_dir + "/organ_landmarks.fcsv"));
    seeds.push_back("# CoordinateSystem = 1\n# columns = label,z,y,x\n"
                    "\"a, \"\"b\"\"\",3,2,1\r\n\nc,1e-300,-0,5e300\n");
  }
  else if (t.name == "dmat")
  {
    seeds.push_back("3 2\n1\n2\n3\n4.5\n-5e-3\n6\n");
    seeds.push_back("1 4\n0\n0\n0.7071067811865476\n0.7071067811865476\n");
    seeds.push_back("0 0\n");
  }
  else if (t.name == "pose")
    seeds.push_back(slurp(data_dir + "/skeleton2d_pose.txt"));
  else if (t.name == "pose-dmat")
  {
    // one quaternion (x y z w) per bone of the 3D chain: as 4 columns, and as one column
    std::ostringstream rows, column, stacked;
    rows << "4 3\n";
    const double q[3][4] = { { 0, 0, 0, 1 }, { 0, 0, 0.38268343236508978, 0.92387953251128674 },
      { 0.5, 0.5, 0.5, 0.5 } };
    for (int c = 0; c < 4; ++c)
      for (int b = 0; b < 3; ++b)
        rows << q[b][c] << "\n";
    column << "1 12\n";
    for (int b = 0; b < 3; ++b)
      for (int c = 0; c < 4; ++c)
        column << q[b][c] << "\n";
    // libigl's stacked transforms: 4 rows of 3 per handle, column-major
    stacked << "3 12\n";
    for (int c = 0; c < 3; ++c)
      for (int h = 0; h < 3; ++h)
        for (int r = 0; r < 4; ++r)
          stacked << (r == c ? 1.0 : (r == 3 ? 0.25 * (h + 1) : 0.0)) << "\n";
    seeds.push_back(rows.str());
    seeds.push_back(column.str());
    seeds.push_back(stacked.str());
  }
  else if (t.name == "numbers")
    seeds.push_back("1 2 3.5 # user weights\n+4e-2\n\n5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20\n");
  else if (t.name == "pseudo-edges")
    seeds.push_back("# pseudo-edges\n0 1\n1 2 # comment\n\n2 0\n");
  return seeds;
}

const std::vector<std::string> kNumbers = { "nan", "-nan", "inf", "-inf", "1e999", "-1e999",
  "1e-400", "4294967301", "2147483648", "-2147483649", "9223372036854775808",
  "-9223372036854775808", "18446744073709551616", "0", "-1", "1e300", "0x10", "1.5", "-0",
  "4294967295", "65536" };

std::vector<std::string> with_numbers(std::vector<std::string> words)
{
  words.insert(words.end(), kNumbers.begin(), kNumbers.end());
  words.insert(words.end(), { " ", "\n", "\r\n", "\t", "#", "\0" });
  return words;
}

std::vector<Target> make_targets()
{
  const std::vector<std::string> xml = with_numbers({ "<VTKFile", "</VTKFile>", "<Piece",
    "</Piece>", "<DataArray", "</DataArray>", "<Points>", "<PointData>", "<CellData>",
    "<Polys>", "<Lines>", "<Verts>", "<Cells>", "NumberOfPoints=\"", "NumberOfPolys=\"",
    "NumberOfLines=\"", "NumberOfCells=\"", "NumberOfComponents=\"", "NumberOfTuples=\"",
    "type=\"Float64\"", "type=\"Int64\"", "type=\"UInt8\"", "type=\"String\"", "format=\"ascii\"",
    "format=\"binary\"", "format=\"appended\"", "offset=\"", "Name=\"connectivity\"",
    "Name=\"offsets\"", "Name=\"types\"", "header_type=\"UInt64\"", "header_type=\"UInt32\"",
    "compressor=\"vtkZLibDataCompressor\"", "compressor=\"vtkLZ4DataCompressor\"",
    "compressor=\"vtkLZMADataCompressor\"", "byte_order=\"BigEndian\"", "<AppendedData encoding=\"raw\">",
    "<AppendedData encoding=\"base64\">", "_", "\"", "/>", ">", "=" });
  const std::vector<std::string> legacy = with_numbers({ "# vtk DataFile Version 5.1\n",
    "# vtk DataFile Version 4.2\n", "# vtk DataFile Version 3.0\n", "ASCII\n", "BINARY\n",
    "DATASET ", "POLYDATA", "UNSTRUCTURED_GRID", "STRUCTURED_POINTS", "STRUCTURED_GRID",
    "RECTILINEAR_GRID", "FIELD", "POINTS ", "VERTICES ", "LINES ", "POLYGONS ",
    "TRIANGLE_STRIPS ", "CELLS ", "CELL_TYPES ", "OFFSETS vtktypeint64\n",
    "CONNECTIVITY vtktypeint64\n", "POINT_DATA ", "CELL_DATA ", "SCALARS ", "VECTORS ",
    "NORMALS ", "TEXTURE_COORDINATES ", "TENSORS ", "TENSORS6 ", "COLOR_SCALARS ",
    "LOOKUP_TABLE ", "default", "METADATA\n", "INFORMATION ", "DIMENSIONS ", "SPACING ",
    "ORIGIN ", "ASPECT_RATIO ", "X_COORDINATES ", "Y_COORDINATES ", "Z_COORDINATES ", "float",
    "double", "int", "unsigned_char", "char", "vtkIdType", "vtktypeint64", "string", "bit",
    "GLOBAL_IDS ", "PEDIGREE_IDS ", "NAME ", "DATA " });
  const std::vector<std::string> text = with_numbers({ "v ", "f ", "l ", "p ", "vn ", "vt ",
    "/", "//", "g ", "OFF", "COFF", "NOFF", "CNOFF", "solid", "facet normal", "outer loop",
    "vertex", "endloop", "endfacet", "endsolid", "ply\n", "format ascii 1.0\n",
    "format binary_little_endian 1.0\n", "format binary_big_endian 1.0\n", "element vertex ",
    "element face ", "property float x\n", "property list uchar int vertex_indices\n",
    "property list uint8 int32 vertex_indices\n", "property double ", "end_header\n",
    "MeshVersionFormatted", "Dimension", "Vertices", "Edges", "Triangles", "Tetrahedra",
    "Quadrilaterals", "Corners", "RequiredVertices", "End", "e" });
  const std::vector<std::string> markups = with_numbers({ "{", "}", "[", "]", ",", ":", "\"",
    "\\", "\\u0000", "\\ud800", "null", "true", "false", "\"markups\"", "\"controlPoints\"",
    "\"position\"", "\"positionStatus\"", "\"defined\"", "\"preview\"", "\"coordinateSystem\"",
    "\"LPS\"", "\"RAS\"", "\"coordinateUnits\"", "\"mm\"", "\"label\"", "\"id\"",
    "# CoordinateSystem = ", "# columns = ",
    "id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID", "LPS", "RAS", "\"\"", "\xff" });
  return {
    { "vtp", ".vtp", "vtkBaryDataIO::Read: VTK XML polygonal data", read_data, xml },
    { "vtu", ".vtu", "vtkBaryDataIO::Read: VTK XML unstructured grid", read_data, xml },
    { "spline", ".vtu", "vtkBarySplineData::FromGrid: a spline grid (barylab spline)", read_spline,
      xml },
    { "vtk", ".vtk", "vtkBaryDataIO::Read: VTK legacy data set", read_data, legacy },
    { "obj", ".obj", "vtkBaryDataIO::Read: Wavefront OBJ (vtkBaryOBJReader)", read_data, text },
    { "stl", ".stl", "vtkBaryDataIO::Read: STL, ASCII and binary", read_data, text },
    { "ply", ".ply", "vtkBaryDataIO::Read: PLY, ASCII and binary", read_data, text },
    { "off", ".off", "vtkBaryDataIO::Read: OFF (vtkBaryOFFReader)", read_data, text },
    { "mesh", ".mesh", "vtkBaryDataIO::Read: MEDIT .mesh (vtkBaryMEDITReader)", read_data, text },
    { "tgf", ".tgf", "vtkBaryDataIO::Read: libigl .tgf skeleton (vtkBaryTGFReader)", read_data, text },
    { "mrk-json", ".mrk.json", "vtkBaryDataIO::Read: 3D Slicer markups JSON (vtkBaryMarkupsReader)",
      read_data, markups },
    { "fcsv", ".fcsv", "vtkBaryDataIO::Read: 3D Slicer legacy .fcsv (vtkBaryMarkupsReader)",
      read_data, markups },
    { "dmat", ".dmat", "vtkBaryDataIO::ReadDMAT: libigl .dmat matrix", read_dmat, text },
    { "pose", ".txt", "vtkBaryDataIO::ReadPose: transforms a line, for the bundled skeleton",
      read_pose, text },
    { "pose-dmat", ".dmat",
      "vtkBaryDataIO::ReadPose: quaternions or stacked transforms (.dmat), for a 3D chain",
      read_pose_dmat, text },
    { "numbers", ".txt", "vtkBaryDataIO::ReadNumbers: tcc user weights", read_numbers, text },
    { "pseudo-edges", ".txt", "vtkBaryDataIO::ReadPseudoEdges: BBW pseudo-edges",
      read_pseudo_edges, text },
  };
}

std::vector<Target>& registry()
{
  static std::vector<Target> targets = make_targets();
  return targets;
}

class SilentWindow : public vtkOutputWindow
{
public:
  static SilentWindow* New();
  vtkTypeMacro(SilentWindow, vtkOutputWindow);
  void DisplayText(const char*) override {}
};
vtkStandardNewMacro(SilentWindow);
} // namespace

const std::vector<Target>& Targets()
{
  return registry();
}

const Target* FindTarget(const std::string& name)
{
  for (const Target& t : registry())
    if (t.name == name)
      return &t;
  return nullptr;
}

void RegisterTarget(Target target)
{
  registry().push_back(std::move(target));
}

std::vector<std::string> Seeds(const Target& target, const std::string& data_dir)
{
  if (target.own_seeds)
    return target.own_seeds();
  return make_seeds(target, data_dir);
}

std::string ScratchPath(const Target& target, const std::string& scratch_dir)
{
  return scratch_dir + "/input" + target.extension;
}

bool RunOne(const Target& target, const std::string& scratch_dir, const std::uint8_t* bytes,
  std::size_t size)
{
  std::string path;
  if (!target.extension.empty())
  {
    path = ScratchPath(target, scratch_dir);
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f)
      throw std::runtime_error("cannot write the scratch file " + path);
    if (size > 0)
      std::fwrite(bytes, 1, size, f);
    std::fclose(f);
  }
  try
  {
    target.run(path, bytes, size);
    return true;
  }
  catch (const bary::Error&)
  {
    return false;
  }
}

void Quiet()
{
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  vtkNew<SilentWindow> silent;
  vtkOutputWindow::SetInstance(silent);
}

} // namespace fuzz
} // namespace barylab
