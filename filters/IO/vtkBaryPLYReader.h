/**
 * @class   vtkBaryPLYReader
 * @brief   Reads PLY polygon files (ASCII and binary, either byte order) into vtkPolyData.
 *
 * VTK's vtkPLYReader (Greg Turk's PLY library) trusts the header: a mistyped property line
 * corrupted its heap (found by BaryLab's fuzzer). This reader checks the header completely and
 * every count against the bytes left before it reads:
 *
 * - header: `ply`, `format ascii|binary_little_endian|binary_big_endian 1.0`, `comment` and
 *   `obj_info` lines, `element NAME COUNT`, `property TYPE NAME`, `property list COUNTTYPE
 *   ITEMTYPE NAME`, `end_header`; types char, uchar, short, ushort, int, uint, float, double
 *   and their sized names (int8 ... float64);
 * - `vertex` elements give the points (properties x, y, z required, read as doubles), `face`
 *   elements the polygons (list `vertex_indices` or `vertex_index`), `edge` elements lines
 *   (`vertex1`, `vertex2`); other elements and properties (normals, colours, texture
 *   coordinates) are read past and dropped.
 *
 * Errors are reported with vtkErrorMacro as "'FILE' line N: ..." (header lines) or
 * "'FILE': element ...", and leave the output empty.
 *
 * @sa vtkBaryDataIO
 */
#ifndef vtkBaryPLYReader_h
#define vtkBaryPLYReader_h

#include "BaryLabIOModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string

class BARYLABIO_EXPORT vtkBaryPLYReader : public vtkPolyDataAlgorithm
{
public:
  static vtkBaryPLYReader* New();
  vtkTypeMacro(vtkBaryPLYReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to read.
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

protected:
  vtkBaryPLYReader();
  ~vtkBaryPLYReader() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;

private:
  vtkBaryPLYReader(const vtkBaryPLYReader&) = delete;
  void operator=(const vtkBaryPLYReader&) = delete;
};

#endif
