/**
 * @class   vtkBaryFileReader
 * @brief   Reads any file vtkBaryDataIO reads, as a pipeline source that reports errors.
 *
 * The format follows the extension (.vtp, .vtu, .vtk, .obj, .stl, .ply, .off, MEDIT .mesh,
 * libigl .tgf, 3D Slicer markups .mrk.json / .fcsv: vtkBaryDataIO), and the file is validated as vtkBaryDataIO::Read validates it
 * (counts, finite coordinates, well-formed cells). The output is the data set of the type the
 * file holds (vtkPolyData, vtkUnstructuredGrid, ...). A file that cannot be read fails the
 * request with vtkErrorMacro naming the file and the problem, and the error code of the
 * bary::Error (vtkBaryConversion::ToVTKErrorCode); the output is then empty.
 *
 * vtkBaryDataIO's static functions throw bary::Error, which cannot cross VTK's Python
 * wrapping; this source (and vtkBaryFileWriter) is how wrapped code reads and writes.
 *
 * @sa vtkBaryDataIO vtkBaryFileWriter
 */
#ifndef vtkBaryFileReader_h
#define vtkBaryFileReader_h

#include "BaryLabIOModule.h" // for export macro
#include "vtkDataObjectAlgorithm.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <string> // for std::string

class vtkDataSet;

class BARYLABIO_EXPORT vtkBaryFileReader : public vtkDataObjectAlgorithm
{
public:
  static vtkBaryFileReader* New();
  vtkTypeMacro(vtkBaryFileReader, vtkDataObjectAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to read. Default "".
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

  /// True if the extension of @p path is one vtkBaryDataIO reads.
  static bool CanReadFile(const char* path);

protected:
  vtkBaryFileReader();
  ~vtkBaryFileReader() override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;
  /// What RequestDataObject read, handed to the output by RequestData.
  vtkSmartPointer<vtkDataSet> Data;

private:
  vtkBaryFileReader(const vtkBaryFileReader&) = delete;
  void operator=(const vtkBaryFileReader&) = delete;
};

#endif
