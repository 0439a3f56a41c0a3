#include "vtkBaryWeightedAverage.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"
#include "vtkBarySurfaceData.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include "core/surface/weighted_averages.h"

#include <algorithm>

vtkStandardNewMacro(vtkBaryWeightedAverage);

struct vtkBaryWeightedAverage::Internals
{
  vtkSmartPointer<vtkDataArray> Weights;
  vtkBarySurfaceData::Cache Cache;
};

vtkBaryWeightedAverage::vtkBaryWeightedAverage()
  : Internal(new Internals)
{
  this->SetNumberOfInputPorts(2);
  const bary::ForwardOptions defaults;
  this->WarmStart = defaults.warm_start;
  this->MaximumTriangles = static_cast<vtkIdType>(defaults.max_triangles);
  this->NumberOfThreads = defaults.threads;
  this->SurfaceTolerance = bary::kDefaultSurfaceTolerance;
  this->SetEmbeddingArrayName(vtkBarySurfaceData::DefaultEmbeddingName());
}

vtkBaryWeightedAverage::~vtkBaryWeightedAverage()
{
  this->SetEmbeddingArrayName(nullptr);
}

void vtkBaryWeightedAverage::SetWeights(vtkDataArray* weights)
{
  if (this->Internal->Weights != weights)
  {
    this->Internal->Weights = weights;
    this->Modified();
  }
}

vtkDataArray* vtkBaryWeightedAverage::GetWeights()
{
  return this->Internal->Weights;
}

vtkMTimeType vtkBaryWeightedAverage::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->Internal->Weights)
    t = std::max(t, this->Internal->Weights->GetMTime());
  return t;
}

int vtkBaryWeightedAverage::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), port == 0 ? "vtkPolyData" : "vtkPointSet");
  return 1;
}

int vtkBaryWeightedAverage::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* surface = vtkPolyData::GetData(inputVector[0]);
  vtkPointSet* anchorData = vtkPointSet::GetData(inputVector[1]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  this->SetErrorCode(0);
  this->NumberOfFailures = this->TrianglesTried = 0;
  this->QuerySeconds = 0;
  try
  {
    if (!this->Internal->Weights)
      throw bary::Error(bary::ErrorCode::EmptyInput, "no weights: call SetWeights");
    const std::string name = this->EmbeddingArrayName ? this->EmbeddingArrayName : "";
    const auto wa = this->Internal->Cache.Get(surface, name);
    const auto anchors =
      vtkBarySurfaceData::Locate(wa->mesh(), anchorData, this->SurfaceTolerance, "anchor");
    const bary::DenseWeights W = vtkBaryConversion::ArrayToMatrix(this->Internal->Weights);
    bary::ForwardOptions options;
    options.search = this->BruteForce ? bary::ForwardOptions::Search::BruteForce
                                      : bary::ForwardOptions::Search::Local;
    options.warm_start = this->WarmStart;
    options.max_triangles = this->MaximumTriangles;
    options.threads = this->NumberOfThreads;
    const bary::ForwardResult r = wa->forward(anchors, W, options, [this](double f) {
      this->UpdateProgress(f);
      return !this->GetAbortExecute();
    });

    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(W.rows());
    vtkNew<vtkCellArray> verts;
    vtkNew<vtkUnsignedCharArray> valid;
    valid->SetName("Valid");
    valid->SetNumberOfTuples(W.rows());
    for (vtkIdType q = 0; q < W.rows(); ++q)
    {
      points->SetPoint(q, r.positions(q, 0), r.positions(q, 1), r.positions(q, 2));
      valid->SetValue(q, r.valid[static_cast<std::size_t>(q)]);
      if (r.valid[static_cast<std::size_t>(q)])
        verts->InsertNextCell(1, &q);
    }
    output->Initialize();
    output->SetPoints(points);
    output->SetVerts(verts);
    vtkBarySurfaceData::AddSurfacePointArrays(output, r.points);
    output->GetPointData()->AddArray(valid);
    this->NumberOfFailures = r.failures;
    this->TrianglesTried = r.triangles_tried;
    this->QuerySeconds = r.seconds;
    return 1;
  }
  VTKBARY_CATCH_ERRORS
}

void vtkBaryWeightedAverage::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "EmbeddingArrayName: " << (this->EmbeddingArrayName ? this->EmbeddingArrayName : "(none)")
     << "\n"
     << indent << "SurfaceTolerance: " << this->SurfaceTolerance << "\n"
     << indent << "BruteForce: " << this->BruteForce << "\n"
     << indent << "WarmStart: " << this->WarmStart << "\n"
     << indent << "MaximumTriangles: " << this->MaximumTriangles << "\n"
     << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n"
     << indent << "Weights: " << (this->Internal->Weights ? "set" : "(none)") << "\n";
}
