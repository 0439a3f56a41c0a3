#include "vtkBaryLinearBlendSkinning.h"

#include "vtkBaryConversion.h"
#include "vtkBaryMixedHandles.h"
#include "vtkBaryFilterErrors.h"

#include "core/common/error.h"
#include "core/deformation/linear_blend_skinning.h"
#include "core/deformation/skeleton.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"

#include <algorithm>
#include <string>

vtkStandardNewMacro(vtkBaryLinearBlendSkinning);
vtkCxxSetObjectMacro(vtkBaryLinearBlendSkinning, Transforms, vtkDoubleArray);

vtkBaryLinearBlendSkinning::vtkBaryLinearBlendSkinning()
{
  this->SetWeightsArrayName("Weights");
}

vtkBaryLinearBlendSkinning::~vtkBaryLinearBlendSkinning()
{
  this->SetTransforms(nullptr);
  this->SetWeightsArrayName(nullptr);
}

vtkMTimeType vtkBaryLinearBlendSkinning::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->Transforms)
    t = std::max(t, this->Transforms->GetMTime());
  return t;
}

int vtkBaryLinearBlendSkinning::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPointSet* input = vtkPointSet::GetData(inputVector[0]);
  vtkPointSet* output = vtkPointSet::GetData(outputVector);
  this->SetErrorCode(0);
  if (!input || !output)
  {
    vtkErrorMacro(<< "No input point set.");
    return 0;
  }
  output->ShallowCopy(input);
  if (input->GetNumberOfPoints() == 0)
    return 1;
  try
  {
    if (!this->Transforms)
      throw bary::Error(bary::ErrorCode::EmptyInput,
        "no handle transforms: set one 12-component tuple ([A | t] row-major) per handle");
    if (this->Transforms->GetNumberOfComponents() != 12)
      throw bary::Error(bary::ErrorCode::SizeMismatch,
        "the transforms array has " + std::to_string(this->Transforms->GetNumberOfComponents()) +
          " components; it needs 12 per handle ([A | t] row-major, 3 by 4)");
    vtkDataArray* weights = vtkBaryConversion::RequirePointArray(input,
      this->WeightsArrayName ? this->WeightsArrayName : "",
      "the handles' weights (compute them with vtkBaryCoordinates)");
    const vtkIdType handles = this->Transforms->GetNumberOfTuples();
    if (weights->GetNumberOfComponents() != handles)
      throw bary::Error(bary::ErrorCode::SizeMismatch,
        "the weights have " + std::to_string(weights->GetNumberOfComponents()) +
          " components (handles) but " + std::to_string(handles) + " transforms are given");
    const bary::DenseWeights W = vtkBaryConversion::ArrayToMatrix(weights);
    for (Eigen::Index p = 0; p < W.rows(); ++p)
      if (!W.row(p).allFinite())
        throw bary::Error(bary::ErrorCode::NonFinite,
          "point " + std::to_string(p) + " has NaN weights (outside the domain?); its skinned "
          "position is undefined");
    bary::AffineTransforms transforms(static_cast<std::size_t>(handles));
    for (vtkIdType j = 0; j < handles; ++j)
    {
      Eigen::MatrixXd T(3, 4);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
          T(r, c) = this->Transforms->GetComponent(j, 4 * r + c);
      transforms[static_cast<std::size_t>(j)] = T;
    }
    const Eigen::MatrixXd X = vtkBaryConversion::PointsToMatrix(input, 3);
    const Eigen::MatrixXd Y =
      bary::linear_blend_skinning(X, W, transforms, this->NumberOfThreads);
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(Y.rows());
    for (Eigen::Index p = 0; p < Y.rows(); ++p)
      points->SetPoint(p, Y(p, 0), Y(p, 1), Y(p, 2));
    output->SetPoints(points);
  }
  VTKBARY_CATCH_ERRORS
  return 1;
}

void vtkBaryLinearBlendSkinning::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Transforms: " << (this->Transforms ? this->Transforms->GetNumberOfTuples() : 0)
     << " handles\n";
  os << indent << "WeightsArrayName: " << (this->WeightsArrayName ? this->WeightsArrayName : "(none)")
     << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}

std::vector<Eigen::MatrixXd> vtkBaryLinearBlendSkinning::PoseFromJoints(vtkPolyData* handles,
  vtkPointSet* posedJoints, int dimension, const Eigen::MatrixXi& pseudoEdges)
{
  const bary::Skeleton skeleton = vtkBaryMixedHandles::ToHandles(handles, dimension);
  const Eigen::MatrixXd posed = vtkBaryConversion::PointsToMatrix(posedJoints, dimension);
  std::vector<Eigen::MatrixXd> pose;
  for (const Eigen::MatrixXd& T : bary::transforms_from_joints(skeleton, posed, pseudoEdges))
    pose.push_back(bary::lift_transform(T));
  return pose;
}
