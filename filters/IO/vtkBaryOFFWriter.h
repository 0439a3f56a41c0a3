/**
 * @class   vtkBaryOFFWriter
 * @brief   Writes the points and polygons of a vtkPolyData as an OFF file.
 *
 * Writes `OFF`, the counts, the points with 17 significant digits (round-trips doubles) and
 * the polygons (0-based). Lines, vertices and strips are not written (strips: triangulate
 * first). Point data are not written: use .vtp to keep the weights.
 *
 * @sa vtkBaryOFFReader vtkBaryDataIO
 */
#ifndef vtkBaryOFFWriter_h
#define vtkBaryOFFWriter_h

#include "BaryLabIOModule.h" // for export macro
#include "vtkWriter.h"

#include <string> // for std::string

class vtkPolyData;

class BARYLABIO_EXPORT vtkBaryOFFWriter : public vtkWriter
{
public:
  static vtkBaryOFFWriter* New();
  vtkTypeMacro(vtkBaryOFFWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to write.
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

protected:
  vtkBaryOFFWriter() = default;
  ~vtkBaryOFFWriter() override = default;
  void WriteData() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;

  std::string FileName;

private:
  vtkBaryOFFWriter(const vtkBaryOFFWriter&) = delete;
  void operator=(const vtkBaryOFFWriter&) = delete;
};

#endif
