/**
 * @class   vtkBaryMarkupsReader
 * @brief   Reads 3D Slicer's markups (.mrk.json and legacy .fcsv) as points in LPS millimetres.
 *
 * Formats (by the file name's ending, or SetFormat):
 * - `.mrk.json`, Slicer's markups JSON (schema markups-schema-v1.0.x): every control point of
 *   every entry of `markups`, in file order (`markups[].controlPoints[].position`). Each entry's
 *   `coordinateSystem` is "LPS" or "RAS" (absent: "LPS", the schema's default) and its
 *   `coordinateUnits` "mm" (absent: "mm"; "um" and others are refused). A control point must
 *   have a `position` of three finite numbers, and a `positionStatus` of "defined" (absent:
 *   "defined"): a "preview" or "undefined" point is refused, naming it, rather than dropped,
 *   because dropping it would shift the order on which control points are matched.
 * - `.fcsv`, Slicer's legacy fiducial CSV: `#` header lines, among them `# CoordinateSystem =`
 *   LPS, RAS, 0 (RAS) or 1 (LPS) (absent: RAS, as Slicer assumed before 4.11) and optionally
 *   `# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID` (any order; that
 *   one when absent); then one point a row, comma-separated, double-quoted fields allowed
 *   ("a, b" and "" inside quotes).
 *
 * Output: vtkPolyData, one point and one vertex cell per control point, in **LPS** (RAS
 * coordinates converted: x and y negated), with the point-data string arrays `Label` (the
 * control points' labels, "" where a point has none), `Id` (their ids, when any point has one)
 * and `Description` (when any point has one) — what vtkBaryMarkupsWriter writes back.
 *
 * Errors (vtkErrorMacro, output empty) name the file and the markup, control point (0-based
 * over the file, with its label) or line: malformed JSON, no `markups`, no control points, a
 * point without a position or not defined, an unknown coordinate system, a row without three
 * numeric coordinates. A non-finite coordinate sets the error code
 * vtkbary::NonFiniteErrorCode (vtkBaryDataIO reports bary::ErrorCode::NonFinite).
 *
 * @sa vtkBaryMarkupsWriter vtkBaryDataIO
 */
#ifndef vtkBaryMarkupsReader_h
#define vtkBaryMarkupsReader_h

#include "BaryLabIOModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string

class BARYLABIO_EXPORT vtkBaryMarkupsReader : public vtkPolyDataAlgorithm
{
public:
  static vtkBaryMarkupsReader* New();
  vtkTypeMacro(vtkBaryMarkupsReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The file formats.
  enum Formats
  {
    FromFileName = 0, ///< .fcsv: legacy fiducial CSV; anything else: markups JSON
    MarkupsJSON = 1,
    FCSV = 2,
  };

  ///@{
  /// The file to read.
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

  ///@{
  /// The format (default FromFileName).
  vtkSetClampMacro(Format, int, FromFileName, FCSV);
  vtkGetMacro(Format, int);
  ///@}

  /// True if @p path ends in .mrk.json or .fcsv (any case).
  static bool IsMarkupsFile(const char* path);

protected:
  vtkBaryMarkupsReader();
  ~vtkBaryMarkupsReader() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;
  int Format = FromFileName;

private:
  vtkBaryMarkupsReader(const vtkBaryMarkupsReader&) = delete;
  void operator=(const vtkBaryMarkupsReader&) = delete;
};

#endif
