#ifndef __VTK_WRAP__
#include "core/deformation/skeleton.h" // for bary::Skeleton
#include <vector>          // for std::vector
#include <Eigen/Core> // for Eigen::MatrixXd
#endif

/**
 * @class   vtkBaryDataIO
 * @brief   Reads and writes data sets by file extension, with errors as exceptions.
 *
 * Formats: .vtp, .vtu, .vtk (legacy), .obj, .stl, .ply (VTK's readers/writers), .off
 * (vtkBaryOFFReader/Writer), 3D Slicer's markups .mrk.json and legacy .fcsv (points in LPS,
 * with their labels: vtkBaryMarkupsReader/Writer), and for reading MEDIT .mesh
 * (vtkBaryMEDITReader) and libigl .tgf skeletons (vtkBaryTGFReader). Read() throws bary::Error(Io) naming the file and the problem
 * (missing, unreadable, unknown extension, parse error reported by the reader, no points).
 * Write() writes to a temporary file beside the target and renames it only on success, so a
 * failed write never leaves a partial file behind.
 *
 * Writing a non-unstructured data set to .vtu converts it (vtkAppendFilter).
 * .obj, .stl, .ply and .off keep only geometry; .vtp/.vtu/.vtk keep named point-data arrays
 * (such as the "Weights" array); .mrk.json and .fcsv keep the points of any data set and their
 * "Label", "Id" and "Description" arrays.
 */
#ifndef vtkBaryDataIO_h
#define vtkBaryDataIO_h

#include "BaryLabIOModule.h" // for export macro
#include "vtkObject.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <string> // for std::string

class vtkDataSet;
class vtkPolyData;

class BARYLABIO_EXPORT vtkBaryDataIO : public vtkObject
{
public:
  static vtkBaryDataIO* New();
  vtkTypeMacro(vtkBaryDataIO, vtkObject);

  /// Reads @p path (a .pvtp / .pvtu: all its pieces as one data set; points that a distributed
  /// run wrote in two pieces appear twice, flagged in vtkGhostType).
  /// @throws bary::Error(Io | EmptyInput | NonFinite)
  static vtkSmartPointer<vtkDataSet> Read(const std::string& path);
  /// Reads @p path and requires a vtkPolyData (cages).  @throws bary::Error
  static vtkSmartPointer<vtkPolyData> ReadPolyData(const std::string& path);
  /// Writes @p data to @p path (format by extension), atomically. @throws bary::Error(Io)
  static void Write(vtkDataSet* data, const std::string& path);
  /// Lower-case extension of @p path including the dot (".vtp"), or "".
  static std::string Extension(const std::string& path);
  /// True if Read() understands the extension of @p path.
  static bool CanRead(const std::string& path);
  /// True if Write() knows the extension of @p path.
  static bool CanWrite(const std::string& path);
  /// Throws what Write(@p data, @p path) would for the pair before anything is written: an
  /// unknown extension, or a surface-only format (.vtp, .obj, .stl, .ply, .off) for data that is
  /// not a vtkPolyData. Callers check their output before a long computation with the data set
  /// the result will copy (the result has its type). @throws bary::Error(Io)
  static void CheckWritable(vtkDataSet* data, const std::string& path);

#ifndef __VTK_WRAP__
  /// libigl's ASCII .dmat matrix: header "columns rows", then the values column-major.
  /// @throws bary::Error(Io) naming the file and the missing/bad value, (NonFinite) for NaN/inf.
  static Eigen::MatrixXd ReadDMAT(const std::string& path);
  /// A list of numbers: whitespace-separated, '#' comments, any number a line (tcc user
  /// weights), or a libigl .dmat read in column-major order.
  /// @throws bary::Error(Io) naming the line and token, (NonFinite) for NaN/inf.
  static std::vector<double> ReadNumbers(const std::string& path);
  /// A pseudo-edges file (BBW poses from moved point handles): one pair of point-handle
  /// indices (0-based) a line, '#' comments. @throws bary::Error(Io) naming the line.
  static Eigen::MatrixXi ReadPseudoEdges(const std::string& path);
  /// A text matrix: one row a line, whitespace-separated numbers, '#' comments, blank lines
  /// skipped (weights of weighted averages, embeddings, x y z points), or a libigl .dmat.
  /// @param columns the required number of columns (0: any, but every row the same)
  /// @throws bary::Error(Io) naming the line and token or a row of another length,
  ///   (NonFinite) naming the line of a NaN/inf, (EmptyInput) for a file without numbers.
  static Eigen::MatrixXd ReadMatrix(const std::string& path, Eigen::Index columns = 0);
  /// Writes @p M as a text matrix, one row a line, shortest round-trip decimals, atomically.
  static void WriteMatrix(const Eigen::MatrixXd& M, const std::string& path);
  /// Writes @p M as ASCII .dmat (shortest round-trip decimal representation), atomically.
  static void WriteDMAT(const Eigen::MatrixXd& M, const std::string& path);

  /**
   * A pose: one affine transform per handle, returned as 3 x 4 matrices [A | t] (2D transforms
   * are lifted: third row [0 0 1 0]). Formats, by content:
   * - BaryLab pose text (any extension but .dmat): one line per handle in weights-column order,
   *   `#` starts a comment, blank lines are skipped; a line holds 12 numbers (3D, row-major
   *   a00 a01 a02 t0 a10 a11 a12 t1 a20 a21 a22 t2), 6 (2D, a00 a01 t0 a10 a11 t1), or a
   *   translation alone (3 numbers in 3D, 2 in 2D).
   * - libigl .dmat, either per-bone rotations as its BBW tutorial poses the hand (a column of
   *   4 #B numbers, or #B rows of 4: quaternions x y z w, relative to the parent bone, applied by
   *   forward kinematics: bary::forward_kinematics; needs @p skeleton; point handles stay put),
   *   or libigl's stacked transforms ((dim+1) #handles rows by dim columns: handle j's [A | t]
   *   transposed in rows (dim+1) j ...).
   * @param handles the number of handles (weights components) the pose must cover
   * @param skeleton the handles' skeleton (may be null unless the file holds rotations)
   * @throws bary::Error(Io) naming the file, line and problem; (SizeMismatch) for a pose that
   *   does not have one transform per handle; (NonFinite) for NaN / infinity.
   */
  static std::vector<Eigen::MatrixXd> ReadPose(
    const std::string& path, Eigen::Index handles, const bary::Skeleton* skeleton = nullptr);
#endif

protected:
  vtkBaryDataIO() = default;
  ~vtkBaryDataIO() override = default;

private:
  vtkBaryDataIO(const vtkBaryDataIO&) = delete;
  void operator=(const vtkBaryDataIO&) = delete;
};

#endif
