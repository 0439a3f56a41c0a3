#include "vtkBarySplineDeform.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"
#include "vtkBarySplineData.h"

#include "core/detail/format.h"

#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkUnstructuredGrid.h"

vtkStandardNewMacro(vtkBarySplineDeform);

vtkBarySplineDeform::vtkBarySplineDeform()
{
  this->SetNumberOfInputPorts(2);
}

int vtkBarySplineDeform::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
    return 1;
  }
  return this->Superclass::FillInputPortInformation(port, info);
}

int vtkBarySplineDeform::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  try
  {
    vtkPointSet* input = vtkPointSet::GetData(inputVector[0]);
    vtkUnstructuredGrid* grid = vtkUnstructuredGrid::GetData(inputVector[1]);
    vtkPointSet* output = vtkPointSet::GetData(outputVector);
    if (!grid)
      throw bary::Error(bary::ErrorCode::EmptyInput, "no spline grid on input port 1");
    if (!input || input->GetNumberOfPoints() == 0)
      throw bary::Error(bary::ErrorCode::EmptyInput, "the model to deform has no points");
    const vtkBarySpline spline = vtkBarySplineData::FromGrid(grid);
    const Eigen::MatrixXd P = vtkBaryConversion::ToMatrix(input->GetPoints(), 3);
    for (bary::Index p = 0; p < P.rows(); ++p)
      if (!P.row(p).allFinite())
        throw bary::Error(bary::ErrorCode::NonFinite,
          "point " + std::to_string(p) + " of the model is not finite");
    const auto where = spline.xy->locate(P.leftCols(2));
    Eigen::MatrixXd Q(P.rows(), 3);
    Q.leftCols(2) = spline.xy->evaluate(where);
    if (spline.is_prism())
    {
      const double lo = spline.prism_bottom, hi = spline.prism_top;
      for (bary::Index p = 0; p < P.rows(); ++p)
        if (P(p, 2) < lo - 1e-12 * (hi - lo) || P(p, 2) > hi + 1e-12 * (hi - lo))
          throw bary::Error(bary::ErrorCode::PointsOutside,
            "point " + std::to_string(p) + " of the model at z = " +
              bary::detail::format_number(P(p, 2)) + " lies outside the prism [" +
              bary::detail::format_number(lo) + ", " + bary::detail::format_number(hi) + "]",
            "make the prism taller (PrismBottom, PrismTop)");
      const Eigen::MatrixXd b = spline.bottom->evaluate(where), t = spline.top->evaluate(where);
      for (bary::Index p = 0; p < P.rows(); ++p)
      {
        const double s = (P(p, 2) - lo) / (hi - lo);
        Q(p, 2) = b(p, 0) + s * (t(p, 0) - b(p, 0));
      }
    }
    else
      Q.col(2) = P.col(2);
    output->ShallowCopy(input);
    auto points = vtkSmartPointer<vtkPoints>::New();
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(Q.rows());
    for (bary::Index p = 0; p < Q.rows(); ++p)
      points->SetPoint(p, Q(p, 0), Q(p, 1), Q(p, 2));
    output->SetPoints(points);
    auto jac = vtkSmartPointer<vtkDoubleArray>::New();
    jac->SetName("SplineJacobian");
    jac->SetNumberOfTuples(Q.rows());
    for (bary::Index p = 0; p < Q.rows(); ++p)
      jac->SetValue(p, spline.xy->jacobian(where.triangle[static_cast<size_t>(p)],
                                     where.barycentric[static_cast<size_t>(p)]).determinant());
    output->GetPointData()->AddArray(jac);
    return 1;
  }
  VTKBARY_CATCH_ERRORS
}
