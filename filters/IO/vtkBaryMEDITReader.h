/**
 * @class   vtkBaryMEDITReader
 * @brief   Reads MEDIT .mesh files (as written by TetGen and libigl) into a vtkUnstructuredGrid.
 *
 * Supports the ASCII format: `MeshVersionFormatted`, `Dimension 2|3`, `Vertices` (count, then
 * x y [z] ref per line), `Triangles` (a b c ref), `Tetrahedra` (a b c d ref), `Edges`, `End`;
 * keywords and numbers may share lines; `#` starts a comment. Indices are 1-based.
 *
 * Output: the tetrahedra when the file has any (a volume mesh — its boundary triangles are
 * dropped), otherwise the triangles. Cell data "Reference" holds each cell's reference number.
 * Errors (missing file, unknown keyword, truncated section, index out of range, NaN) are reported
 * with vtkErrorMacro naming the file and the problem.
 *
 * @sa vtkBaryDataIO
 */
#ifndef vtkBaryMEDITReader_h
#define vtkBaryMEDITReader_h

#include "BaryLabIOModule.h" // for export macro
#include "vtkUnstructuredGridAlgorithm.h"

#include <string> // for std::string

class BARYLABIO_EXPORT vtkBaryMEDITReader : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkBaryMEDITReader* New();
  vtkTypeMacro(vtkBaryMEDITReader, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to read.
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

protected:
  vtkBaryMEDITReader();
  ~vtkBaryMEDITReader() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;

private:
  vtkBaryMEDITReader(const vtkBaryMEDITReader&) = delete;
  void operator=(const vtkBaryMEDITReader&) = delete;
};

#endif
