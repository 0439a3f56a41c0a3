#include "vtkBaryWeightStatistics.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"

#include "core/common/error.h"
#include "core/analysis/weight_statistics.h"
#include "core/deformation/cage_deformation.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkTable.h"

#include <string>

vtkStandardNewMacro(vtkBaryWeightStatistics);

namespace
{
void add_value(vtkTable* table, const char* name, double value)
{
  vtkNew<vtkDoubleArray> column;
  column->SetName(name);
  column->InsertNextValue(value);
  table->AddColumn(column);
}
} // namespace

vtkBaryWeightStatistics::vtkBaryWeightStatistics()
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(2);
  this->SetWeightsArrayName("Weights");
  this->SetFaceWeightsArrayName("FaceWeights");
}

vtkBaryWeightStatistics::~vtkBaryWeightStatistics()
{
  this->SetWeightsArrayName(nullptr);
  this->SetFaceWeightsArrayName(nullptr);
}

void vtkBaryWeightStatistics::SetCageData(vtkPolyData* cage)
{
  this->SetInputData(1, cage);
}

int vtkBaryWeightStatistics::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

int vtkBaryWeightStatistics::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0]);
  vtkPolyData* cage = vtkPolyData::GetData(inputVector[1]);
  vtkTable* figures = vtkTable::GetData(outputVector, 0);
  vtkTable* histogramTable = vtkTable::GetData(outputVector, 1);
  this->SetErrorCode(0);
  try
  {
    const std::string name = this->WeightsArrayName ? this->WeightsArrayName : "";
    vtkDataArray* array = vtkBaryConversion::RequirePointArray(input, name);
    const int nc = array->GetNumberOfComponents();
    const bary::DenseWeights W = vtkBaryConversion::ArrayToMatrix(array);
    bary::WeightStatisticsOptions options;
    options.threshold = this->Threshold;
    bary::WeightStatistics s;
    vtkIdType faceCoefficients = 0;
    if (cage)
    {
      // bare points (free control points, or a 2D cage as `v` lines): component i = point i
      const bool bare = cage->GetNumberOfPolys() == 0 && cage->GetNumberOfLines() == 0;
      const vtkBaryCage c = bare ? vtkBaryConversion::ToControlPoints(cage, this->CageDimension)
                                 : vtkBaryConversion::ToCage(cage, this->CageDimension);
      if (c.Cage.num_controls() != nc)
        throw bary::Error(bary::ErrorCode::SizeMismatch,
          "the weights array '" + name + "' has " + std::to_string(nc) +
            " components but the cage has " + std::to_string(c.Cage.num_controls()) + " points");
      const int dim = c.Cage.dimension();
      const Eigen::MatrixXd C = vtkBaryConversion::ToMatrix(cage->GetPoints(), dim);
      Eigen::MatrixXd P = vtkBaryConversion::PointsToMatrix(input, dim);
      // Green coordinates: x = W C + psi N; the reproduction of x - psi N by W C is checked
      vtkDataArray* faces = this->FaceWeightsArrayName && *this->FaceWeightsArrayName
        ? vtkBaryConversion::FindPointArray(input, this->FaceWeightsArrayName)
        : nullptr;
      if (faces)
      {
        const vtkIdType nf = dim == 2 ? c.Cage.num_controls() : c.Cage.F.rows();
        if (faces->GetNumberOfComponents() != nf || nf == 0)
          throw bary::Error(bary::ErrorCode::SizeMismatch,
            "the face coefficients '" + std::string(this->FaceWeightsArrayName) + "' have " +
              std::to_string(faces->GetNumberOfComponents()) + " components but the cage has " +
              std::to_string(nf) + (dim == 2 ? " edges" : " faces"));
        const bary::DenseWeights psi = vtkBaryConversion::ArrayToMatrix(faces);
        P -= psi * bary::green_face_terms(c.Cage, c.Cage.V); // rest cage: the unit normals
        faceCoefficients = nf;
      }
      s = bary::weight_statistics(W, &C, &P, options);
    }
    else
      s = bary::weight_statistics(W, nullptr, nullptr, options);

    vtkNew<vtkTable> table;
    add_value(table, "points", static_cast<double>(s.points));
    add_value(table, "controls", static_cast<double>(s.controls));
    add_value(table, "threshold", s.threshold);
    add_value(table, "min_weight", s.min_weight);
    add_value(table, "max_weight", s.max_weight);
    add_value(table, "negative_weights", static_cast<double>(s.negative_weights));
    add_value(table, "non_finite_rows", static_cast<double>(s.non_finite_rows));
    add_value(table, "max_partition_error", s.max_partition_error);
    add_value(table, "mean_partition_error", s.mean_partition_error);
    add_value(table, "mean_significant", s.mean_significant);
    add_value(table, "max_significant", static_cast<double>(s.max_significant));
    if (s.has_reproduction)
    {
      add_value(table, "max_reproduction_error", s.max_reproduction_error);
      add_value(table, "mean_reproduction_error", s.mean_reproduction_error);
      if (faceCoefficients > 0)
        add_value(table, "face_coefficients", static_cast<double>(faceCoefficients));
    }
    vtkNew<vtkIntArray> k;
    k->SetName("k");
    vtkNew<vtkIdTypeArray> count;
    count->SetName("points");
    k->SetNumberOfTuples(static_cast<vtkIdType>(s.max_significant) + 1);
    count->SetNumberOfTuples(k->GetNumberOfTuples());
    count->Fill(0);
    for (vtkIdType i = 0; i < k->GetNumberOfTuples(); ++i)
      k->SetValue(i, static_cast<int>(i));
    for (auto n : s.significant)
      count->SetValue(static_cast<vtkIdType>(n), count->GetValue(static_cast<vtkIdType>(n)) + 1);
    vtkNew<vtkTable> histogram;
    histogram->AddColumn(k);
    histogram->AddColumn(count);
    figures->ShallowCopy(table);
    histogramTable->ShallowCopy(histogram);
  }
  VTKBARY_CATCH_ERRORS
  return 1;
}

void vtkBaryWeightStatistics::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "WeightsArrayName: " << (this->WeightsArrayName ? this->WeightsArrayName : "(none)")
     << "\n";
  os << indent << "FaceWeightsArrayName: "
     << (this->FaceWeightsArrayName ? this->FaceWeightsArrayName : "(none)") << "\n";
  os << indent << "Threshold: " << this->Threshold << "\n";
  os << indent << "CageDimension: " << this->CageDimension << "\n";
}
