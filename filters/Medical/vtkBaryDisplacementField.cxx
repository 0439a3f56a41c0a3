#include "vtkBaryDisplacementField.h"

#include "vtkBaryCageMesher.h"
#include "vtkBaryConversion.h"
#include "vtkBaryErrorObserver.h"
#include "vtkBaryFilterErrors.h"
#include "vtkBaryWeightMethod.h"

#include "core/common/error.h"
#include "core/coordinates/weight_methods.h"
#include "core/deformation/cage_deformation.h"
#include "core/detail/format.h"
#include "core/imaging/image_grid.h"
#include "core/meshing/mesh_point_locator.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <string>

vtkStandardNewMacro(vtkBaryDisplacementField);

namespace
{
/// Updates @p algorithm; its first error becomes bary::Error (with the algorithm's error code).
void run_displacement_stage(vtkAlgorithm* algorithm, const char* what)
{
  vtkNew<vtkBaryErrorObserver> observer;
  observer->Observe(algorithm);
  algorithm->Update();
  observer->Release();
  if (observer->HasError() || algorithm->GetErrorCode() != 0)
    throw bary::Error(
      vtkBaryConversion::ErrorCodeOf(algorithm->GetErrorCode(), bary::ErrorCode::InvalidArgument),
      std::string(what) + ": " +
        (observer->HasError() ? observer->GetFirstError() : std::string("failed")));
}

/// The physical points of the voxels [begin, end) of @p grid, (end - begin) by 3.
bary::Points block_points(const bary::ImageGrid& grid, const Eigen::Matrix3d& M, vtkIdType begin,
  vtkIdType end)
{
  bary::Points P(end - begin, 3);
  for (vtkIdType v = begin; v < end; ++v)
  {
    const Eigen::Vector3d index(double(v % grid.size[0]), double((v / grid.size[0]) % grid.size[1]),
      double(v / (grid.size[0] * grid.size[1])));
    P.row(v - begin) = (grid.origin + M * index).transpose();
  }
  return P;
}

void add_number(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}
} // namespace

vtkBaryDisplacementField::vtkBaryDisplacementField()
{
  this->SetNumberOfInputPorts(3);
  this->SetNumberOfOutputPorts(2);
  this->WeightMethod = vtkBaryWeightMethod::New();
  this->SetDisplacementArrayName("Displacement");
}

vtkBaryDisplacementField::~vtkBaryDisplacementField()
{
  if (this->WeightMethod)
    this->WeightMethod->UnRegister(this);
  this->SetDisplacementArrayName(nullptr);
}

void vtkBaryDisplacementField::SetWeightMethod(vtkBaryWeightMethod* method)
{
  if (vtkBaryWeightMethod::Replace(this, this->WeightMethod, method))
    this->Modified();
}

vtkMTimeType vtkBaryDisplacementField::GetMTime()
{
  return std::max(this->Superclass::GetMTime(), this->WeightMethod->GetMTime());
}

void vtkBaryDisplacementField::SetRestCageData(vtkPolyData* cage)
{
  this->SetInputData(0, cage);
}
void vtkBaryDisplacementField::SetRestCageConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(0, output);
}
void vtkBaryDisplacementField::SetDeformedCageData(vtkPointSet* cage)
{
  this->SetInputData(1, cage);
}
void vtkBaryDisplacementField::SetDeformedCageConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}
void vtkBaryDisplacementField::SetReferenceImageData(vtkImageData* image)
{
  this->SetInputData(2, image);
}
void vtkBaryDisplacementField::SetReferenceImageConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(2, output);
}

int vtkBaryDisplacementField::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  else if (port == 1)
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

bary::ImageGrid vtkBaryDisplacementField::ToGrid(vtkImageData* image)
{
  if (!image)
    throw bary::Error(bary::ErrorCode::EmptyInput, "no image");
  int extent[6];
  image->GetExtent(extent);
  bary::ImageGrid grid;
  for (int a = 0; a < 3; ++a)
    grid.size[a] = std::max(0, extent[2 * a + 1] - extent[2 * a] + 1);
  if (grid.size[0] * grid.size[1] * grid.size[2] == 0)
    throw bary::Error(bary::ErrorCode::EmptyInput, "the image has no voxels");
  const double* s = image->GetSpacing();
  const double* o = image->GetOrigin();
  grid.spacing = Eigen::Vector3d(s[0], s[1], s[2]);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      grid.direction(r, c) = image->GetDirectionMatrix()->GetElement(r, c);
  grid.origin = Eigen::Vector3d(o[0], o[1], o[2]) +
    grid.direction *
      grid.spacing.cwiseProduct(Eigen::Vector3d(extent[0], extent[2], extent[4]));
  bary::validate_image_grid(grid, "the image's grid");
  return grid;
}

void vtkBaryDisplacementField::SetGrid(vtkImageData* image, const bary::ImageGrid& grid)
{
  image->SetExtent(0, int(grid.size[0]) - 1, 0, int(grid.size[1]) - 1, 0, int(grid.size[2]) - 1);
  image->SetOrigin(grid.origin.data());
  image->SetSpacing(grid.spacing.data());
  double d[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      d[3 * r + c] = grid.direction(r, c);
  image->SetDirectionMatrix(d);
}

bary::DisplacementField vtkBaryDisplacementField::ToField(vtkImageData* image, const char* name)
{
  bary::DisplacementField field;
  field.grid = ToGrid(image);
  vtkDataArray* array = nullptr;
  if (name && *name)
    array = image->GetPointData()->GetArray(name);
  if (!array)
    array = image->GetPointData()->GetVectors();
  if (!array && image->GetPointData()->GetScalars() &&
    image->GetPointData()->GetScalars()->GetNumberOfComponents() == 3)
    array = image->GetPointData()->GetScalars();
  if (!array || array->GetNumberOfComponents() != 3)
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      std::string("the image holds no 3-component displacement array") +
        (name && *name ? std::string(" '") + name + "'" : std::string()) +
        " (a displacement field has one 3D vector per voxel)");
  const vtkIdType n = array->GetNumberOfTuples();
  if (n != field.grid.voxel_count())
    throw bary::Error(bary::ErrorCode::SizeMismatch,
      "the displacement array has " + std::to_string(n) + " vectors for " +
        std::to_string(field.grid.voxel_count()) + " voxels");
  field.values.resize(3, n);
  if (auto* doubles = vtkDoubleArray::SafeDownCast(array)) // the same layout: one copy
    std::copy(doubles->GetPointer(0), doubles->GetPointer(0) + 3 * n, field.values.data());
  else
    for (vtkIdType v = 0; v < n; ++v)
      for (int c = 0; c < 3; ++c)
        field.values(c, v) = array->GetComponent(v, c);
  bary::validate_displacement_field(field);
  return field;
}

vtkSmartPointer<vtkImageData> vtkBaryDisplacementField::FromField(
  const bary::DisplacementField& field, const char* name)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  SetGrid(image, field.grid);
  vtkNew<vtkDoubleArray> array;
  array->SetName(name && *name ? name : "Displacement");
  array->SetNumberOfComponents(3);
  array->SetNumberOfTuples(field.values.cols());
  std::copy(field.values.data(), field.values.data() + field.values.size(), array->GetPointer(0));
  image->GetPointData()->SetScalars(array); // what vtkBaryImageIO::Write writes
  image->GetPointData()->SetVectors(array);
  return image;
}

bary::DisplacementField vtkBaryDisplacementField::SwapLPSRAS(const bary::DisplacementField& field)
{
  bary::DisplacementField out = field;
  out.grid.origin.head<2>() *= -1.0;
  out.grid.direction.topRows<2>() *= -1.0;
  out.values.topRows<2>() *= -1.0;
  return out;
}

bary::ImageGrid vtkBaryDisplacementField::RequestedGrid(vtkInformationVector** inputVector)
{
  if (vtkImageData* reference = vtkImageData::GetData(inputVector[2], 0))
    return ToGrid(reference);
  if (!(this->Bounds[1] >= this->Bounds[0]) || !(this->Bounds[3] >= this->Bounds[2]) ||
    !(this->Bounds[5] >= this->Bounds[4]))
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "no grid: connect a reference image or set Bounds (non-empty) and Spacing");
  return bary::grid_from_bounds(Eigen::Vector3d(this->Bounds[0], this->Bounds[2], this->Bounds[4]),
    Eigen::Vector3d(this->Bounds[1], this->Bounds[3], this->Bounds[5]),
    Eigen::Vector3d(this->Spacing[0], this->Spacing[1], this->Spacing[2]));
}

int vtkBaryDisplacementField::RequestInformation(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The grid is known here from the parameters, or from the reference image's information.
  bary::ImageGrid grid;
  vtkInformation* ref = inputVector[2]->GetNumberOfInformationObjects() > 0
    ? inputVector[2]->GetInformationObject(0)
    : nullptr;
  try
  {
    if (ref && ref->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    {
      int e[6];
      ref->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), e);
      double o[3] = { 0, 0, 0 }, s[3] = { 1, 1, 1 };
      if (ref->Has(vtkDataObject::ORIGIN()))
        ref->Get(vtkDataObject::ORIGIN(), o);
      if (ref->Has(vtkDataObject::SPACING()))
        ref->Get(vtkDataObject::SPACING(), s);
      if (ref->Has(vtkDataObject::DIRECTION()))
      {
        double d[9];
        ref->Get(vtkDataObject::DIRECTION(), d);
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            grid.direction(r, c) = d[3 * r + c];
      }
      for (int a = 0; a < 3; ++a)
        grid.size[a] = std::max(1, e[2 * a + 1] - e[2 * a] + 1);
      grid.spacing = Eigen::Vector3d(s[0], s[1], s[2]);
      grid.origin = Eigen::Vector3d(o[0], o[1], o[2]) +
        grid.direction * grid.spacing.cwiseProduct(Eigen::Vector3d(e[0], e[2], e[4]));
    }
    else if (ref)
      return 1; // a reference without information: the grid is read in RequestData
    else
      grid = this->RequestedGrid(inputVector);
  }
  VTKBARY_CATCH_ERRORS
  for (int port = 0; port < 2; ++port)
  {
    vtkInformation* info = outputVector->GetInformationObject(port);
    const int extent[6] = { 0, int(grid.size[0]) - 1, 0, int(grid.size[1]) - 1, 0,
      int(grid.size[2]) - 1 };
    info->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
    info->Set(vtkDataObject::ORIGIN(), grid.origin.data(), 3);
    info->Set(vtkDataObject::SPACING(), grid.spacing.data(), 3);
    double d[9];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        d[3 * r + c] = grid.direction(r, c);
    info->Set(vtkDataObject::DIRECTION(), d, 9);
    vtkDataObject::SetPointDataActiveScalarInfo(info, VTK_DOUBLE, 3);
  }
  return 1;
}

int vtkBaryDisplacementField::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // the cages and the reference image whole (the reference is read for its grid only)
  for (int port = 0; port < 3; ++port)
    for (int i = 0; i < inputVector[port]->GetNumberOfInformationObjects(); ++i)
    {
      vtkInformation* info = inputVector[port]->GetInformationObject(i);
      info->Set(vtkStreamingDemandDrivenPipeline::EXACT_EXTENT(), 0);
      if (info->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
        info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
          info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
      info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
      info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
    }
  return 1;
}

int vtkBaryDisplacementField::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->JacobianMinimum = 0.0;
  this->NumberOfFoldedVoxels = this->NumberOfOutsideVoxels = 0;
  this->InverseMaximumResidual = this->InverseMeanResidual = this->InverseToleranceUsed = 0.0;
  this->InverseNotConverged = this->InverseNotConvergedAtBorder = 0;
  this->InverseIterations = 0;
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  vtkImageData* inverseOutput = vtkImageData::GetData(outputVector, 1);
  try
  {
    vtkPolyData* rest = vtkPolyData::GetData(inputVector[0], 0);
    vtkPointSet* deformed = vtkPointSet::GetData(inputVector[1], 0);
    if (!rest || !deformed)
      throw bary::Error(bary::ErrorCode::EmptyInput, "the rest cage and the deformed cage are required");
    const bary::ImageGrid grid = this->RequestedGrid(inputVector);
    const bary::Index n = grid.voxel_count();
    const Eigen::Matrix3d M = grid.index_to_physical();
    const int method = this->WeightMethod->GetMethod();
    vtkNew<vtkBaryWeightMethod> weightMethod; // a copy: the settings of this execution
    weightMethod->DeepCopy(this->WeightMethod);
    // celestial methods: the hull points are decided and placed from the grid's 8 corners (and
    // the controls), the same for every block; the grid is the convex hull of its corners
    vtkNew<vtkPolyData> corners;
    vtkBaryShared shared;
    if (vtkBaryWeightMethod::IsPointBased(method))
    {
      bary::Points C(8, 3);
      for (int c = 0; c < 8; ++c)
        C.row(c) = grid.point(Eigen::Vector3d((c & 1) ? double(grid.size[0] - 1) : 0.0,
                                (c & 2) ? double(grid.size[1] - 1) : 0.0,
                                (c & 4) ? double(grid.size[2] - 1) : 0.0))
                     .transpose();
      vtkNew<vtkPoints> cornerPoints;
      cornerPoints->SetDataTypeToDouble();
      corners->SetPoints(cornerPoints);
      vtkBaryConversion::SetPoints(corners, C);
      shared.AllPoints = corners;
    }
    bary::DisplacementField field;
    field.grid = grid;
    field.values.resize(3, n);
    const bary::MethodInfo& info = bary::method_info(static_cast<bary::MethodId>(method));
    // x' = W C' (linear precision), or x + W (C' - C) (BBW blends displacements, as
    // vtkBaryCageDeformation does); Green coordinates add their face terms
    auto deform = [&](const bary::WeightsResult& r, const vtkBaryCage& columns,
                    const Eigen::MatrixXd& X) -> Eigen::MatrixXd {
      if (columns.Cage.dimension() != 3)
        throw bary::Error(bary::ErrorCode::InvalidArgument,
          "a displacement field needs a 3D cage (this one is 2D)");
      Eigen::MatrixXd C = vtkBaryConversion::ControlPoints(deformed, columns);
      if (r.added_controls.rows() > 0) // celestial hull points stay where they are
      {
        Eigen::MatrixXd all(C.rows() + r.added_controls.rows(), 3);
        all << C, r.added_controls;
        C = all;
      }
      if (r.face_weights.cols() > 0)
        return bary::deform_points_green(r.W, r.face_weights, columns.Cage, C);
      if (!info.linear_precision)
        return X + bary::deform_points(r.W, C - columns.Cage.V);
      return bary::deform_points(r.W, C);
    };
    if (info.domain_mesh)
    {
      // the deformation at the vertices of a mesh of the cage (weights on it as the given
      // domain), interpolated linearly at the voxels; outside the cage, the closest point's
      vtkNew<vtkBaryCageMesher> mesher;
      mesher->SetCageData(rest);
      const int target = weightMethod->GetTargetNumberOfCells();
      mesher->SetTargetNumberOfCells(target > 0 ? target : 20000);
      mesher->SetMaximumCellSize(weightMethod->GetMaximumCellSize());
      run_displacement_stage(mesher, "meshing the cage");
      vtkUnstructuredGrid* mesh = mesher->GetOutput();
      vtkBaryCage columns;
      const bary::WeightsResult r = weightMethod->Compute(mesh, rest, mesh,
        [this](double f) {
          this->UpdateProgress(0.4 * f);
          return !this->GetAbortExecute();
        },
        &columns, nullptr);
      Eigen::MatrixXd V;
      Eigen::MatrixXi T;
      vtkBaryConversion::ToSimplices(mesh, 3, V, T);
      const bary::DenseWeights displacement = deform(r, columns, V) - V;
      const bary::MeshPointLocator locator(V, T);
      for (vtkIdType begin = 0; begin < n; begin += this->BlockSize)
      {
        const vtkIdType end = std::min<vtkIdType>(n, begin + this->BlockSize);
        const bary::MeshPointLocator::Result located = locator.interpolate(
          displacement, block_points(grid, M, begin, end), bary::OutsidePolicy::Nearest);
        field.values.middleCols(begin, end - begin) = located.W.transpose();
        this->NumberOfOutsideVoxels += static_cast<vtkIdType>(located.outside.size());
        this->UpdateProgress(0.4 + 0.4 * double(end) / double(n));
        if (this->GetAbortExecute())
          throw bary::Error(bary::ErrorCode::Cancelled, "the displacement field was cancelled");
      }
    }
    else
    {
      for (vtkIdType begin = 0; begin < n; begin += this->BlockSize)
      {
        const vtkIdType end = std::min<vtkIdType>(n, begin + this->BlockSize);
        const bary::Points P = block_points(grid, M, begin, end);
        vtkNew<vtkPolyData> block;
        vtkNew<vtkPoints> points;
        points->SetDataTypeToDouble();
        block->SetPoints(points);
        vtkBaryConversion::SetPoints(block, P);
        vtkBaryCage columns;
        const bary::WeightsResult r =
          weightMethod->Compute(block, rest, nullptr, {}, &columns, nullptr, shared);
        const Eigen::MatrixXd Q = deform(r, columns, P);
        for (vtkIdType v = begin; v < end; ++v)
        {
          const Eigen::Vector3d d = (Q.row(v - begin) - P.row(v - begin)).transpose();
          if (!d.allFinite())
          {
            const Eigen::Vector3d p = P.row(v - begin).transpose();
            throw bary::Error(bary::ErrorCode::NonFinite,
              "the deformation is NaN or infinite at the voxel point " +
                bary::detail::format_point(p.data(), 3),
              "the method is not defined there: choose a grid where it is");
          }
          field.values.col(v) = d;
        }
        this->UpdateProgress(0.8 * double(end) / double(n));
        if (this->GetAbortExecute())
          throw bary::Error(bary::ErrorCode::Cancelled, "the displacement field was cancelled");
      }
    }
    const int threads = weightMethod->GetNumberOfThreads();
    const bary::JacobianStatistics jacobian = bary::jacobian_statistics(field, threads);
    this->JacobianMinimum = jacobian.minimum;
    this->NumberOfFoldedVoxels = jacobian.folded;
    if (jacobian.folded > 0)
      vtkWarningMacro(<< "the deformation folds at " << jacobian.folded
                      << " voxels (Jacobian determinant <= 0, minimum " << jacobian.minimum
                      << "): it has no inverse there");
    vtkSmartPointer<vtkImageData> image = FromField(field, this->DisplacementArrayName);
    output->ShallowCopy(image);
    vtkFieldData* fd = output->GetFieldData();
    add_number(fd, "JacobianMinimum", jacobian.minimum);
    add_number(fd, "FoldedVoxels", double(jacobian.folded));
    add_number(fd, "OutsideVoxels", double(this->NumberOfOutsideVoxels));
    if (this->ComputeInverse)
    {
      bary::InverseFieldOptions options;
      options.tolerance = this->InverseTolerance;
      options.max_iterations = this->InverseMaximumIterations;
      options.threads = threads;
      const bary::InverseFieldResult inverse = bary::invert_displacement_field(field, options,
        [this](double f) {
          this->UpdateProgress(0.8 + 0.2 * f);
          return !this->GetAbortExecute();
        });
      this->InverseMaximumResidual = inverse.max_residual;
      this->InverseMeanResidual = inverse.mean_residual;
      this->InverseNotConverged = inverse.not_converged;
      this->InverseNotConvergedAtBorder = inverse.not_converged_at_border;
      this->InverseToleranceUsed = inverse.tolerance;
      this->InverseIterations = inverse.max_iterations_used;
      if (inverse.not_converged > 0)
        vtkWarningMacro(<< "the inverse did not converge at " << inverse.not_converged << " of "
                        << inverse.voxels << " voxels (" << inverse.not_converged_at_border
                        << " at the grid's border, where the preimage is outside the grid); "
                        << "maximum residual " << inverse.max_residual << ", tolerance "
                        << inverse.tolerance);
      vtkSmartPointer<vtkImageData> inv = FromField(inverse.inverse, this->DisplacementArrayName);
      inverseOutput->ShallowCopy(inv);
      for (vtkFieldData* f : { fd, inverseOutput->GetFieldData() })
      {
        add_number(f, "InverseMaximumResidual", inverse.max_residual);
        add_number(f, "InverseMeanResidual", inverse.mean_residual);
        add_number(f, "InverseNotConverged", double(inverse.not_converged));
        add_number(f, "InverseNotConvergedAtBorder", double(inverse.not_converged_at_border));
        add_number(f, "InverseTolerance", inverse.tolerance);
      }
    }
    else
    {
      vtkNew<vtkImageData> empty;
      SetGrid(empty, grid);
      inverseOutput->ShallowCopy(empty);
    }
  }
  VTKBARY_CATCH_ERRORS
  return 1;
}

void vtkBaryDisplacementField::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "WeightMethod: " << vtkBaryWeightMethod::GetMethodName(this->WeightMethod->GetMethod()) << "\n";
  os << indent << "Bounds: (" << this->Bounds[0] << ", " << this->Bounds[1] << ", " << this->Bounds[2]
     << ", " << this->Bounds[3] << ", " << this->Bounds[4] << ", " << this->Bounds[5] << ")\n";
  os << indent << "Spacing: (" << this->Spacing[0] << ", " << this->Spacing[1] << ", "
     << this->Spacing[2] << ")\n";
  os << indent << "ComputeInverse: " << this->ComputeInverse << "\n";
  os << indent << "InverseTolerance: " << this->InverseTolerance << "\n";
  os << indent << "InverseMaximumIterations: " << this->InverseMaximumIterations << "\n";
  os << indent << "BlockSize: " << this->BlockSize << "\n";
  os << indent << "DisplacementArrayName: "
     << (this->DisplacementArrayName ? this->DisplacementArrayName : "(none)") << "\n";
}
