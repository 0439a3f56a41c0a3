/**
 * @file   vtkBaryFormatCheck.h
 * @brief  Checks of a file's announced sizes before a VTK reader allocates for them; private
 *         to the IO module (vtkBaryDataIO::Read calls them).
 *
 * VTK's XML readers allocate what a file's header announces before they read the data: an XML
 * `NumberOfPoints="99999999999"` asks for terabytes (std::bad_alloc at best, the machine's
 * memory at worst) on a file of a few bytes, and they trust its compression headers. These
 * checks refuse, naming the attribute or the array, what the file cannot hold: an XML file may
 * compress its data, by at most the 1032:1 of zlib (a bound of 1100 values a byte;
 * LZMA-compressed files beyond it are refused). (Legacy .vtk files are read by BaryLab's own
 * reader, which checks each count as it goes: vtkBaryLegacyVTK.h.)
 */
#ifndef vtkBaryFormatCheck_h
#define vtkBaryFormatCheck_h

#include <cstdint>
#include <string>

namespace vtkbary
{
/// A VTK XML file of @p size bytes: every Number...="N" attribute of the header (before the
/// appended data) is a whole number, and N times the largest NumberOfComponents fits in
/// 1100 values a byte of the file. @throws bary::Error(Io)
void CheckXMLCounts(const std::string& path, std::uintmax_t size);
/// A compressed VTK XML file of @p size bytes: each data array's compression header (block
/// count, block size, last block's size, compressed sizes; inline base64 or appended, raw or
/// base64) is consistent and fits in the file. VTK's reader trusts it: a block size of 0
/// divides by zero, a last block larger than the others reads past the block table.
/// @throws bary::Error(Io)
void CheckXMLCompression(const std::string& path, std::uintmax_t size);
/// A binary STL file of @p size bytes (binary as vtkSTLReader decides it): the triangle
/// count at byte 80 must fit in the file (84 bytes + 50 a triangle). VTK's reader allocates for
/// the count first (4 billion triangles for a 300-byte file). @throws bary::Error(Io)
void CheckSTLCount(const std::string& path, std::uintmax_t size);
} // namespace vtkbary

#endif
