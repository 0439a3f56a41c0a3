#include "vtkBaryImageWarp.h"

#include "vtkBaryDisplacementField.h"
#include "vtkBaryFilterErrors.h"

#include "core/common/error.h"
#include "core/imaging/image_resampling.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <algorithm>
#include <cmath>

vtkStandardNewMacro(vtkBaryImageWarp);

vtkBaryImageWarp::vtkBaryImageWarp()
{
  this->SetNumberOfInputPorts(3);
}

vtkBaryImageWarp::~vtkBaryImageWarp()
{
  this->SetDisplacementArrayName(nullptr);
}

void vtkBaryImageWarp::SetFieldData(vtkImageData* field)
{
  this->SetInputData(1, field);
}
void vtkBaryImageWarp::SetFieldConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}
void vtkBaryImageWarp::SetReferenceImageData(vtkImageData* image)
{
  this->SetInputData(2, image);
}
void vtkBaryImageWarp::SetReferenceImageConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(2, output);
}

int vtkBaryImageWarp::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  if (port == 2)
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkBaryImageWarp::RequestInformation(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // the output grid: the reference's, else the moving image's; extent from 0 with the origin
  // moved to the first voxel (as vtkBaryDisplacementField::SetGrid writes it)
  vtkInformation* in = inputVector[2]->GetNumberOfInformationObjects() > 0
    ? inputVector[2]->GetInformationObject(0)
    : inputVector[0]->GetInformationObject(0);
  vtkInformation* out = outputVector->GetInformationObject(0);
  int e[6];
  in->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), e);
  double o[3] = { 0, 0, 0 }, s[3] = { 1, 1, 1 }, d[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  if (in->Has(vtkDataObject::ORIGIN()))
    in->Get(vtkDataObject::ORIGIN(), o);
  if (in->Has(vtkDataObject::SPACING()))
    in->Get(vtkDataObject::SPACING(), s);
  if (in->Has(vtkDataObject::DIRECTION()))
    in->Get(vtkDataObject::DIRECTION(), d);
  double origin[3];
  for (int r = 0; r < 3; ++r)
    origin[r] = o[r] + d[3 * r] * s[0] * e[0] + d[3 * r + 1] * s[1] * e[2] + d[3 * r + 2] * s[2] * e[4];
  const int extent[6] = { 0, e[1] - e[0], 0, e[3] - e[2], 0, e[5] - e[4] };
  out->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  out->Set(vtkDataObject::ORIGIN(), origin, 3);
  out->Set(vtkDataObject::SPACING(), s, 3);
  out->Set(vtkDataObject::DIRECTION(), d, 9);
  // the moving image's scalar type
  vtkInformation* scalarInfo = vtkDataObject::GetActiveFieldInformation(inputVector[0]->GetInformationObject(0),
    vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
  if (scalarInfo)
    vtkDataObject::SetPointDataActiveScalarInfo(
      out, scalarInfo->Get(vtkDataObject::FIELD_ARRAY_TYPE()), 1);
  return 1;
}

int vtkBaryImageWarp::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  for (int port = 0; port < 3; ++port)
    for (int i = 0; i < inputVector[port]->GetNumberOfInformationObjects(); ++i)
    {
      vtkInformation* info = inputVector[port]->GetInformationObject(i);
      if (info->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
        info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
          info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
    }
  return 1;
}

int vtkBaryImageWarp::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->NumberOfOutsideVoxels = this->InverseNotConverged = this->InverseNotConvergedAtBorder = 0;
  this->InverseMaximumResidual = this->InverseMeanResidual = 0.0;
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  try
  {
    vtkImageData* moving = vtkImageData::GetData(inputVector[0], 0);
    vtkImageData* fieldImage = vtkImageData::GetData(inputVector[1], 0);
    vtkImageData* reference = vtkImageData::GetData(inputVector[2], 0);
    if (!moving || !fieldImage)
      throw bary::Error(bary::ErrorCode::EmptyInput, "the moving image and the field are required");
    vtkDataArray* scalars = moving->GetPointData()->GetScalars();
    if (!scalars)
      throw bary::Error(bary::ErrorCode::InvalidArgument, "the moving image has no point scalars");
    if (scalars->GetNumberOfComponents() != 1)
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "the moving image has " + std::to_string(scalars->GetNumberOfComponents()) +
          " components per voxel; only scalar images are warped");
    bary::ScalarImage image;
    image.grid = vtkBaryDisplacementField::ToGrid(moving);
    const vtkIdType n = scalars->GetNumberOfTuples();
    image.values.resize(static_cast<size_t>(n));
    for (vtkIdType v = 0; v < n; ++v)
      image.values[size_t(v)] = scalars->GetComponent(v, 0);
    const bary::ImageGrid outputGrid =
      reference ? vtkBaryDisplacementField::ToGrid(reference) : image.grid;
    bary::DisplacementField field =
      vtkBaryDisplacementField::ToField(fieldImage, this->DisplacementArrayName);
    if (!this->FieldIsInverse)
    {
      bary::InverseFieldOptions options;
      options.tolerance = this->InverseTolerance;
      options.max_iterations = this->InverseMaximumIterations;
      options.threads = this->NumberOfThreads;
      bary::InverseFieldResult inverse = bary::invert_displacement_field(field, options,
        [this](double f) {
          this->UpdateProgress(0.5 * f);
          return !this->GetAbortExecute();
        });
      this->InverseMaximumResidual = inverse.max_residual;
      this->InverseMeanResidual = inverse.mean_residual;
      this->InverseNotConverged = inverse.not_converged;
      this->InverseNotConvergedAtBorder = inverse.not_converged_at_border;
      if (inverse.not_converged > 0)
        vtkWarningMacro(<< "the field's inverse did not converge at " << inverse.not_converged
                        << " of " << inverse.voxels << " voxels ("
                        << inverse.not_converged_at_border << " at the grid's border); maximum "
                        << "residual " << inverse.max_residual << ", tolerance "
                        << inverse.tolerance);
      field = std::move(inverse.inverse);
    }
    bary::ResampleOptions options;
    options.interpolation = this->Interpolation == NEAREST ? bary::Interpolation::Nearest
                                                            : bary::Interpolation::Linear;
    options.default_value = this->DefaultValue;
    options.threads = this->NumberOfThreads;
    const double begin = this->FieldIsInverse ? 0.0 : 0.5;
    const bary::ResampleResult r = bary::warp_image(image, outputGrid, field, options,
      [this, begin](double f) {
        this->UpdateProgress(begin + (1.0 - begin) * f);
        return !this->GetAbortExecute();
      });
    this->NumberOfOutsideVoxels = r.outside;
    vtkSmartPointer<vtkDataArray> out;
    out.TakeReference(scalars->NewInstance());
    out->SetName(scalars->GetName());
    out->SetNumberOfComponents(1);
    out->SetNumberOfTuples(static_cast<vtkIdType>(r.values.size()));
    const bool integral = scalars->GetDataType() != VTK_FLOAT && scalars->GetDataType() != VTK_DOUBLE;
    const double lo = out->GetDataTypeMin(), hi = out->GetDataTypeMax();
    for (size_t v = 0; v < r.values.size(); ++v)
    {
      double value = r.values[v];
      if (integral)
        value = std::min(hi, std::max(lo, std::nearbyint(value)));
      out->SetComponent(static_cast<vtkIdType>(v), 0, value);
    }
    vtkBaryDisplacementField::SetGrid(output, outputGrid);
    output->GetPointData()->Initialize();
    output->GetPointData()->SetScalars(out);
  }
  VTKBARY_CATCH_ERRORS
  return 1;
}

void vtkBaryImageWarp::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Interpolation: " << (this->Interpolation == NEAREST ? "nearest" : "linear") << "\n";
  os << indent << "FieldIsInverse: " << this->FieldIsInverse << "\n";
  os << indent << "DefaultValue: " << this->DefaultValue << "\n";
  os << indent << "DisplacementArrayName: "
     << (this->DisplacementArrayName ? this->DisplacementArrayName : "(vectors)") << "\n";
  os << indent << "InverseTolerance: " << this->InverseTolerance << "\n";
  os << indent << "InverseMaximumIterations: " << this->InverseMaximumIterations << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
