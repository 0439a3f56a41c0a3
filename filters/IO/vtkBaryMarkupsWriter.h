/**
 * @class   vtkBaryMarkupsWriter
 * @brief   Writes the points of a data set as 3D Slicer markups (.mrk.json or legacy .fcsv), LPS.
 *
 * Formats (SetFormat; by default from the file name: `.fcsv` legacy CSV, anything else JSON):
 * - markups JSON as 3D Slicer 5 writes it: `"@schema"` markups-schema-v1.0.3, one markup of
 *   `type` "Fiducial" (a point list), `coordinateSystem` "LPS", `coordinateUnits` "mm", one
 *   control point per point with `id`, `label`, `description`, `associatedNodeID`, `position`,
 *   `orientation` (Slicer's identity, written in LPS), `selected`, `locked`, `visibility` and
 *   `positionStatus` "defined". Coordinates with the shortest decimals that read back exactly.
 * - fcsv: the `# Markups fiducial file version = 4.11`, `# CoordinateSystem = LPS` and
 *   `# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID` headers, one row
 *   a point (fields with a comma or a quote are double-quoted; line breaks become spaces).
 *
 * The points are written as they are, taken to be LPS millimetres (BaryLab's convention). Labels,
 * ids and descriptions come from the point-data arrays `Label`, `Id` and `Description` when the
 * input has them (vtkBaryMarkupsReader's output, and what passes through a deformation);
 * otherwise labels are "F-1", "F-2", ... and ids "1", "2", .... Cells and other arrays are not
 * written. A non-finite point or an input without points is an error (nothing written).
 *
 * @sa vtkBaryMarkupsReader vtkBaryDataIO
 */
#ifndef vtkBaryMarkupsWriter_h
#define vtkBaryMarkupsWriter_h

#include "BaryLabIOModule.h" // for export macro
#include "vtkWriter.h"

#include <string> // for std::string

class BARYLABIO_EXPORT vtkBaryMarkupsWriter : public vtkWriter
{
public:
  static vtkBaryMarkupsWriter* New();
  vtkTypeMacro(vtkBaryMarkupsWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The file formats (the values of vtkBaryMarkupsReader::Formats).
  enum Formats
  {
    FromFileName = 0, ///< .fcsv: legacy fiducial CSV; anything else: markups JSON
    MarkupsJSON = 1,
    FCSV = 2,
  };

  ///@{
  /// The file to write.
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

  ///@{
  /// The format (default FromFileName).
  vtkSetClampMacro(Format, int, FromFileName, FCSV);
  vtkGetMacro(Format, int);
  ///@}

protected:
  vtkBaryMarkupsWriter() = default;
  ~vtkBaryMarkupsWriter() override = default;
  void WriteData() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;

  std::string FileName;
  int Format = FromFileName;

private:
  vtkBaryMarkupsWriter(const vtkBaryMarkupsWriter&) = delete;
  void operator=(const vtkBaryMarkupsWriter&) = delete;
};

#endif
