#include "vtkBaryDataIO.h"

#include "vtkBaryOBJReader.h"
#include "vtkBaryOFFReader.h"
#include "vtkBaryPLYReader.h"
#include "vtkBaryTextParsing.h"
#include "vtkBaryOFFWriter.h"
#include "vtkBaryMEDITReader.h"
#include "vtkBaryMarkupsReader.h"
#include "vtkBaryMarkupsWriter.h"
#include "vtkBaryTGFReader.h"

#include "vtkBaryConversion.h"
#include "vtkBaryErrorObserver.h"
#include "vtkBaryFormatCheck.h"
#include "vtkBaryLegacyVTK.h"

#include "core/common/error.h"
#include "core/deformation/linear_blend_skinning.h"

#include "vtkAlgorithm.h"
#include "vtkAppendFilter.h"
#include "vtkCommand.h"
#include "vtkDataSet.h"
#include "vtkDataSetWriter.h"
#include "vtkExecutive.h"
#include "vtkOBJWriter.h"
#include "vtkObjectFactory.h"
#include "vtkOutputWindow.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkImageData.h"
#include "vtkRectilinearGrid.h"
#include "vtkStructuredGrid.h"
#include "vtkUnsignedCharArray.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkPointData.h"
#include "vtkPLYWriter.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkSTLReader.h"
#include "vtkSTLWriter.h"
#include "vtkUnstructuredGrid.h"
#include "vtkWriter.h"
#include "vtkXMLWriter.h"
#include "vtkXMLPPolyDataReader.h"
#include "vtkXMLPUnstructuredGridReader.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLPolyDataWriter.h"
#include "vtkXMLUnstructuredGridReader.h"
#include "vtkXMLUnstructuredGridWriter.h"

#include <algorithm>
#include <array>
#include <climits>
#include <sstream>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <sys/stat.h>
#include <vector>

vtkStandardNewMacro(vtkBaryDataIO);

namespace
{
using bary::Error;
using bary::ErrorCode;

/// Takes the place of VTK's output window while a file is read: VTK's readers report part of
/// their problems (a data size that does not match its declaration, an unknown attribute type)
/// through the global output window rather than through the reader's error events. Each
/// message is kept, not printed, and the read then fails with it.
class CaptureOutputWindow : public vtkOutputWindow
{
public:
  static CaptureOutputWindow* New();
  vtkTypeMacro(CaptureOutputWindow, vtkOutputWindow);
  void DisplayText(const char* text) override { this->Keep(text); }
  void DisplayErrorText(const char* text) override { this->Keep(text); }
  void DisplayWarningText(const char* text) override { this->Keep(text); }
  void DisplayGenericWarningText(const char* text) override { this->Keep(text); }
  void DisplayDebugText(const char*) override {}
  /// The first message, as one line without VTK's "In file, line" and "vtkClass (0x..): ".
  std::string First() const { return this->Messages.empty() ? std::string() : this->Messages.front(); }

private:
  void Keep(const char* text)
  {
    std::string line;
    std::string all = text ? text : "";
    // the last non-empty line holds the message; strip a "vtkClass (0x...): " prefix
    std::size_t end = all.find_last_not_of(" \n\r");
    if (end == std::string::npos)
      return;
    all.erase(end + 1);
    const std::size_t start = all.find_last_of('\n');
    line = start == std::string::npos ? all : all.substr(start + 1);
    const std::size_t object = line.find("): ");
    if (line.rfind("vtk", 0) == 0 && object != std::string::npos)
      line = line.substr(object + 3);
    this->Messages.push_back(line);
  }
  std::vector<std::string> Messages;
};
vtkStandardNewMacro(CaptureOutputWindow);

/// Installs a CaptureOutputWindow for its lifetime.
class ScopedCapture
{
public:
  ScopedCapture()
    : Previous(vtkOutputWindow::GetInstance())
  {
    this->Previous->Register(nullptr);
    vtkOutputWindow::SetInstance(this->Window);
  }
  ~ScopedCapture()
  {
    vtkOutputWindow::SetInstance(this->Previous);
    this->Previous->UnRegister(nullptr);
  }
  ScopedCapture(const ScopedCapture&) = delete;
  ScopedCapture& operator=(const ScopedCapture&) = delete;
  const CaptureOutputWindow* operator->() const { return this->Window; }

private:
  vtkOutputWindow* Previous;
  vtkNew<CaptureOutputWindow> Window;
};

/// The largest number of points of a data set whose points are implicit (an image's grid, a
/// rectilinear grid): a header of a few bytes can announce 10^15 of them.
constexpr vtkIdType kMaxImplicitPoints = vtkIdType(1) << 31;

/// One of a data set's cell arrays must be well formed before VTK builds anything from it:
/// offsets from 0, increasing, ending at the connectivity's length, every id a point, every
/// cell at least @p least points (VTK's cell map throws on fewer and leaves the data set
/// without cells, and the next cell access crashes). Cells are numbered from @p first in
/// messages; returns their count.
vtkIdType check_cell_array(vtkCellArray* cells, vtkIdType np, vtkIdType least, const char* kind,
  const std::string& path, vtkIdType first)
{
  if (!cells || cells->GetNumberOfCells() == 0)
    return 0;
  vtkDataArray* offsets = cells->GetOffsetsArray();
  vtkDataArray* connectivity = cells->GetConnectivityArray();
  const auto fail = [&](const std::string& what) {
    return Error(ErrorCode::Io, "cannot read '" + path + "': " + what);
  };
  if (!offsets || !connectivity || offsets->GetNumberOfComponents() != 1 ||
    connectivity->GetNumberOfComponents() != 1)
    throw fail(std::string("the ") + kind + " cells have no valid offsets and connectivity");
  const vtkIdType nc = offsets->GetNumberOfTuples() - 1;
  const vtkIdType size = connectivity->GetNumberOfTuples();
  if (nc < 0 || offsets->GetComponent(0, 0) != 0.0 ||
    offsets->GetComponent(nc, 0) != static_cast<double>(size))
    throw fail(std::string("the ") + kind + " cells' offsets do not span their connectivity (" +
      std::to_string(size) + " ids)");
  double begin = 0.0;
  for (vtkIdType c = 0; c < nc; ++c)
  {
    const double end = offsets->GetComponent(c + 1, 0);
    if (!(end - begin >= static_cast<double>(least)) || end > static_cast<double>(size))
      throw fail("cell " + std::to_string(first + c) + " (a " + kind + ") has " +
        (end < begin ? std::string("a negative number of") : vtkBaryConversion::CountText(end - begin)) +
        " points, fewer than the " + std::to_string(least) + " it needs");
    for (auto k = static_cast<vtkIdType>(begin); k < static_cast<vtkIdType>(end); ++k)
    {
      const double id = connectivity->GetComponent(k, 0);
      if (!(id >= 0.0 && id < static_cast<double>(np)))
        throw Error(ErrorCode::InvalidArgument,
          "cannot read '" + path + "': cell " + std::to_string(first + c) + " names point " +
            vtkBaryConversion::CountText(id) + ", but the file has " + std::to_string(np) + " points (0 to " +
            std::to_string(np - 1) + ")");
    }
    begin = end;
  }
  return nc;
}

/// The points a fixed-size VTK cell type has (0: any number, from a minimum; -1: not a type
/// BaryLab reads).
int cell_type_points(int type, vtkIdType& least)
{
  least = 1;
  switch (type)
  {
    case VTK_VERTEX: return 1;
    case VTK_POLY_VERTEX: return 0;
    case VTK_LINE: return 2;
    case VTK_POLY_LINE: least = 2; return 0;
    case VTK_TRIANGLE: return 3;
    case VTK_TRIANGLE_STRIP: least = 3; return 0;
    case VTK_POLYGON: least = 3; return 0;
    case VTK_PIXEL: return 4;
    case VTK_QUAD: return 4;
    case VTK_TETRA: return 4;
    case VTK_VOXEL: return 8;
    case VTK_HEXAHEDRON: return 8;
    case VTK_WEDGE: return 6;
    case VTK_PYRAMID: return 5;
    case VTK_PENTAGONAL_PRISM: return 10;
    case VTK_HEXAGONAL_PRISM: return 12;
    case VTK_QUADRATIC_EDGE: return 3;
    case VTK_QUADRATIC_TRIANGLE: return 6;
    case VTK_QUADRATIC_QUAD: return 8;
    case VTK_QUADRATIC_TETRA: return 10;
    case VTK_QUADRATIC_HEXAHEDRON: return 20;
    case VTK_QUADRATIC_WEDGE: return 15;
    case VTK_QUADRATIC_PYRAMID: return 13;
    default: return -1;
  }
}

/// What a reader gave must be safe to use: finite points, well-formed cells naming existing
/// points, one tuple per point in every point-data array (cell arrays that do not fit are
/// dropped), grids whose size matches their points.
/// @throws Error naming the file and the first problem.
void validate_read(vtkDataSet* data, const std::string& path)
{
  const auto fail = [&path](ErrorCode code, const std::string& what) {
    return Error(code, "cannot read '" + path + "': " + what);
  };
  const auto finite3 = [](const double* x) {
    return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
  };
  if (auto* image = vtkImageData::SafeDownCast(data))
  {
    if (!finite3(image->GetOrigin()) || !finite3(image->GetSpacing()))
      throw fail(ErrorCode::NonFinite, "the image's origin or spacing is not finite");
  }
  else if (auto* rect = vtkRectilinearGrid::SafeDownCast(data))
  {
    int dims[3];
    rect->GetDimensions(dims);
    vtkDataArray* coords[3] = { rect->GetXCoordinates(), rect->GetYCoordinates(),
      rect->GetZCoordinates() };
    for (int k = 0; k < 3; ++k)
    {
      if (!coords[k] || coords[k]->GetNumberOfTuples() != dims[k])
        throw fail(ErrorCode::Io, std::string("the grid's ") + "xyz"[k] + " coordinates do not "
          "match its dimension " + std::to_string(dims[k]));
      for (vtkIdType i = 0; i < dims[k]; ++i)
        if (!std::isfinite(coords[k]->GetComponent(i, 0)))
          throw fail(ErrorCode::NonFinite, "a grid coordinate is not finite");
    }
  }
  if (vtkImageData::SafeDownCast(data) || vtkRectilinearGrid::SafeDownCast(data))
  {
    if (data->GetNumberOfPoints() > kMaxImplicitPoints)
      throw fail(ErrorCode::Io, "the grid has " + std::to_string(data->GetNumberOfPoints()) +
        " points, more than BaryLab reads (2^31)");
  }
  const vtkIdType np = data->GetNumberOfPoints();
  if (auto* set = vtkPointSet::SafeDownCast(data))
  {
    vtkPoints* points = set->GetPoints();
    for (vtkIdType p = 0; points && p < np; ++p)
    {
      double x[3];
      points->GetPoint(p, x);
      if (!finite3(x))
        throw fail(ErrorCode::NonFinite,
          "point " + std::to_string(p) + " has a non-finite coordinate (NaN or infinity)");
    }
  }
  if (auto* grid = vtkStructuredGrid::SafeDownCast(data))
  {
    int dims[3];
    grid->GetDimensions(dims);
    if (static_cast<double>(dims[0]) * dims[1] * dims[2] != static_cast<double>(np))
      throw fail(ErrorCode::Io, "the grid's dimensions " + std::to_string(dims[0]) + " x " +
        std::to_string(dims[1]) + " x " + std::to_string(dims[2]) + " do not match its " +
        std::to_string(np) + " points");
  }
  if (auto* poly = vtkPolyData::SafeDownCast(data))
  {
    // cells are numbered as vtkPolyData numbers them: vertices, lines, polygons, strips
    vtkIdType first = check_cell_array(poly->GetVerts(), np, 1, "vertex", path, 0);
    first += check_cell_array(poly->GetLines(), np, 2, "line", path, first);
    first += check_cell_array(poly->GetPolys(), np, 3, "polygon", path, first);
    check_cell_array(poly->GetStrips(), np, 3, "triangle strip", path, first);
  }
  else if (auto* grid = vtkUnstructuredGrid::SafeDownCast(data))
  {
    vtkCellArray* cells = grid->GetCells();
    vtkUnsignedCharArray* types = grid->GetCellTypesArray();
    const vtkIdType nc = cells ? cells->GetNumberOfCells() : 0;
    if (nc > 0)
    {
      check_cell_array(cells, np, 1, "cell", path, 0);
      if (!types || types->GetNumberOfTuples() != nc)
        throw fail(ErrorCode::Io, "the grid has " + std::to_string(nc) + " cells but " +
          std::to_string(types ? types->GetNumberOfTuples() : 0) + " cell types");
      for (vtkIdType c = 0; c < nc; ++c)
      {
        vtkIdType least = 1;
        const int type = types->GetValue(c);
        const int fixed = cell_type_points(type, least);
        const vtkIdType size = cells->GetCellSize(c);
        if (type == VTK_BEZIER_TRIANGLE)
        {
          // BaryLab's spline grids: (d + 1)(d + 2)/2 points, degree 1 to 12.
          bool triangular = false;
          for (vtkIdType d = 1; d <= 12; ++d)
            triangular = triangular || size == (d + 1) * (d + 2) / 2;
          if (!triangular)
            throw fail(ErrorCode::Io, "Bézier triangle " + std::to_string(c) + " has " +
              std::to_string(size) + " points, not (d + 1)(d + 2)/2 for a degree d in [1, 12]");
          continue;
        }
        if (fixed < 0)
          throw fail(ErrorCode::Io, "cell " + std::to_string(c) + " has VTK cell type " +
            std::to_string(type) + ", which BaryLab does not read (linear and quadratic "
            "cells, polygons, strips, poly-lines and Bézier triangles are read; no polyhedra)");
        if ((fixed > 0 && size != fixed) || (fixed == 0 && size < least))
          throw fail(ErrorCode::Io, "cell " + std::to_string(c) + " of VTK cell type " +
            std::to_string(type) + " has " + std::to_string(size) + " points, " +
            (fixed > 0 ? "not " + std::to_string(fixed) : "fewer than " + std::to_string(least)));
      }
    }
  }
  const auto check_arrays = [&fail](vtkFieldData* fields, vtkIdType count, const char* what) {
    for (int i = 0; fields && i < fields->GetNumberOfArrays(); ++i)
    {
      vtkAbstractArray* array = fields->GetAbstractArray(i);
      if (array && array->GetNumberOfTuples() != count)
        throw fail(ErrorCode::SizeMismatch,
          std::string("the ") + what + "-data array '" +
            (array->GetName() ? array->GetName() : "(unnamed)") + "' has " +
            std::to_string(array->GetNumberOfTuples()) + " tuples for " + std::to_string(count) +
            " " + what + "s");
    }
  };
  check_arrays(data->GetPointData(), np, "point");
  // cell arrays that do not fit are dropped (BaryLab reads no cell data), not refused
  vtkCellData* cells = data->GetCellData();
  for (int i = cells->GetNumberOfArrays() - 1; i >= 0; --i)
    if (cells->GetAbstractArray(i)->GetNumberOfTuples() != data->GetNumberOfCells())
      cells->RemoveArray(i);
}

vtkSmartPointer<vtkAlgorithm> make_reader(const std::string& ext, const std::string& path)
{
  if (vtkBaryMarkupsReader::IsMarkupsFile(path.c_str())) // 3D Slicer's .mrk.json, .fcsv
  {
    auto r = vtkSmartPointer<vtkBaryMarkupsReader>::New();
    r->SetFileName(path.c_str());
    r->SetFormat(ext == ".fcsv" ? vtkBaryMarkupsReader::FCSV : vtkBaryMarkupsReader::MarkupsJSON);
    return r;
  }
  if (ext == ".vtp")
  {
    auto r = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    r->SetFileName(path.c_str());
    return r;
  }
  if (ext == ".vtu")
  {
    auto r = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
    r->SetFileName(path.c_str());
    return r;
  }
  if (ext == ".pvtp") // VTK's parallel XML: all the pieces, as one data set
  {
    auto r = vtkSmartPointer<vtkXMLPPolyDataReader>::New();
    r->SetFileName(path.c_str());
    return r;
  }
  if (ext == ".pvtu")
  {
    auto r = vtkSmartPointer<vtkXMLPUnstructuredGridReader>::New();
    r->SetFileName(path.c_str());
    return r;
  }
  if (ext == ".vtk")
    return nullptr; // vtkbary::ReadLegacyVTK, not an algorithm
  if (ext == ".obj")
  {
    auto r = vtkSmartPointer<vtkBaryOBJReader>::New();
    r->SetFileName(path.c_str());
    return r;
  }
  if (ext == ".stl")
  {
    auto r = vtkSmartPointer<vtkSTLReader>::New();
    r->SetFileName(path.c_str());
    return r;
  }
  if (ext == ".ply")
  {
    auto r = vtkSmartPointer<vtkBaryPLYReader>::New();
    r->SetFileName(path.c_str());
    return r;
  }
  if (ext == ".off")
  {
    auto r = vtkSmartPointer<vtkBaryOFFReader>::New();
    r->SetFileName(path.c_str());
    return r;
  }
  if (ext == ".mesh")
  {
    auto r = vtkSmartPointer<vtkBaryMEDITReader>::New();
    r->SetFileName(path.c_str());
    return r;
  }
  if (ext == ".tgf")
  {
    auto r = vtkSmartPointer<vtkBaryTGFReader>::New();
    r->SetFileName(path.c_str());
    return r;
  }
  return nullptr;
}

/// @p data as read from @p path, once it is safe to use (validate_read) and has points.
vtkSmartPointer<vtkDataSet> checked(vtkSmartPointer<vtkDataSet> data, const std::string& path,
  const std::string& ext)
{
  if (data->GetNumberOfPoints() == 0)
    throw Error(ErrorCode::EmptyInput,
      "'" + path + "' contains no points (empty or not a valid " + ext + " file)");
  validate_read(data, path);
  return data;
}

const char* const kReadable =
  ".vtp, .vtu, .pvtp, .pvtu, .vtk, .obj, .stl, .ply, .off, .mesh, .tgf, .mrk.json, .fcsv";
} // namespace

std::string vtkBaryDataIO::Extension(const std::string& path)
{
  const auto slash = path.find_last_of("/\\");
  const auto dot = path.rfind('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
    return "";
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

bool vtkBaryDataIO::CanRead(const std::string& path)
{
  return Extension(path) == ".vtk" || make_reader(Extension(path), path) != nullptr;
}

bool vtkBaryDataIO::CanWrite(const std::string& path)
{
  const std::string ext = Extension(path);
  return ext == ".vtp" || ext == ".vtu" || ext == ".vtk" || ext == ".obj" || ext == ".stl" ||
    ext == ".ply" || ext == ".off" || vtkBaryMarkupsReader::IsMarkupsFile(path.c_str());
}

vtkSmartPointer<vtkDataSet> vtkBaryDataIO::Read(const std::string& path)
{
  const std::string ext = Extension(path);
  vtkSmartPointer<vtkAlgorithm> reader = make_reader(ext, path);
  if (!reader && ext != ".vtk")
    throw Error(ErrorCode::Io,
      "cannot read '" + path + "': unknown file extension '" + ext + "' (readable: " +
        kReadable + ")");
  struct stat st;
  if (stat(path.c_str(), &st) != 0)
    throw Error(ErrorCode::Io, "cannot read '" + path + "': no such file");
  if (!S_ISREG(st.st_mode))
    throw Error(ErrorCode::Io, "cannot read '" + path + "': not a regular file");
  {
    std::ifstream probe(path);
    if (!probe)
      throw Error(ErrorCode::Io, "cannot read '" + path + "': permission denied");
    if (st.st_size == 0)
      throw Error(ErrorCode::Io, "cannot read '" + path + "': the file is empty");
  }
  if (ext == ".vtk")
  {
    // BaryLab's own legacy reader (vtkBaryLegacyVTK.h): VTK's trusted the file and crashed
    vtkSmartPointer<vtkDataSet> legacy;
    try
    {
      legacy = vtkbary::ReadLegacyVTK(path);
    }
    catch (const std::bad_alloc&)
    {
      throw Error(ErrorCode::Io,
        "cannot read '" + path + "': it announces more data than this machine's memory holds");
    }
    return checked(legacy, path, ext);
  }
  // sizes a VTK reader would allocate for must fit in the file (vtkBaryFormatCheck.h)
  if (ext == ".stl")
    vtkbary::CheckSTLCount(path, static_cast<std::uintmax_t>(st.st_size));
  if (ext == ".vtp" || ext == ".vtu")
  {
    vtkbary::CheckXMLCounts(path, static_cast<std::uintmax_t>(st.st_size));
    vtkbary::CheckXMLCompression(path, static_cast<std::uintmax_t>(st.st_size));
  }
  vtkNew<vtkBaryErrorObserver> collector;
  collector->Observe(reader);
  std::string vtkMessage;
  {
    ScopedCapture capture;
    try
    {
      reader->Update();
    }
    catch (const std::bad_alloc&)
    {
      collector->Release();
      throw Error(ErrorCode::Io,
        "cannot read '" + path + "': it announces more data than this machine's memory holds");
    }
    catch (const std::exception& e)
    {
      collector->Release();
      throw Error(ErrorCode::Io, "cannot read '" + path + "': " + e.what());
    }
    vtkMessage = capture->First();
  }
  collector->Release();
  vtkDataSet* data = vtkDataSet::SafeDownCast(reader->GetOutputDataObject(0));
  if (!collector->HasError() && !vtkMessage.empty())
    throw Error(ErrorCode::Io, "cannot read '" + path + "': " + vtkMessage);
  if (collector->HasError())
  {
    // readers that name the file themselves ("'x.off' line 3: ...") need no second prefix
    const std::string& message = collector->GetFirstError();
    const std::string quoted = "'" + path + "' ";
    throw Error(reader->GetErrorCode() == vtkbary::NonFiniteErrorCode ? ErrorCode::NonFinite
                                                                      : ErrorCode::Io,
      message.compare(0, quoted.size(), quoted) == 0 ? "cannot read " + message
                                                     : "cannot read '" + path + "': " + message);
  }
  if (!data)
    throw Error(ErrorCode::Io, "cannot read '" + path + "': the reader produced no data set");
  vtkSmartPointer<vtkDataSet> result;
  result.TakeReference(data->NewInstance());
  result->ShallowCopy(data);
  return checked(result, path, ext);
}

vtkSmartPointer<vtkPolyData> vtkBaryDataIO::ReadPolyData(const std::string& path)
{
  vtkSmartPointer<vtkDataSet> data = Read(path);
  vtkSmartPointer<vtkPolyData> poly = vtkPolyData::SafeDownCast(data);
  if (!poly)
    throw Error(ErrorCode::Io,
      "'" + path + "' holds a " + data->GetClassName() +
        " but a polygon/triangle surface (vtkPolyData) is needed here");
  return poly;
}

void vtkBaryDataIO::CheckWritable(vtkDataSet* data, const std::string& path)
{
  if (!data)
    throw Error(ErrorCode::Io, "nothing to write to '" + path + "'");
  const std::string ext = Extension(path);
  if (!CanWrite(path))
    throw Error(ErrorCode::Io,
      "cannot write '" + path + "': unknown file extension '" + ext +
        "' (writable: .vtp, .vtu, .vtk, .obj, .stl, .ply, .off, .mrk.json, .fcsv)");
  const bool surface_only = !vtkBaryMarkupsReader::IsMarkupsFile(path.c_str()) &&
    (ext == ".vtp" || ext == ".obj" || ext == ".stl" || ext == ".ply" || ext == ".off");
  if (surface_only && !vtkPolyData::SafeDownCast(data))
    throw Error(ErrorCode::Io,
      "cannot write a " + std::string(data->GetClassName()) + " to '" + path + "': " + ext +
        " holds surfaces only; use .vtu or .vtk");
}

void vtkBaryDataIO::Write(vtkDataSet* data, const std::string& path)
{
  CheckWritable(data, path);
  const std::string ext = Extension(path);
  vtkSmartPointer<vtkAlgorithm> writer;
  // Temporary file beside the target (same file system, so rename is atomic); same extension,
  // since some writers look at it.
  vtkSmartPointer<vtkDataSet> converted;
  std::random_device rd;
  const std::string tmp = path + ".tmp" + std::to_string(rd() % 1000000) + ext;
  if (vtkBaryMarkupsReader::IsMarkupsFile(path.c_str())) // any data set's points
  {
    auto w = vtkSmartPointer<vtkBaryMarkupsWriter>::New();
    w->SetFileName(tmp.c_str());
    w->SetFormat(ext == ".fcsv" ? vtkBaryMarkupsWriter::FCSV : vtkBaryMarkupsWriter::MarkupsJSON);
    writer = w;
  }
  else if (ext == ".vtp")
  {
    auto w = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
    w->SetFileName(tmp.c_str());
    w->SetDataModeToAppended();
    w->EncodeAppendedDataOff(); // raw bytes, LZ4: ~30x faster than base64 zlib, files no larger
    w->SetCompressorTypeToLZ4();
    writer = w;
  }
  else if (ext == ".vtu")
  {
    if (!vtkUnstructuredGrid::SafeDownCast(data))
    { // any data set converts losslessly (points, cells, arrays) to an unstructured grid
      vtkNew<vtkAppendFilter> convert;
      convert->AddInputData(data);
      convert->Update();
      converted = convert->GetOutput();
      data = converted;
    }
    auto w = vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New();
    w->SetFileName(tmp.c_str());
    w->SetDataModeToAppended();
    w->EncodeAppendedDataOff(); // raw bytes, LZ4: ~30x faster than base64 zlib, files no larger
    w->SetCompressorTypeToLZ4();
    writer = w;
  }
  else if (ext == ".vtk")
  {
    auto w = vtkSmartPointer<vtkDataSetWriter>::New();
    w->SetFileName(tmp.c_str());
    w->SetFileTypeToBinary();
    writer = w;
  }
  else if (ext == ".obj")
  {
    auto w = vtkSmartPointer<vtkOBJWriter>::New();
    w->SetFileName(tmp.c_str());
    writer = w;
  }
  else if (ext == ".stl")
  {
    auto w = vtkSmartPointer<vtkSTLWriter>::New();
    w->SetFileName(tmp.c_str());
    writer = w;
  }
  else if (ext == ".ply")
  {
    auto w = vtkSmartPointer<vtkPLYWriter>::New();
    w->SetFileName(tmp.c_str());
    writer = w;
  }
  else if (ext == ".off")
  {
    auto w = vtkSmartPointer<vtkBaryOFFWriter>::New();
    w->SetFileName(tmp.c_str());
    writer = w;
  }
  else
    throw Error(ErrorCode::Internal, "vtkBaryDataIO::Write: no writer for '" + ext + "'");

  vtkNew<vtkBaryErrorObserver> collector;
  collector->Observe(writer);
  writer->SetInputDataObject(0, data);
  int ok = 0;
  unsigned long code = 0;
  if (auto* w = vtkWriter::SafeDownCast(writer))
  {
    ok = w->Write();
    code = w->GetErrorCode();
  }
  else if (auto* x = vtkXMLWriter::SafeDownCast(writer))
  {
    ok = x->Write();
    code = x->GetErrorCode();
  }
  collector->Release();
  if (!ok || collector->HasError() || code != 0)
  {
    std::remove(tmp.c_str());
    throw Error(ErrorCode::Io,
      "cannot write '" + path + "'" +
        (collector->HasError() ? ": " + collector->GetFirstError()
                               : std::string(" (is the folder writable?)")));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
  {
    std::remove(tmp.c_str());
    throw Error(ErrorCode::Io, "cannot write '" + path + "': renaming the temporary file failed");
  }
}

Eigen::MatrixXd vtkBaryDataIO::ReadDMAT(const std::string& path)
{
  struct stat st;
  std::ifstream in(path);
  if (!in || stat(path.c_str(), &st) != 0)
    throw Error(ErrorCode::Io, "cannot read '" + path + "': no such file or not readable");
  if (!S_ISREG(st.st_mode))
    throw Error(ErrorCode::Io, "cannot read '" + path + "': not a regular file");
  std::string token;
  auto next_number = [&](double& x) {
    return (in >> token) && vtkbary::ParseDouble(token, x) == vtkbary::Parsed::Ok;
  };
  double cols = -1, rows = -1;
  if (!next_number(cols) || !next_number(rows) || !(cols >= 0) || !(rows >= 0) ||
    cols != std::floor(cols) || rows != std::floor(rows))
    throw Error(ErrorCode::Io,
      "cannot read '" + path + "': a .dmat file starts with 'columns rows' (ASCII)");
  // each value takes at least two bytes ("0\n"): a header that promises more than the file can
  // hold is refused before anything is allocated for it
  // (each count on its own too: 0 columns by 6e29 rows holds no value but is no matrix size)
  const double most = static_cast<double>(st.st_size) / 2.0;
  if (cols * rows > most || cols > 2147483647.0 || rows > 2147483647.0)
    throw Error(ErrorCode::Io,
      "cannot read '" + path + "': its header announces " + vtkBaryConversion::CountText(cols) + " columns by " +
        vtkBaryConversion::CountText(rows) + " rows, more values than a file of " + std::to_string(st.st_size) +
        " bytes holds");
  // a matrix without values (0 rows, or 0 columns) is read without looping over the other
  // count, which may be anything (0 by 10^15 took forever)
  Eigen::MatrixXd M(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  for (Eigen::Index c = 0; M.size() > 0 && c < M.cols(); ++c) // column-major
    for (Eigen::Index r = 0; r < M.rows(); ++r)
    {
      double x;
      if (!next_number(x))
        throw Error(ErrorCode::Io,
          "cannot read '" + path + "': value " + std::to_string(c * M.rows() + r + 1) + " of " +
            std::to_string(M.size()) + " is missing or not a number");
      if (!std::isfinite(x))
        throw Error(ErrorCode::NonFinite,
          "'" + path + "': value " + std::to_string(c * M.rows() + r + 1) + " is not finite");
      M(r, c) = x;
    }
  if (in >> token)
    throw Error(ErrorCode::Io,
      "cannot read '" + path + "': more values than its header's " + std::to_string(M.cols()) +
        " columns by " + std::to_string(M.rows()) + " rows");
  return M;
}

std::vector<double> vtkBaryDataIO::ReadNumbers(const std::string& path)
{
  if (Extension(path) == ".dmat")
  {
    const Eigen::MatrixXd M = ReadDMAT(path);
    return std::vector<double>(M.data(), M.data() + M.size());
  }
  std::ifstream in(path);
  if (!in)
    throw Error(ErrorCode::Io, "cannot read '" + path + "': no such file or not readable");
  std::vector<double> values;
  std::string line;
  std::istringstream fields;
  for (long number = 1; std::getline(in, line); ++number)
  {
    fields.clear();
    fields.str(line.substr(0, line.find('#')));
    std::string token;
    while (fields >> token)
    {
      double v = 0.0;
      if (vtkbary::ParseDouble(token, v) != vtkbary::Parsed::Ok)
        throw Error(ErrorCode::Io,
          "cannot read '" + path + "' line " + std::to_string(number) + ": '" +
            vtkbary::Printable(token) + "' is not a number double precision holds");
      if (!std::isfinite(v))
        throw Error(ErrorCode::NonFinite,
          "'" + path + "' line " + std::to_string(number) + " holds NaN or infinity");
      values.push_back(v);
    }
  }
  return values;
}

Eigen::MatrixXi vtkBaryDataIO::ReadPseudoEdges(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw Error(ErrorCode::Io, "cannot read '" + path + "': no such file or not readable");
  std::vector<std::array<int, 2>> edges;
  std::string line;
  std::istringstream fields;
  for (long number = 1; std::getline(in, line); ++number)
  {
    fields.clear();
    fields.str(line.substr(0, line.find('#')));
    std::vector<std::string> tokens;
    for (std::string token; fields >> token;)
      tokens.push_back(token);
    if (tokens.empty())
      continue;
    long long ab[2] = { -1, -1 };
    if (tokens.size() != 2 || !vtkbary::ParseInteger(tokens[0], ab[0]) ||
      !vtkbary::ParseInteger(tokens[1], ab[1]) || ab[0] < 0 || ab[1] < 0 || ab[0] > INT_MAX ||
      ab[1] > INT_MAX)
      throw Error(ErrorCode::Io,
        "cannot read '" + path + "' line " + std::to_string(number) +
          ": a pseudo-edge line holds two point-handle indices (whole numbers from 0)");
    edges.push_back({ static_cast<int>(ab[0]), static_cast<int>(ab[1]) });
  }
  Eigen::MatrixXi E(static_cast<Eigen::Index>(edges.size()), 2);
  for (std::size_t e = 0; e < edges.size(); ++e)
    E.row(static_cast<Eigen::Index>(e)) << edges[e][0], edges[e][1];
  return E;
}

Eigen::MatrixXd vtkBaryDataIO::ReadMatrix(const std::string& path, Eigen::Index columns)
{
  Eigen::MatrixXd M;
  if (Extension(path) == ".dmat")
    M = ReadDMAT(path);
  else
  {
    std::ifstream in(path);
    if (!in)
      throw Error(ErrorCode::Io, "cannot read '" + path + "': no such file or not readable");
    std::vector<double> values;
    Eigen::Index width = -1, rows = 0;
    long width_line = 0;
    std::string line;
    std::istringstream fields;
    for (long number = 1; std::getline(in, line); ++number)
    {
      fields.clear();
      fields.str(line.substr(0, line.find('#')));
      std::string token;
      Eigen::Index count = 0;
      while (fields >> token)
      {
        double v = 0.0;
        if (vtkbary::ParseDouble(token, v) != vtkbary::Parsed::Ok)
          throw Error(ErrorCode::Io, "cannot read '" + path + "' line " + std::to_string(number) +
              ": '" + vtkbary::Printable(token) + "' is not a number double precision holds");
        if (!std::isfinite(v))
          throw Error(ErrorCode::NonFinite,
            "'" + path + "' line " + std::to_string(number) + " holds NaN or infinity");
        values.push_back(v);
        ++count;
      }
      if (count == 0)
        continue;
      if (width < 0)
      {
        width = count;
        width_line = number;
      }
      else if (count != width)
        throw Error(ErrorCode::Io, "cannot read '" + path + "' line " + std::to_string(number) +
            ": it holds " + std::to_string(count) + " numbers but line " +
            std::to_string(width_line) + " holds " + std::to_string(width) +
            " (every row of a matrix has the same length)");
      ++rows;
    }
    if (rows == 0)
      throw Error(ErrorCode::EmptyInput, "'" + path + "' holds no numbers");
    M = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      values.data(), rows, width);
  }
  if (M.size() == 0)
    throw Error(ErrorCode::EmptyInput, "'" + path + "' holds no numbers");
  if (columns > 0 && M.cols() != columns)
    throw Error(ErrorCode::SizeMismatch, "'" + path + "' has " + std::to_string(M.cols()) +
        " numbers a row; " + std::to_string(columns) + " expected");
  return M;
}

namespace
{

/// Writes text through @p write to a temporary file beside @p path and renames it: a failed
/// write leaves no partial file.
template<class Write>
void write_text_atomically(const std::string& path, Write&& write)
{
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out)
      throw Error(ErrorCode::Io, "cannot write '" + path + "' (is the folder writable?)");
    write(out);
    if (!out)
    {
      out.close();
      std::remove(tmp.c_str());
      throw Error(ErrorCode::Io, "cannot write '" + path + "' (disk full?)");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
  {
    std::remove(tmp.c_str());
    throw Error(ErrorCode::Io, "cannot write '" + path + "'");
  }
}

/// The shortest decimal that reads back as @p x.
void write_number(std::ostream& out, double x)
{
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), x);
  (void)ec;
  out.write(buffer, end - buffer);
}

} // namespace

void vtkBaryDataIO::WriteMatrix(const Eigen::MatrixXd& M, const std::string& path)
{
  write_text_atomically(path, [&](std::ostream& out) {
    for (Eigen::Index r = 0; r < M.rows(); ++r)
    {
      for (Eigen::Index c = 0; c < M.cols(); ++c)
      {
        if (c > 0)
          out.put(' ');
        write_number(out, M(r, c));
      }
      out.put('\n');
    }
  });
}

void vtkBaryDataIO::WriteDMAT(const Eigen::MatrixXd& M, const std::string& path)
{
  write_text_atomically(path, [&](std::ostream& out) {
    out << M.cols() << ' ' << M.rows() << '\n';
    for (Eigen::Index c = 0; c < M.cols(); ++c)
      for (Eigen::Index r = 0; r < M.rows(); ++r)
      {
        write_number(out, M(r, c));
        out.put('\n');
      }
  });
}


std::vector<Eigen::MatrixXd> vtkBaryDataIO::ReadPose(
  const std::string& path, Eigen::Index handles, const bary::Skeleton* skeleton)
{
  std::vector<Eigen::MatrixXd> pose;
  const auto count_mismatch = [&](Eigen::Index got, const std::string& what) {
    return Error(ErrorCode::SizeMismatch,
      "'" + path + "' holds " + std::to_string(got) + " " + what + " but the weights have " +
        std::to_string(handles) + " handles: a pose needs one transform per handle, in weights "
        "order (point handles, then bones)");
  };
  if (Extension(path) == ".dmat")
  {
    const Eigen::MatrixXd M = ReadDMAT(path);
    const Eigen::Index bones = skeleton ? skeleton->BE.rows() : -1;
    const bool column = M.cols() == 1 && M.rows() % 4 == 0 && M.rows() > 0;
    const bool rows4 = M.cols() == 4 && M.rows() > 0;
    if (column || rows4)
    {
      // libigl's per-bone rotations (x y z w), relative to the parent bone.
      const Eigen::Index nq = column ? M.rows() / 4 : M.rows();
      if (!skeleton)
        throw Error(ErrorCode::InvalidArgument,
          "'" + path + "' holds " + std::to_string(nq) + " quaternions (per-bone rotations); "
          "posing them needs the skeleton (the handles file)");
      if (nq != bones)
        throw Error(ErrorCode::SizeMismatch,
          "'" + path + "' holds " + std::to_string(nq) + " quaternions but the skeleton has " +
            std::to_string(bones) + " bones (one rotation per bone, in bone order)");
      std::vector<Eigen::Quaterniond> rotations;
      for (Eigen::Index b = 0; b < nq; ++b)
      {
        const auto q = [&](int k) { return column ? M(4 * b + k, 0) : M(b, k); };
        rotations.emplace_back(q(3), q(0), q(1), q(2));
      }
      const std::vector<Eigen::MatrixXd> bone_transforms = bary::forward_kinematics(*skeleton, rotations);
      Eigen::MatrixXd identity = Eigen::MatrixXd::Zero(3, 4);
      identity.leftCols(3).setIdentity();
      pose.assign(static_cast<std::size_t>(skeleton->P.size()), identity);
      pose.insert(pose.end(), bone_transforms.begin(), bone_transforms.end());
      return pose;
    }
    // libigl's stacked transforms: (dim + 1) m rows by dim columns.
    const Eigen::Index dim = M.cols();
    if ((dim != 2 && dim != 3) || M.rows() % (dim + 1) != 0)
      throw Error(ErrorCode::Io,
        "'" + path + "' is a " + std::to_string(M.rows()) + " by " + std::to_string(M.cols()) +
          " matrix: a .dmat pose holds per-bone quaternions (4 #B numbers) or libigl's stacked "
          "transforms ((dim+1) #handles rows by dim columns)");
    if (M.rows() / (dim + 1) != handles)
      throw count_mismatch(M.rows() / (dim + 1), "transforms");
    for (Eigen::Index j = 0; j < handles; ++j)
      pose.push_back(bary::lift_transform(M.block((dim + 1) * j, 0, dim + 1, dim).transpose()));
    return pose;
  }

  std::ifstream in(path);
  if (!in)
    throw Error(ErrorCode::Io, "cannot read '" + path + "': no such file or not readable");
  std::string line;
  int line_number = 0;
  while (std::getline(in, line))
  {
    ++line_number;
    const auto hash = line.find('#');
    if (hash != std::string::npos)
      line.erase(hash);
    std::vector<double> values;
    std::size_t i = 0;
    while (i < line.size())
    {
      while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i])))
        ++i;
      if (i == line.size())
        break;
      std::size_t j = i;
      while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j])))
        ++j;
      double x = 0;
      if (vtkbary::ParseDouble(std::string_view(line).substr(i, j - i), x) != vtkbary::Parsed::Ok)
        throw Error(ErrorCode::Io,
          "cannot read '" + path + "' line " + std::to_string(line_number) + ": '" +
            vtkbary::Printable(std::string_view(line).substr(i, j - i)) +
            "' is not a number double precision holds");
      if (!std::isfinite(x))
        throw Error(ErrorCode::NonFinite,
          "'" + path + "' line " + std::to_string(line_number) + " holds NaN or infinity");
      values.push_back(x);
      i = j;
    }
    if (values.empty())
      continue;
    Eigen::MatrixXd T;
    switch (values.size())
    {
      case 12:
        T = Eigen::Map<const Eigen::Matrix<double, 3, 4, Eigen::RowMajor>>(values.data());
        break;
      case 6:
        T = Eigen::Map<const Eigen::Matrix<double, 2, 3, Eigen::RowMajor>>(values.data());
        break;
      case 3:
      case 2:
        T = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(values.size()),
          static_cast<Eigen::Index>(values.size()) + 1);
        T.leftCols(static_cast<Eigen::Index>(values.size())).setIdentity();
        for (std::size_t k = 0; k < values.size(); ++k)
          T(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(values.size())) = values[k];
        break;
      default:
        throw Error(ErrorCode::Io,
          "cannot read '" + path + "' line " + std::to_string(line_number) + ": " +
            std::to_string(values.size()) + " numbers; a pose line holds 12 (3D [A | t] "
            "row-major), 6 (2D), 3 or 2 (a translation)");
    }
    pose.push_back(bary::lift_transform(T));
  }
  if (static_cast<Eigen::Index>(pose.size()) != handles)
    throw count_mismatch(static_cast<Eigen::Index>(pose.size()), "transforms");
  return pose;
}
