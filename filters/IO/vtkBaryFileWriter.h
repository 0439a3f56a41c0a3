/**
 * @class   vtkBaryFileWriter
 * @brief   Writes a data set to any file vtkBaryDataIO writes, reporting errors.
 *
 * The format follows the extension (.vtp, .vtu, .vtk, .obj, .stl, .ply, .off, 3D Slicer markups
 * .mrk.json / .fcsv; only .vtp, .vtu and .vtk keep point data such as the "Weights" array,
 * markups the points' "Label", "Id" and "Description"). The file is written atomically (a
 * temporary file beside it, renamed on success: vtkBaryDataIO::Write). A failure (unknown
 * extension, a folder that does not exist, a full disk) is reported with vtkErrorMacro naming
 * the file, and Write() returns 0.
 *
 * @sa vtkBaryDataIO vtkBaryFileReader
 */
#ifndef vtkBaryFileWriter_h
#define vtkBaryFileWriter_h

#include "BaryLabIOModule.h" // for export macro
#include "vtkWriter.h"

#include <string> // for std::string

class BARYLABIO_EXPORT vtkBaryFileWriter : public vtkWriter
{
public:
  static vtkBaryFileWriter* New();
  vtkTypeMacro(vtkBaryFileWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to write. Default "".
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

  /// True if the extension of @p path is one vtkBaryDataIO writes.
  static bool CanWriteFile(const char* path);

protected:
  vtkBaryFileWriter() = default;
  ~vtkBaryFileWriter() override = default;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  void WriteData() override;

  std::string FileName;

private:
  vtkBaryFileWriter(const vtkBaryFileWriter&) = delete;
  void operator=(const vtkBaryFileWriter&) = delete;
};

#endif
