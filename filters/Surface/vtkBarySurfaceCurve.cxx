#include "vtkBarySurfaceCurve.h"

#include "vtkBaryFilterErrors.h"
#include "vtkBarySurfaceData.h"

#include "vtkCellArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include "core/surface/surface_curves.h"
#include "core/surface/weighted_averages.h"

#include <vector>

vtkStandardNewMacro(vtkBarySurfaceCurve);

struct vtkBarySurfaceCurve::Internals
{
  vtkBarySurfaceData::Cache Cache;
};

vtkBarySurfaceCurve::vtkBarySurfaceCurve()
  : Internal(new Internals)
{
  this->SetNumberOfInputPorts(2);
  this->SurfaceTolerance = bary::kDefaultSurfaceTolerance;
  this->SetEmbeddingArrayName(vtkBarySurfaceData::DefaultEmbeddingName());
}

vtkBarySurfaceCurve::~vtkBarySurfaceCurve()
{
  this->SetEmbeddingArrayName(nullptr);
}

int vtkBarySurfaceCurve::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), port == 0 ? "vtkPolyData" : "vtkPointSet");
  return 1;
}

int vtkBarySurfaceCurve::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* surface = vtkPolyData::GetData(inputVector[0]);
  vtkPointSet* controlData = vtkPointSet::GetData(inputVector[1]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  this->SetErrorCode(0);
  this->NumberOfFailures = 0;
  try
  {
    const std::string name = this->EmbeddingArrayName ? this->EmbeddingArrayName : "";
    const auto wa = this->Internal->Cache.Get(surface, name);
    const auto controls =
      vtkBarySurfaceData::Locate(wa->mesh(), controlData, this->SurfaceTolerance, "control point");
    const bary::DenseWeights W = bary::bspline_weights(
      static_cast<bary::Index>(controls.size()), this->SamplesPerSegment, this->Closed);
    bary::ForwardOptions options;
    options.warm_start = true; // each sample from the previous one (§4.1)
    options.threads = this->NumberOfThreads;
    const bary::ForwardResult r = wa->forward(controls, W, options, [this](double f) {
      this->UpdateProgress(f);
      return !this->GetAbortExecute();
    });

    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(W.rows());
    vtkNew<vtkUnsignedCharArray> valid;
    valid->SetName("Valid");
    valid->SetNumberOfTuples(W.rows());
    vtkNew<vtkCellArray> lines;
    std::vector<vtkIdType> run;
    auto flush = [&] {
      if (run.size() >= 2)
        lines->InsertNextCell(static_cast<vtkIdType>(run.size()), run.data());
      run.clear();
    };
    for (vtkIdType q = 0; q < W.rows(); ++q)
    {
      points->SetPoint(q, r.positions(q, 0), r.positions(q, 1), r.positions(q, 2));
      const bool ok = r.valid[static_cast<std::size_t>(q)] != 0;
      valid->SetValue(q, ok ? 1 : 0);
      if (ok)
        run.push_back(q);
      else
        flush();
    }
    if (this->Closed && !run.empty() && run.front() == 0 && r.valid.front() && r.valid.back() &&
      static_cast<vtkIdType>(run.size()) == W.rows())
      run.push_back(0); // close the loop
    flush();
    output->Initialize();
    output->SetPoints(points);
    output->SetLines(lines);
    vtkBarySurfaceData::AddSurfacePointArrays(output, r.points);
    output->GetPointData()->AddArray(valid);
    this->NumberOfFailures = r.failures;
    return 1;
  }
  VTKBARY_CATCH_ERRORS
}

void vtkBarySurfaceCurve::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "EmbeddingArrayName: " << (this->EmbeddingArrayName ? this->EmbeddingArrayName : "(none)")
     << "\n"
     << indent << "SamplesPerSegment: " << this->SamplesPerSegment << "\n"
     << indent << "Closed: " << this->Closed << "\n"
     << indent << "SurfaceTolerance: " << this->SurfaceTolerance << "\n"
     << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
