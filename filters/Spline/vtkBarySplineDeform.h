/**
 * @class   vtkBarySplineDeform
 * @brief   Deforms a point set (input 0: a model) by a spline deformation (input 1: a spline
 *          grid, vtkBarySplineData): 2D, (x, y, z) -> (phi(x, y), z); 2.5D (a prism grid),
 *          (x, y, z) -> (phi(x, y), sigma0(x, y) + t (sigma1(x, y) - sigma0(x, y))) with
 *          t = (z - PrismBottom) / (PrismTop - PrismBottom) (Rodrigues et al. 2014, §5). Every
 *          point must lie in the domain (x, y) and, for a prism, within [PrismBottom, PrismTop]
 *          (an error names the first that does not). Adds the point array `SplineJacobian`
 *          (the xy Jacobian determinant at each point). The output is the input's type with
 *          moved points; cells and other arrays are kept.
 *
 * @sa vtkBarySplineData vtkBarySplineSource vtkBarySplineEdit
 */
#ifndef vtkBarySplineDeform_h
#define vtkBarySplineDeform_h

#include "BaryLabSplineModule.h" // for export macro
#include "vtkPointSetAlgorithm.h"

class BARYLABSPLINE_EXPORT vtkBarySplineDeform : public vtkPointSetAlgorithm
{
public:
  static vtkBarySplineDeform* New();
  vtkTypeMacro(vtkBarySplineDeform, vtkPointSetAlgorithm);

  /// The spline grid (input port 1).
  void SetSplineConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetSplineData(vtkDataObject* grid) { this->SetInputData(1, grid); }

protected:
  vtkBarySplineDeform();
  ~vtkBarySplineDeform() override = default;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkBarySplineDeform(const vtkBarySplineDeform&) = delete;
  void operator=(const vtkBarySplineDeform&) = delete;
};

#endif
