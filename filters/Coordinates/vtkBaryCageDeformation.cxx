#include "vtkBaryCageDeformation.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"

#include "core/deformation/cage_deformation.h"
#include "core/common/error.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <cmath>
#include <string>
#include <utility>

vtkStandardNewMacro(vtkBaryCageDeformation);


namespace
{
/// FNV-1a over raw bytes: a content hash, so equal data give equal keys whatever their MTime.
struct Hasher
{
  std::uint64_t h = 1469598103934665603ULL;
  void add(const void* data, std::size_t bytes)
  {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i)
      h = (h ^ p[i]) * 1099511628211ULL;
  }
  template <class T>
  void add(const T& value)
  {
    add(&value, sizeof(T));
  }
};

void hash_points(Hasher& hasher, vtkPoints* points)
{
  const vtkIdType n = points ? points->GetNumberOfPoints() : 0;
  hasher.add(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double x[3];
    points->GetPoint(i, x);
    hasher.add(x, sizeof(x));
  }
}

void hash_cells(Hasher& hasher, vtkCellArray* cells)
{
  const vtkIdType n = cells ? cells->GetNumberOfCells() : 0;
  hasher.add(n);
  for (vtkIdType c = 0; c < n; ++c)
  {
    vtkIdType size;
    const vtkIdType* ids;
    cells->GetCellAtId(c, size, ids);
    hasher.add(size);
    hasher.add(ids, sizeof(vtkIdType) * static_cast<std::size_t>(size));
  }
}
} // namespace

struct vtkBaryCageDeformation::Cache
{
  bool Valid = false;
  std::uint64_t Key = 0;
  bary::DenseWeights W;   // core control order
  bary::DenseWeights Psi; // face coefficients (GREEN), core face order; empty otherwise
};

vtkBaryCageDeformation::vtkBaryCageDeformation()
  : WeightCache(new Cache)
{
  this->SetNumberOfInputPorts(3);
  this->WeightMethod = vtkBaryWeightMethod::New();
  this->SetWeightsArrayName("Weights");
  this->SetFaceWeightsArrayName("FaceWeights");
}

void vtkBaryCageDeformation::SetWeightMethod(vtkBaryWeightMethod* method)
{
  if (vtkBaryWeightMethod::Replace(this, this->WeightMethod, method))
    this->Modified();
}

vtkMTimeType vtkBaryCageDeformation::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  return std::max(t, this->WeightMethod->GetMTime());
}

vtkBaryCageDeformation::~vtkBaryCageDeformation()
{
  this->WeightMethod->UnRegister(this);
  this->SetWeightsArrayName(nullptr);
  this->SetFaceWeightsArrayName(nullptr);
}

void vtkBaryCageDeformation::ClearCache()
{
  this->WeightCache->Valid = false;
  this->WeightCache->W.resize(0, 0);
  this->WeightCache->Psi.resize(0, 0);
}

void vtkBaryCageDeformation::SetRestCageData(vtkPolyData* cage)
{
  this->SetInputData(1, cage);
}
void vtkBaryCageDeformation::SetRestCageConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}
void vtkBaryCageDeformation::SetDeformedCageData(vtkPointSet* cage)
{
  this->SetInputData(2, cage);
}
void vtkBaryCageDeformation::SetDeformedCageConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(2, output);
}

int vtkBaryCageDeformation::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  else
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  return 1;
}

int vtkBaryCageDeformation::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPointSet* input = vtkPointSet::GetData(inputVector[0]);
  vtkPolyData* restCage = vtkPolyData::GetData(inputVector[1]);
  vtkPointSet* deformedCage = vtkPointSet::GetData(inputVector[2]);
  vtkPointSet* output = vtkPointSet::GetData(outputVector);
  this->SetErrorCode(0);
  if (!input || !output)
  {
    vtkErrorMacro(<< "No input point set.");
    return 0;
  }
  if (!restCage)
  {
    vtkErrorMacro(<< "No rest cage: connect a vtkPolyData to input port 1 (SetRestCageData).");
    return 0;
  }
  if (!deformedCage)
  {
    vtkErrorMacro(<< "No deformed cage: connect a vtkPointSet to input port 2 "
                     "(SetDeformedCageData).");
    return 0;
  }
  output->ShallowCopy(input);
  if (input->GetNumberOfPoints() == 0)
  {
    vtkWarningMacro(<< "The input has no points; nothing to deform.");
    return 1;
  }

  try
  {
    // methods without linear precision (BBW) blend displacements, see the class description
    const bool blendsDisplacements =
      !bary::method_info(static_cast<bary::MethodId>(this->WeightMethod->GetMethod()))
         .linear_precision;
    // Green coordinates: vertex weights and face coefficients, deformed with the faces' normals
    const bool faceTerms = vtkBaryWeightMethod::HasFaceTerms(this->WeightMethod->GetMethod());
    const vtkBaryCage cage = this->WeightMethod->ReadControls(restCage);
    const int dim = cage.Cage.dimension();
    const vtkIdType nc = cage.Cage.num_controls();
    const Eigen::MatrixXd C = vtkBaryConversion::ControlPoints(deformedCage, cage);

    const vtkIdType nf = dim == 2 ? nc : cage.Cage.F.rows();
    const bary::DenseWeights* W = nullptr;
    const bary::DenseWeights* Psi = nullptr;
    bary::DenseWeights fromInput, facesFromInput;
    vtkDataArray* given = this->UseInputWeights && this->WeightsArrayName
      ? input->GetPointData()->GetArray(this->WeightsArrayName)
      : nullptr;
    // Compact (reduced) weights written by vtkBaryReduceWeights: <name>Indices/<name>Values,
    // read when the dense array is absent; deformed with a sparse product, O(K) per point.
    vtkDataArray* compactIndices = nullptr;
    vtkDataArray* compactValues = nullptr;
    if (!given && this->UseInputWeights && this->WeightsArrayName && *this->WeightsArrayName)
    {
      const std::string name = this->WeightsArrayName;
      compactIndices = input->GetPointData()->GetArray((name + "Indices").c_str());
      compactValues = input->GetPointData()->GetArray((name + "Values").c_str());
      if (!compactIndices || !compactValues)
        compactIndices = compactValues = nullptr;
    }
    if (compactIndices && faceTerms)
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "Green coordinates cannot deform with the compact (reduced) weights '" +
          std::string(this->WeightsArrayName) + "Indices'/'" + this->WeightsArrayName +
          "Values': the deformation needs every vertex weight and every face coefficient; give "
          "the dense arrays '" + this->WeightsArrayName + "' and '" +
          (this->FaceWeightsArrayName ? this->FaceWeightsArrayName : "") +
          "', or turn UseInputWeights off to compute them");
    if (compactIndices)
    {
      const std::string name = this->WeightsArrayName;
      vtkDataArray* count =
        input->GetFieldData()->GetArray((name + "NumberOfControlPoints").c_str());
      // compared as doubles: a NaN or huge count in the file is no integer to cast to
      if (count && count->GetNumberOfTuples() > 0 &&
        !(count->GetComponent(0, 0) == static_cast<double>(nc)))
        throw bary::Error(bary::ErrorCode::SizeMismatch,
          "the compact weights '" + name + "Indices'/'" + name + "Values' are for " +
            vtkBaryConversion::CountText(count->GetComponent(0, 0)) + " control points but the cage has " +
            std::to_string(nc));
      const bary::SparseWeights Ws =
        vtkBaryConversion::FromCompactArrays(compactIndices, compactValues, nc);
      if (Ws.rows() != input->GetNumberOfPoints())
        throw bary::Error(bary::ErrorCode::SizeMismatch, "compact weights: wrong number of tuples");
      this->UpdateProgress(0.5);
      // Columns are cage point ids (like the dense array's components): the moved control
      // points in cage point order.
      Eigen::MatrixXd Cp(nc, dim);
      for (vtkIdType k = 0; k < nc; ++k)
        Cp.row(cage.ControlPointIds[static_cast<std::size_t>(k)]) =
          blendsDisplacements ? Eigen::RowVectorXd(C.row(k) - cage.Cage.V.row(k))
                                                  : Eigen::RowVectorXd(C.row(k));
      const Eigen::MatrixXd X = blendsDisplacements
        ? Eigen::MatrixXd(vtkBaryConversion::PointsToMatrix(input, dim) +
            bary::deform_points(Ws, Cp))
        : bary::deform_points(Ws, Cp);
      vtkBaryConversion::SetPoints(output, X);
      this->UpdateProgress(1.0);
      return 1;
    }
    // GREEN: the face coefficients must come with the weights, else both are computed
    vtkDataArray* givenFaces = faceTerms && given && this->FaceWeightsArrayName &&
        *this->FaceWeightsArrayName
      ? input->GetPointData()->GetArray(this->FaceWeightsArrayName)
      : nullptr;
    const bool facesUsable = !faceTerms || (givenFaces && givenFaces->GetNumberOfComponents() == nf);
    if (given && given->GetNumberOfComponents() == nc && !facesUsable)
    {
      if (givenFaces)
        vtkWarningMacro(<< "Ignoring input arrays '" << this->WeightsArrayName << "' and '"
                        << this->FaceWeightsArrayName << "': the face coefficients have "
                        << givenFaces->GetNumberOfComponents() << " components but the cage has "
                        << nf << " faces; computing Green coordinates instead.");
      else
        vtkWarningMacro(<< "Ignoring input array '" << this->WeightsArrayName
                        << "': Green coordinates also need the face coefficients '"
                        << (this->FaceWeightsArrayName ? this->FaceWeightsArrayName : "")
                        << "', which the model does not carry; computing them instead.");
    }
    if (given && given->GetNumberOfComponents() == nc && facesUsable)
    {
      fromInput = vtkBaryConversion::FromArray(given, cage);
      W = &fromInput;
      if (faceTerms)
      {
        facesFromInput = vtkBaryConversion::ArrayToMatrix(givenFaces);
        if (!facesFromInput.allFinite())
          throw bary::Error(bary::ErrorCode::NonFinite,
            "the face coefficients '" + std::string(this->FaceWeightsArrayName) +
              "' contain NaN or infinity");
        Psi = &facesFromInput;
      }
      this->UpdateProgress(0.5);
    }
    else
    {
      if (given && given->GetNumberOfComponents() != nc)
        vtkWarningMacro(<< "Ignoring input array '" << this->WeightsArrayName << "': it has "
                        << given->GetNumberOfComponents() << " components but the cage has "
                        << nc << " points; computing weights instead.");
      Hasher hasher;
      hash_points(hasher, restCage->GetPoints());
      hash_cells(hasher, restCage->GetPolys());
      hash_cells(hasher, restCage->GetLines());
      hash_points(hasher, input->GetPoints());
      hasher.add(this->WeightMethod->GetSettingsHash());
      if (!this->WeightCache->Valid || this->WeightCache->Key != hasher.h)
      {
        this->WeightCache->Valid = false;
        const Eigen::MatrixXd points = vtkBaryConversion::PointsToMatrix(input, dim);
        bary::WeightsResult computed = this->WeightMethod->Compute(input, restCage, nullptr,
          [this](double f) {
            this->UpdateProgress(0.9 * f);
            return !this->GetAbortExecute();
          },
          nullptr, nullptr);
        this->WeightCache->W = std::move(computed.W);
        this->WeightCache->Psi = std::move(computed.face_weights);
        this->WeightCache->Key = hasher.h;
        this->WeightCache->Valid = true;
        ++this->NumberOfWeightComputations;
      }
      W = &this->WeightCache->W;
      Psi = &this->WeightCache->Psi;
    }

    if (!W->allFinite())
      vtkWarningMacro(<< "Some weights are undefined (NaN) — points far outside the cage; "
                         "their deformed positions are NaN.");
    // Methods with linear precision (sum_i w_i c_i = x): x' = sum_i w_i c'_i. BBW have none (the
    // paper, §4): they blend the cage vertices' displacements instead, x' = x + sum_i w_i
    // (c'_i - c_i) — linear blend skinning with translations — so the rest pose is the identity.
    // Green coordinates (face terms): x' = phi C' + psi (s n(t')), Lipman et al. 2008.
    const Eigen::MatrixXd X = faceTerms
      ? bary::deform_points_green(*W, *Psi, cage.Cage, C)
      : blendsDisplacements
      ? Eigen::MatrixXd(vtkBaryConversion::PointsToMatrix(input, dim) +
          bary::deform_points(*W, C - cage.Cage.V))
      : bary::deform_points(*W, C);
    vtkBaryConversion::SetPoints(output, X);
    if (this->PassWeights && this->WeightsArrayName && *this->WeightsArrayName)
      output->GetPointData()->AddArray(
        vtkBaryConversion::ToArray(*W, cage, this->WeightsArrayName));
    if (this->PassWeights && faceTerms && this->FaceWeightsArrayName && *this->FaceWeightsArrayName)
      output->GetPointData()->AddArray(vtkBaryConversion::FaceArray(*Psi, this->FaceWeightsArrayName));
    this->UpdateProgress(1.0);
  }
  VTKBARY_CATCH_ERRORS
  return 1;
}

void vtkBaryCageDeformation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "WeightMethod:\n";
  this->WeightMethod->PrintSelf(os, indent.GetNextIndent());
  os << indent << "WeightsArrayName: " << (this->WeightsArrayName ? this->WeightsArrayName : "(none)")
     << "\n";
  os << indent << "FaceWeightsArrayName: "
     << (this->FaceWeightsArrayName ? this->FaceWeightsArrayName : "(none)") << "\n";
  os << indent << "UseInputWeights: " << this->UseInputWeights << "\n";
  os << indent << "PassWeights: " << this->PassWeights << "\n";
  os << indent << "NumberOfWeightComputations: " << this->NumberOfWeightComputations << "\n";
}
