#include "vtkBaryLabelMapSurface.h"

#include "vtkBaryFilterErrors.h"

#include "core/common/cage.h"
#include "core/common/error.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDecimatePro.h"
#include "vtkQuadricDecimation.h"
#include "vtkDiscreteFlyingEdges3D.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataConnectivityFilter.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowedSincPolyDataFilter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkBaryLabelMapSurface);

namespace
{
using bary::Error;
using bary::ErrorCode;

enum class Decimation
{
  None,
  Pro,
  Quadric
};

std::string number(double x)
{
  std::ostringstream s;
  s.precision(12);
  s << x;
  return s.str();
}

/// "1 (5321 voxels), 2 (77 voxels)", at most @p shown labels.
std::string label_list(const std::map<double, vtkIdType>& counts, std::size_t shown = 12)
{
  std::string text;
  std::size_t n = 0;
  for (const auto& [value, count] : counts)
  {
    if (n == shown)
    {
      text += ", ... (" + std::to_string(counts.size()) + " values in all)";
      break;
    }
    text += (n++ ? ", " : "") + number(value) + " (" + std::to_string(count) + " voxels)";
  }
  return text.empty() ? "none" : text;
}

/// Updates @p filter; its error becomes bary::Error(Internal) naming @p step.
void update(vtkAlgorithm* filter, const char* step)
{
  filter->Update();
  if (filter->GetErrorCode() != 0)
    throw Error(ErrorCode::Internal, std::string("the surface extraction failed at ") + step);
}
} // namespace

vtkBaryLabelMapSurface::vtkBaryLabelMapSurface()
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
}

int vtkBaryLabelMapSurface::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

int vtkBaryLabelMapSurface::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkImageData* image = vtkImageData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  this->LabelUsed = 0;
  this->NumberOfLabelVoxels = 0;
  this->LabelVolume = this->EnclosedVolume = 0.0;
  this->NumberOfExtractedFaces = 0;
  this->NumberOfDroppedComponents = 0;
  this->TouchesBorder = false;
  this->SmoothingIterationsUsed = 0;
  this->DecimationUsed = "none";
  this->NumberOfAttempts = 0;
  this->FirstFailure.clear();
  try
  {
    if (!image)
      throw Error(ErrorCode::EmptyInput, "no image on input 0");
    vtkDataArray* values = image->GetPointData()->GetScalars();
    if (!values || values->GetNumberOfTuples() == 0)
      throw Error(ErrorCode::EmptyInput, "the image has no voxel values (point scalars)");
    if (values->GetNumberOfComponents() != 1)
      throw Error(ErrorCode::InvalidArgument,
        "the image has " + std::to_string(values->GetNumberOfComponents()) +
          " components per voxel; a label map has one");
    int dims[3], extent[6];
    image->GetDimensions(dims);
    image->GetExtent(extent);
    if (values->GetNumberOfTuples() != static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2])
      throw Error(ErrorCode::SizeMismatch, "the image's scalars do not match its extent");

    // The geometry: x = origin + D (index o spacing), refused where it cannot map.
    double D[3][3];
    const double* spacing = image->GetSpacing();
    const double* origin = image->GetOrigin();
    for (int r = 0; r < 3; ++r)
    {
      if (!std::isfinite(origin[r]))
        throw Error(ErrorCode::NonFinite, "the image's origin is not finite");
      if (!std::isfinite(spacing[r]) || spacing[r] <= 0)
        throw Error(ErrorCode::InvalidArgument,
          "the image's spacing on axis " + std::to_string(r + 1) + " is " + number(spacing[r]) +
            " (must be positive and finite)");
      for (int c = 0; c < 3; ++c)
      {
        D[r][c] = image->GetDirectionMatrix()->GetElement(r, c);
        if (!std::isfinite(D[r][c]))
          throw Error(ErrorCode::NonFinite, "the image's direction matrix is not finite");
      }
    }
    double column_norms = 1.0;
    for (int c = 0; c < 3; ++c)
      column_norms *= std::sqrt(D[0][c] * D[0][c] + D[1][c] * D[1][c] + D[2][c] * D[2][c]);
    const double det = vtkMath::Determinant3x3(D);
    if (!(std::abs(det) > 1e-9 * column_norms))
      throw Error(ErrorCode::InvalidArgument,
        "the image's direction matrix is singular (determinant " + number(det) +
          "): its voxels do not map to 3-D space");

    // The label.
    const vtkIdType voxels = values->GetNumberOfTuples();
    const bool floating =
      values->GetDataType() == VTK_FLOAT || values->GetDataType() == VTK_DOUBLE;
    double label = 0.0;
    std::map<double, vtkIdType> counts;
    if (!this->UseThreshold)
    {
      for (vtkIdType v = 0; v < voxels; ++v)
      {
        const double x = values->GetTuple1(v);
        if (floating && !(std::isfinite(x) && x == std::floor(x)))
        {
          const int i = static_cast<int>(v % dims[0]);
          const int j = static_cast<int>((v / dims[0]) % dims[1]);
          const int k = static_cast<int>(v / (static_cast<vtkIdType>(dims[0]) * dims[1]));
          throw Error(ErrorCode::InvalidArgument,
            "the image holds a value that is not an integer label (" + number(x) +
              " at voxel (" + std::to_string(i) + ", " + std::to_string(j) + ", " +
              std::to_string(k) + ")): a label map holds integers",
            "segment voxels at or above a value with UseThreshold / Threshold (--threshold)");
        }
        ++counts[x];
      }
      std::map<double, vtkIdType> labels = counts;
      labels.erase(0.0);
      if (this->Label != 0)
      {
        label = static_cast<double>(this->Label);
        if (!labels.count(label))
          throw Error(ErrorCode::EmptyInput,
            "label " + std::to_string(this->Label) + " is empty: no voxel has that value; " +
              "labels present: " + label_list(labels));
      }
      else if (labels.empty())
        throw Error(ErrorCode::EmptyInput, "the image has no non-zero label (every voxel is 0)");
      else if (labels.size() > 1)
        throw Error(ErrorCode::InvalidArgument,
          "the image has " + std::to_string(labels.size()) + " labels: " + label_list(labels) +
            "; choose one",
          "set Label (--label)");
      else
        label = labels.begin()->first;
      this->LabelUsed = static_cast<long long>(label);
    }

    // The object's voxels, cropped to their bounding box plus one voxel of background.
    auto inside = [&](vtkIdType v) {
      const double x = values->GetTuple1(v);
      return this->UseThreshold ? x >= this->Threshold : x == label;
    };
    std::array<int, 3> lo = { dims[0], dims[1], dims[2] }, hi = { -1, -1, -1 };
    vtkIdType count = 0;
    std::vector<unsigned char> object(static_cast<std::size_t>(voxels), 0);
    vtkIdType v = 0;
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i, ++v)
          if (inside(v))
          {
            object[static_cast<std::size_t>(v)] = 1;
            ++count;
            lo = { std::min(lo[0], i), std::min(lo[1], j), std::min(lo[2], k) };
            hi = { std::max(hi[0], i), std::max(hi[1], j), std::max(hi[2], k) };
          }
    if (count == 0)
      throw Error(ErrorCode::EmptyInput,
        "no voxel is at or above the threshold " + number(this->Threshold) +
          " (the image's values lie in [" + number(values->GetRange(0)[0]) + ", " +
          number(values->GetRange(0)[1]) + "])");
    this->NumberOfLabelVoxels = count;
    this->LabelVolume = static_cast<double>(count) * std::abs(det) * spacing[0] * spacing[1] *
      spacing[2];
    for (int d = 0; d < 3; ++d)
      if (lo[d] == 0 || hi[d] == dims[d] - 1)
        this->TouchesBorder = true;

    const int m[3] = { hi[0] - lo[0] + 3, hi[1] - lo[1] + 3, hi[2] - lo[2] + 3 };
    vtkNew<vtkImageData> mask;
    mask->SetDimensions(m);
    mask->SetSpacing(spacing[0], spacing[1], spacing[2]);
    // index o spacing coordinates of the input, including its extent's offset
    mask->SetOrigin((extent[0] + lo[0] - 1) * spacing[0], (extent[2] + lo[1] - 1) * spacing[1],
      (extent[4] + lo[2] - 1) * spacing[2]);
    vtkNew<vtkUnsignedCharArray> bits;
    bits->SetNumberOfTuples(static_cast<vtkIdType>(m[0]) * m[1] * m[2]);
    bits->FillValue(0);
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i)
          if (object[static_cast<std::size_t>(i + dims[0] * (j + static_cast<vtkIdType>(dims[1]) * k))])
            bits->SetValue(
              (i - lo[0] + 1) + m[0] * ((j - lo[1] + 1) + static_cast<vtkIdType>(m[1]) * (k - lo[2] + 1)), 1);
    std::vector<unsigned char>().swap(object);
    mask->GetPointData()->SetScalars(bits);

    vtkNew<vtkDiscreteFlyingEdges3D> contour;
    contour->SetInputData(mask);
    contour->SetValue(0, 1.0);
    contour->ComputeNormalsOff();
    contour->ComputeGradientsOff();
    contour->ComputeScalarsOff();
    update(contour, "the contouring");

    vtkNew<vtkPolyDataConnectivityFilter> largest;
    largest->SetInputConnection(contour->GetOutputPort());
    largest->SetExtractionModeToLargestRegion();
    update(largest, "the connected pieces");
    this->NumberOfDroppedComponents = std::max(0, largest->GetNumberOfExtractedRegions() - 1);
    vtkSmartPointer<vtkPolyData> surface = largest->GetOutput();
    this->NumberOfExtractedFaces = surface->GetNumberOfPolys();
    if (this->NumberOfExtractedFaces == 0)
      throw Error(ErrorCode::Internal, "the contouring of the label gave no triangle");

    // The surface mapped to physical space (only the points its triangles use), outward, as a
    // cage for validation.
    auto to_cage = [&](vtkPolyData* mesh) {
      vtkCellArray* polys = mesh->GetPolys();
      std::vector<vtkIdType> index(static_cast<std::size_t>(mesh->GetNumberOfPoints()), -1);
      std::vector<std::array<vtkIdType, 3>> triangles;
      triangles.reserve(static_cast<std::size_t>(polys->GetNumberOfCells()));
      vtkIdType used = 0;
      vtkIdType n;
      const vtkIdType* ids;
      for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
      {
        if (n != 3)
          throw Error(ErrorCode::Internal, "the surface has a polygon that is not a triangle");
        std::array<vtkIdType, 3> t{};
        for (int c = 0; c < 3; ++c)
        {
          auto& slot = index[static_cast<std::size_t>(ids[c])];
          if (slot < 0)
            slot = used++;
          t[c] = slot;
        }
        triangles.push_back(t);
      }
      bary::Cage cage;
      cage.V.resize(used, 3);
      cage.F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
      for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
      {
        const vtkIdType q = index[static_cast<std::size_t>(p)];
        if (q < 0)
          continue;
        double x[3];
        mesh->GetPoint(p, x);
        for (int r = 0; r < 3; ++r)
          cage.V(q, r) = origin[r] + D[r][0] * x[0] + D[r][1] * x[1] + D[r][2] * x[2];
      }
      for (std::size_t t = 0; t < triangles.size(); ++t)
        for (int c = 0; c < 3; ++c)
          cage.F(static_cast<Eigen::Index>(t), c) = static_cast<int>(triangles[t][c]);
      if (bary::signed_measure(cage) < 0)
      { // a direction of negative determinant mirrors the surface: turn it outward again
        const Eigen::VectorXi second = cage.F.col(1);
        cage.F.col(1) = cage.F.col(2);
        cage.F.col(2) = second;
      }
      return cage;
    };
    auto smoothed = [&](int iterations) -> vtkSmartPointer<vtkPolyData> {
      if (iterations == 0)
        return surface;
      vtkNew<vtkWindowedSincPolyDataFilter> smooth;
      smooth->SetInputData(surface);
      smooth->SetNumberOfIterations(iterations);
      smooth->SetPassBand(this->SmoothingPassBand);
      smooth->NormalizeCoordinatesOn();
      smooth->BoundarySmoothingOff();
      smooth->FeatureEdgeSmoothingOff();
      smooth->NonManifoldSmoothingOn();
      update(smooth, "the smoothing");
      return smooth->GetOutput();
    };
    auto reduction_for = [&](vtkIdType faces, double scale) {
      if (this->TargetNumberOfFaces > 0)
      {
        const double target = scale * this->TargetNumberOfFaces;
        return faces > target ? 1.0 - target / static_cast<double>(faces) : 0.0;
      }
      return this->TargetReduction / scale;
    };
    auto decimated = [&](vtkPolyData* input, Decimation method, double reduction)
      -> vtkSmartPointer<vtkPolyData> {
      if (method == Decimation::Pro)
      {
        vtkNew<vtkDecimatePro> decimate;
        decimate->SetInputData(input);
        decimate->SetTargetReduction(reduction);
        decimate->PreserveTopologyOn();
        decimate->SplittingOff();
        decimate->BoundaryVertexDeletionOff();
        update(decimate, "the decimation");
        return decimate->GetOutput();
      }
      vtkNew<vtkQuadricDecimation> decimate;
      decimate->SetInputData(input);
      decimate->SetTargetReduction(reduction);
      decimate->VolumePreservationOn();
      update(decimate, "the decimation");
      return decimate->GetOutput();
    };

    // Smoothing, then decimation, then validation. VTK's decimations keep the topology of most
    // surfaces but not of every one (vtkDecimatePro with PreserveTopology left an edge shared
    // by four triangles on a 256^3 organ): a surface that fails the checks is replaced by the
    // next candidate, in this order: vtkDecimatePro, vtkQuadricDecimation (volume preserving),
    // both again at twice the triangles, no decimation; then all of it without smoothing.
    bary::Cage cage;
    bool valid = false;
    this->NumberOfAttempts = 0;
    this->FirstFailure.clear();
    std::vector<int> smoothings = { this->SmoothingIterations };
    if (this->SmoothingIterations > 0)
      smoothings.push_back(0);
    for (std::size_t si = 0; si < smoothings.size() && !valid; ++si)
    {
      vtkSmartPointer<vtkPolyData> smooth = smoothed(smoothings[si]);
      const vtkIdType faces = smooth->GetNumberOfPolys();
      std::vector<std::pair<Decimation, double>> candidates;
      for (double scale : { 1.0, 2.0 })
      {
        const double reduction = reduction_for(faces, scale);
        if (reduction > 0.0)
        {
          candidates.emplace_back(Decimation::Pro, reduction);
          candidates.emplace_back(Decimation::Quadric, reduction);
        }
      }
      candidates.emplace_back(Decimation::None, 0.0);
      for (const auto& [method, reduction] : candidates)
      {
        vtkSmartPointer<vtkPolyData> result =
          method == Decimation::None ? smooth : decimated(smooth, method, reduction);
        ++this->NumberOfAttempts;
        try
        {
          cage = to_cage(result);
          bary::validate_cage(cage);
        }
        catch (const Error& e)
        {
          if (this->FirstFailure.empty())
            this->FirstFailure = e.message();
          continue;
        }
        valid = true;
        this->SmoothingIterationsUsed = smoothings[si];
        this->DecimationUsed = method == Decimation::Pro ? "decimate-pro"
          : method == Decimation::Quadric                ? "quadric"
                                                         : "none";
        break;
      }
    }
    if (!valid)
      throw Error(ErrorCode::InvalidCage,
        "the surface of the label failed BaryLab's surface checks, with and without smoothing "
        "and decimation (" + this->FirstFailure + ")",
        "check the label map (a label of a few voxels, or voxels that touch only at an edge or "
        "corner)");
    this->EnclosedVolume = bary::enclosed_measure(cage);

    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(cage.V.rows());
    for (Eigen::Index p = 0; p < cage.V.rows(); ++p)
      points->SetPoint(p, cage.V(p, 0), cage.V(p, 1), cage.V(p, 2));
    vtkNew<vtkCellArray> cells;
    cells->AllocateExact(cage.F.rows(), 3 * cage.F.rows());
    for (Eigen::Index t = 0; t < cage.F.rows(); ++t)
    {
      const vtkIdType ids[3] = { cage.F(t, 0), cage.F(t, 1), cage.F(t, 2) };
      cells->InsertNextCell(3, ids);
    }
    output->Initialize();
    output->SetPoints(points);
    output->SetPolys(cells);
    return 1;
  }
  VTKBARY_CATCH_ERRORS
}

void vtkBaryLabelMapSurface::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Label: " << this->Label << "\n";
  os << indent << "UseThreshold: " << this->UseThreshold << "\n";
  os << indent << "Threshold: " << this->Threshold << "\n";
  os << indent << "SmoothingIterations: " << this->SmoothingIterations << "\n";
  os << indent << "SmoothingPassBand: " << this->SmoothingPassBand << "\n";
  os << indent << "TargetNumberOfFaces: " << this->TargetNumberOfFaces << "\n";
  os << indent << "TargetReduction: " << this->TargetReduction << "\n";
  os << indent << "SmoothingIterationsUsed: " << this->SmoothingIterationsUsed << "\n";
  os << indent << "DecimationUsed: " << this->DecimationUsed << "\n";
  os << indent << "NumberOfAttempts: " << this->NumberOfAttempts << "\n";
}
