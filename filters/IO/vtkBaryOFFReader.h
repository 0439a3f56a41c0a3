/**
 * @class   vtkBaryOFFReader
 * @brief   Reads Object File Format (.off) polygon meshes into vtkPolyData.
 *
 * Supports the common geometry-processing dialect: an optional `OFF` header (also `COFF`,
 * `NOFF`, `CNOFF` — per-vertex colours/normals after the coordinates are skipped), `#`
 * comments, a counts line `nv nf [ne]`, nv vertex lines, nf face lines `k i0 ... ik-1`
 * (0-based; trailing face colours are ignored). Faces with 2 indices become lines. Errors
 * (missing file, bad header, truncated data, out-of-range index, NaN) are reported with
 * vtkErrorMacro and the line number, and leave the output empty.
 *
 * @sa vtkBaryOFFWriter vtkBaryDataIO
 */
#ifndef vtkBaryOFFReader_h
#define vtkBaryOFFReader_h

#include "BaryLabIOModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string

class BARYLABIO_EXPORT vtkBaryOFFReader : public vtkPolyDataAlgorithm
{
public:
  static vtkBaryOFFReader* New();
  vtkTypeMacro(vtkBaryOFFReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to read.
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

protected:
  vtkBaryOFFReader();
  ~vtkBaryOFFReader() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;

private:
  vtkBaryOFFReader(const vtkBaryOFFReader&) = delete;
  void operator=(const vtkBaryOFFReader&) = delete;
};

#endif
