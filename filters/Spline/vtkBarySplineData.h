/**
 * @class   vtkBarySplineData
 * @brief   The one place where a spline (bary::TriangularSpline, with the 2.5D deformation's
 *          bottom and top surfaces) becomes a vtkUnstructuredGrid of Bézier triangles and back.
 *
 * The grid (the format `barylab spline` reads and writes, as .vtu):
 * - points: the global control points (SplineNet's numbering), at the deformation's values
 *   (x, y, 0);
 * - cells: one VTK_BEZIER_TRIANGLE per domain triangle, in the domain's triangle order, its
 *   (d + 1)(d + 2)/2 points in VTK's ordering (vtkHigherOrderTriangle::Index), so ParaView draws
 *   the curved deformed grid and VTK evaluates the spline; cell data `HigherOrderDegrees`
 *   (d, d, d);
 * - point data `Nominal` (the control points' nominal positions: the domain; its first #V rows
 *   are the domain's vertices), `ControlPointType` (Table 1: 0 corner, 1 edge corner, 2 edge,
 *   3 inner corner, 4 inner edge, 5 interior), `Pinned` (1: no edit moves it), and for a 2.5D
 *   deformation `Bottom` and `Top` (the values of the surface splines sigma0, sigma1);
 * - field data `SplineDegree`, and for a 2.5D deformation `PrismBottom`, `PrismTop` (the
 *   undeformed prism's z range).
 *
 * @sa vtkBarySplineSource vtkBarySplineEdit vtkBarySplineDeform
 */
#ifndef vtkBarySplineData_h
#define vtkBarySplineData_h

#include "BaryLabSplineModule.h" // for export macro
#include "vtkObject.h"
#include "vtkSmartPointer.h" // for the returned grid

#ifndef __VTK_WRAP__
#include "core/spline/triangular_spline.h" // for bary::TriangularSpline

#include <optional>
#include <vector>

/// A spline deformation as the filters pass it: the xy deformation phi and, for a 2.5D
/// deformation, the bottom and top surfaces sigma0, sigma1 over the same net.
struct vtkBarySpline
{
  std::optional<bary::TriangularSpline> xy;
  std::optional<bary::TriangularSpline> bottom, top;
  double prism_bottom = 0, prism_top = 0; ///< the undeformed prism's z range (2.5D)
  std::vector<bary::Index> pinned;
  bool is_prism() const noexcept { return bottom.has_value() && top.has_value(); }
};
#endif

class vtkUnstructuredGrid;

class BARYLABSPLINE_EXPORT vtkBarySplineData : public vtkObject
{
public:
  static vtkBarySplineData* New();
  vtkTypeMacro(vtkBarySplineData, vtkObject);

#ifndef __VTK_WRAP__
  /// The grid of Bézier triangles of @p spline.
  static vtkSmartPointer<vtkUnstructuredGrid> ToGrid(const vtkBarySpline& spline);
  /// The spline a grid made by ToGrid holds.
  /// @throws bary::Error(InvalidArgument) naming what is missing or inconsistent (not Bézier
  ///   triangles, mixed degrees, no `Nominal`, a numbering that is not BaryLab's), or as
  ///   bary::SplineNet for the domain
  static vtkBarySpline FromGrid(vtkUnstructuredGrid* grid);
  /// VTK's point index (vtkHigherOrderTriangle ordering) of BaryLab's local control point (i, j,
  /// k) of degree d (i the weight of the triangle's first vertex).
  static int VTKIndex(int d, int i, int j);
#endif

protected:
  vtkBarySplineData() = default;
  ~vtkBarySplineData() override = default;

private:
  vtkBarySplineData(const vtkBarySplineData&) = delete;
  void operator=(const vtkBarySplineData&) = delete;
};

#endif
