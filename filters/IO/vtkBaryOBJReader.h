/**
 * @class   vtkBaryOBJReader
 * @brief   Reads Wavefront .obj geometry into vtkPolyData in full double precision.
 *
 * VTK's vtkOBJReader stores coordinates as float: 1e300 became 3.4e38, 1e999 was never
 * reported, 0.1 lost its last nine digits, and a face index of 4294967301 wrapped round to
 * vertex 5. This reader keeps what BaryLab uses of an .obj file, exactly:
 *
 * - `v x y z [w | r g b]`: a point (double; extra numbers, a weight or a colour, are ignored);
 * - `f a b c ...` (polygons, at least 3 corners), `l a b ...` (polylines, at least 2), `p a ...`
 *   (vertices); each corner `i`, `i/t`, `i//n` or `i/t/n`, 1-based, negative counting back from
 *   the last vertex read so far;
 * - everything else (`vt`, `vn`, `g`, `o`, `s`, `usemtl`, `mtllib`, free-form curves) is
 *   skipped: texture coordinates, normals and groups are not read.
 *
 * Cells come out as vtkPolyData orders them: vertices, lines, polygons. Errors (a missing or
 * malformed number, a number double cannot hold, NaN or infinity, an index naming no vertex, a
 * cell with too few corners) are reported with vtkErrorMacro as "'FILE' line N: ...", and
 * leave the output empty.
 *
 * @sa vtkBaryDataIO vtkBaryOFFReader
 */
#ifndef vtkBaryOBJReader_h
#define vtkBaryOBJReader_h

#include "BaryLabIOModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string

class BARYLABIO_EXPORT vtkBaryOBJReader : public vtkPolyDataAlgorithm
{
public:
  static vtkBaryOBJReader* New();
  vtkTypeMacro(vtkBaryOBJReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to read.
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

protected:
  vtkBaryOBJReader();
  ~vtkBaryOBJReader() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;

private:
  vtkBaryOBJReader(const vtkBaryOBJReader&) = delete;
  void operator=(const vtkBaryOBJReader&) = delete;
};

#endif
