#ifndef __VTK_WRAP__
#include <Eigen/Core> // for Eigen::MatrixXd
#endif

/**
 * @class   vtkBaryDataIO
 * @brief   Reads and writes data sets by file extension, with errors as exceptions.
 *
 * Formats: .vtp, .vtu, .vtk (legacy), .obj, .stl, .ply (VTK's readers/writers), .off
 * (vtkBaryOFFReader/Writer), and for reading MEDIT .mesh (vtkBaryMEDITReader) and libigl .tgf
 * skeletons (vtkBaryTGFReader). Read() throws bary::Error(Io) naming the file and the problem
 * (missing, unreadable, unknown extension, parse error reported by the reader, no points).
 * Write() writes to a temporary file beside the target and renames it only on success, so a
 * failed write never leaves a partial file behind.
 *
 * Writing a non-unstructured data set to .vtu converts it (vtkAppendFilter).
 * .obj, .stl, .ply and .off keep only geometry; .vtp/.vtu/.vtk keep named point-data arrays
 * (such as the "Weights" array).
 */
#ifndef vtkBaryDataIO_h
#define vtkBaryDataIO_h

#include "BaryLabIOModule.h" // for export macro
#include "vtkObject.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <string> // for std::string

class vtkDataSet;
class vtkPolyData;

class BARYLABIO_EXPORT vtkBaryDataIO : public vtkObject
{
public:
  static vtkBaryDataIO* New();
  vtkTypeMacro(vtkBaryDataIO, vtkObject);

  /// Reads @p path. @throws bary::Error(Io | EmptyInput | NonFinite)
  static vtkSmartPointer<vtkDataSet> Read(const std::string& path);
  /// Reads @p path and requires a vtkPolyData (cages).  @throws bary::Error
  static vtkSmartPointer<vtkPolyData> ReadPolyData(const std::string& path);
  /// Writes @p data to @p path (format by extension), atomically. @throws bary::Error(Io)
  static void Write(vtkDataSet* data, const std::string& path);
  /// Lower-case extension of @p path including the dot (".vtp"), or "".
  static std::string Extension(const std::string& path);
  /// True if Read() understands the extension of @p path.
  static bool CanRead(const std::string& path);
  /// True if Write() knows the extension of @p path.
  static bool CanWrite(const std::string& path);

#ifndef __VTK_WRAP__
  /// libigl's ASCII .dmat matrix: header "columns rows", then the values column-major.
  /// @throws bary::Error(Io) naming the file and the missing/bad value, (NonFinite) for NaN/inf.
  static Eigen::MatrixXd ReadDMAT(const std::string& path);
  /// Writes @p M as ASCII .dmat (shortest round-trip decimal representation), atomically.
  static void WriteDMAT(const Eigen::MatrixXd& M, const std::string& path);
#endif

protected:
  vtkBaryDataIO() = default;
  ~vtkBaryDataIO() override = default;

private:
  vtkBaryDataIO(const vtkBaryDataIO&) = delete;
  void operator=(const vtkBaryDataIO&) = delete;
};

#endif
