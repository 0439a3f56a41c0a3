/**
 * @class   vtkBaryTGFReader
 * @brief   Reads libigl's .tgf skeletons (handles for bounded biharmonic weights).
 *
 * Format: vertex lines `index x y z` (1-based index, ignored beyond ordering), a line `#`, then
 * edge lines `a b [...]` (1-based vertex indices; extra columns ignored), optionally a second `#`
 * and ignored lines. As in libigl, every edge is a bone handle and a vertex on no edge is a point
 * handle.
 *
 * Output: vtkPolyData with the vertices as points, one line cell per bone (file order) and one
 * vertex cell per point handle (file order) — the handle layout vtkBary filters and `barylab`
 * accept from .vtp files too.
 */
#ifndef vtkBaryTGFReader_h
#define vtkBaryTGFReader_h

#include "BaryLabIOModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string

class BARYLABIO_EXPORT vtkBaryTGFReader : public vtkPolyDataAlgorithm
{
public:
  static vtkBaryTGFReader* New();
  vtkTypeMacro(vtkBaryTGFReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to read.
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

protected:
  vtkBaryTGFReader();
  ~vtkBaryTGFReader() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;

private:
  vtkBaryTGFReader(const vtkBaryTGFReader&) = delete;
  void operator=(const vtkBaryTGFReader&) = delete;
};

#endif
