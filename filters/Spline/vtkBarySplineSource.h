/**
 * @class   vtkBarySplineSource
 * @brief   The identity spline deformation (Rodrigues et al. 2014, §3) on a 2D domain: input a
 *          triangulation (vtkPolyData of triangles in a plane z = const, used as given) or one
 *          polygon (meshed by CGAL's 2D mesher with about TargetTriangles triangles); output the
 *          spline grid of vtkBarySplineData (Bézier triangles of degree Degree). With Prism on,
 *          a 2.5D deformation: the bottom and top surfaces are the constants PrismBottom and
 *          PrismTop. With fit samples on input ports 1 and 2 (two point sets with as many points:
 *          where in the domain, and where they go), the xy deformation is instead the C1 spline
 *          fitted to them by least squares (bary::fit_spline), e.g. a cage deformation sampled at
 *          points. PinBorder pins the control points on the domain's border (no edit moves them).
 *
 * @sa vtkBarySplineData vtkBarySplineEdit vtkBarySplineDeform
 */
#ifndef vtkBarySplineSource_h
#define vtkBarySplineSource_h

#include "BaryLabSplineModule.h" // for export macro
#include "vtkUnstructuredGridAlgorithm.h"

class BARYLABSPLINE_EXPORT vtkBarySplineSource : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkBarySplineSource* New();
  vtkTypeMacro(vtkBarySplineSource, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Degree of the pieces, [5, 12] (bary::kMinSplineDegree, kMaxSplineDegree). Default 5.
  vtkSetMacro(Degree, int);
  vtkGetMacro(Degree, int);
  /// Triangles to aim for when the domain is a polygon. Default 200.
  vtkSetMacro(TargetTriangles, int);
  vtkGetMacro(TargetTriangles, int);
  /// Make a 2.5D (prism) deformation with flat bottom and top at PrismBottom < PrismTop.
  vtkSetMacro(Prism, bool);
  vtkGetMacro(Prism, bool);
  vtkBooleanMacro(Prism, bool);
  vtkSetMacro(PrismBottom, double);
  vtkGetMacro(PrismBottom, double);
  vtkSetMacro(PrismTop, double);
  vtkGetMacro(PrismTop, double);
  /// Pin the control points on the border edges of the domain. Default off.
  vtkSetMacro(PinBorder, bool);
  vtkGetMacro(PinBorder, bool);
  vtkBooleanMacro(PinBorder, bool);
  /// Fit samples (optional): the points where the map is sampled (port 1) and their images
  /// (port 2), as many of each.
  void SetFitFromData(vtkDataObject* points) { this->SetInputData(1, points); }
  void SetFitToData(vtkDataObject* points) { this->SetInputData(2, points); }

  /// The last fit's errors (root mean square and largest |phi(x) - y| over the samples).
  vtkGetMacro(FitRMSError, double);
  vtkGetMacro(FitMaxError, double);

protected:
  vtkBarySplineSource();
  ~vtkBarySplineSource() override = default;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Degree;
  int TargetTriangles = 200;
  bool Prism = false;
  double PrismBottom = -1.0;
  double PrismTop = 1.0;
  bool PinBorder = false;
  double FitRMSError = 0;
  double FitMaxError = 0;

private:
  vtkBarySplineSource(const vtkBarySplineSource&) = delete;
  void operator=(const vtkBarySplineSource&) = delete;
};

#endif
