/**
 * @file   vtkBaryLegacyVTK.h
 * @brief  BaryLab's reader of VTK's legacy .vtk format; private to the IO module
 *         (vtkBaryDataIO::Read uses it for .vtk).
 *
 * VTK's own legacy readers trust the file: under fuzzing they crashed on a FIELD block they
 * could not read (vtkStructuredGridReader dereferenced the null field data), on cell sizes that
 * overrun the connectivity (vtkCellArray::AppendLegacyFormat), on keywords in binary data
 * (vtkDataReader::ReadString), and allocated whatever a count announced. This reader walks
 * the same format with every count checked against the bytes left before anything is
 * allocated, every cell size against the connectivity, every number parsed in full.
 *
 * Read: versions 1.0 to 5.1, ASCII and BINARY (big-endian); DATASET POLYDATA,
 * UNSTRUCTURED_GRID, STRUCTURED_POINTS, STRUCTURED_GRID, RECTILINEAR_GRID; cells in the
 * classic layout (`LINES n size`) and in 5.x's (`OFFSETS`, `CONNECTIVITY`); POINT_DATA and
 * CELL_DATA with SCALARS (and LOOKUP_TABLE), COLOR_SCALARS, VECTORS, NORMALS,
 * TEXTURE_COORDINATES, TENSORS, TENSORS6, GLOBAL_IDS, PEDIGREE_IDS and FIELD arrays; FIELD data
 * of the data set; METADATA blocks (skipped). Numeric types bit, char, unsigned_char, short,
 * unsigned_short, int, unsigned_int, long, unsigned_long, vtktypeint64, vtktypeuint64,
 * vtkIdType, float, double. Not read (refused by name): string, utf8_string and variant arrays,
 * polyhedra (FACES), other data set types. Lookup tables are read and dropped. Points are
 * stored as doubles.
 */
#ifndef vtkBaryLegacyVTK_h
#define vtkBaryLegacyVTK_h

#include "vtkSmartPointer.h"

#include <string>

class vtkDataSet;

namespace vtkbary
{
/// Reads the legacy .vtk file @p path. @throws bary::Error(Io) "cannot read 'path' line N: ..."
/// naming the first problem.
vtkSmartPointer<vtkDataSet> ReadLegacyVTK(const std::string& path);
} // namespace vtkbary

#endif
