#include "vtkBarySurfaceRemesh.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"
#include "vtkBarySurfaceData.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include "core/surface/remeshing.h"

#include <limits>

vtkStandardNewMacro(vtkBarySurfaceRemesh);

struct vtkBarySurfaceRemesh::Internals
{
  vtkBarySurfaceData::Cache Cache;
};

vtkBarySurfaceRemesh::vtkBarySurfaceRemesh()
  : Internal(new Internals)
{
  this->SetNumberOfInputPorts(2);
  const bary::RemeshOptions defaults;
  this->Levels = defaults.levels;
  this->SmoothingSteps = defaults.smoothing_steps;
  this->NumberOfThreads = defaults.threads;
  this->SurfaceTolerance = bary::kDefaultSurfaceTolerance;
  this->SetEmbeddingArrayName(vtkBarySurfaceData::DefaultEmbeddingName());
}

vtkBarySurfaceRemesh::~vtkBarySurfaceRemesh()
{
  this->SetEmbeddingArrayName(nullptr);
}

int vtkBarySurfaceRemesh::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

int vtkBarySurfaceRemesh::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* surface = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* coarse = vtkPolyData::GetData(inputVector[1]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  this->SetErrorCode(0);
  this->NumberOfFailures = 0;
  try
  {
    const std::string name = this->EmbeddingArrayName ? this->EmbeddingArrayName : "";
    const auto wa = this->Internal->Cache.Get(surface, name);
    const auto points =
      vtkBarySurfaceData::Locate(wa->mesh(), coarse, this->SurfaceTolerance, "coarse vertex");
    vtkCellArray* polys = coarse->GetPolys();
    Eigen::MatrixXi Q(polys ? polys->GetNumberOfCells() : 0, 4);
    if (polys)
    {
      auto it = vtk::TakeSmartPointer(polys->NewIterator());
      vtkIdType q = 0;
      for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++q)
      {
        vtkIdType n = 0;
        const vtkIdType* ids = nullptr;
        it->GetCurrentCell(n, ids);
        if (n != 4)
          throw bary::Error(bary::ErrorCode::InvalidArgument, "polygon " + std::to_string(q) +
              " of the coarse mesh has " + std::to_string(n) + " points, not 4 (a quad layout)");
        for (int k = 0; k < 4; ++k)
          Q(q, k) = static_cast<int>(ids[k]);
      }
    }
    bary::RemeshOptions options;
    options.levels = this->Levels;
    options.smoothing_steps = this->SmoothingSteps;
    options.threads = this->NumberOfThreads;
    const bary::QuadRemesh r = bary::semiregular_remesh(*wa, points, Q, options, [this](double f) {
      this->UpdateProgress(f);
      return !this->GetAbortExecute();
    });
    const Eigen::MatrixXd X = bary::surface_point_positions(wa->mesh().F, wa->mesh().V, [&] {
      auto p = r.points;
      for (auto& s : p)
        if (s.face < 0)
          s = bary::SurfacePoint{ 0, Eigen::Vector3d(1, 0, 0) };
      return p;
    }());
    vtkNew<vtkPoints> out_points;
    out_points->SetDataTypeToDouble();
    out_points->SetNumberOfPoints(X.rows());
    vtkNew<vtkUnsignedCharArray> valid;
    valid->SetName("Valid");
    valid->SetNumberOfTuples(X.rows());
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (vtkIdType v = 0; v < X.rows(); ++v)
    {
      const bool ok = r.valid[static_cast<std::size_t>(v)] != 0;
      if (ok)
        out_points->SetPoint(v, X(v, 0), X(v, 1), X(v, 2));
      else
        out_points->SetPoint(v, nan, nan, nan);
      valid->SetValue(v, ok ? 1 : 0);
    }
    vtkNew<vtkCellArray> quads;
    for (vtkIdType q = 0; q < r.quads.rows(); ++q)
    {
      const vtkIdType ids[4] = { r.quads(q, 0), r.quads(q, 1), r.quads(q, 2), r.quads(q, 3) };
      quads->InsertNextCell(4, ids);
    }
    output->Initialize();
    output->SetPoints(out_points);
    output->SetPolys(quads);
    vtkBarySurfaceData::AddSurfacePointArrays(output, r.points);
    output->GetPointData()->AddArray(valid);
    this->NumberOfFailures = r.failures;
    return 1;
  }
  VTKBARY_CATCH_ERRORS
}

void vtkBarySurfaceRemesh::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "EmbeddingArrayName: " << (this->EmbeddingArrayName ? this->EmbeddingArrayName : "(none)")
     << "\n"
     << indent << "Levels: " << this->Levels << "\n"
     << indent << "SmoothingSteps: " << this->SmoothingSteps << "\n"
     << indent << "SurfaceTolerance: " << this->SurfaceTolerance << "\n"
     << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
