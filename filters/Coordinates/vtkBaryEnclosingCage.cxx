#include "vtkBaryEnclosingCage.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"

#include "core/common/error.h"
#include "core/meshing/enclosing_cage.h"

#include "vtkCellArray.h"
#include "vtkCellTypes.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkBaryEnclosingCage);

namespace
{
using bary::Error;
using bary::ErrorCode;

/// The model as core sees it: triangles (3D or 2D), or in 2D the sides of its polygons and
/// lines as segments (also the sides of triangles when other polygons are present). Bare
/// points in a plane, with no cells, are a closed polygon in point order.
void ToModel(vtkPolyData* model, Eigen::MatrixXd& V, Eigen::MatrixXi& F, double& z)
{
  const vtkIdType n = model->GetNumberOfPoints();
  if (n == 0)
    throw Error(ErrorCode::EmptyInput, "enclosing cage: the model has no points");
  double b[6];
  model->GetBounds(b);
  for (double x : b)
    if (!std::isfinite(x))
      throw Error(ErrorCode::NonFinite, "enclosing cage: the model has NaN or infinite point coordinates");
  const bool planar = b[5] - b[4] <= 1e-9 * std::max(1.0, std::max(b[1] - b[0], b[3] - b[2]));
  z = b[4];
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 2>> segments;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < model->GetNumberOfCells(); ++c)
  {
    const int type = model->GetCellType(c);
    if (type == VTK_VERTEX || type == VTK_POLY_VERTEX || type == VTK_EMPTY_CELL)
      continue;
    model->GetCellPoints(c, ids);
    const vtkIdType m = ids->GetNumberOfIds();
    const bool sides = type == VTK_POLYGON || type == VTK_QUAD || type == VTK_TRIANGLE;
    const bool lines = type == VTK_LINE || type == VTK_POLY_LINE;
    if (type == VTK_TRIANGLE)
      triangles.push_back({ int(ids->GetId(0)), int(ids->GetId(1)), int(ids->GetId(2)) });
    if ((sides && type != VTK_TRIANGLE && planar) || lines)
    {
      if (!planar)
        throw Error(ErrorCode::InvalidArgument,
          "enclosing cage: model cell " + std::to_string(c) + " is a line; lines are supported "
          "in a plane z = const (2D) only");
      for (vtkIdType k = 0; k + 1 < m + (sides ? 1 : 0); ++k)
        segments.push_back({ int(ids->GetId(k)), int(ids->GetId((k + 1) % m)) });
      continue;
    }
    if (type != VTK_TRIANGLE)
      throw Error(ErrorCode::InvalidArgument,
        "enclosing cage: model cell " + std::to_string(c) + " is a " +
          std::string(vtkCellTypes::GetClassNameFromTypeId(type)) +
          "; a 3D model must be triangles (triangulate it, e.g. vtkTriangleFilter)");
  }
  if (triangles.empty() && segments.empty() && model->GetNumberOfCells() == 0 && planar && n >= 3)
    for (vtkIdType k = 0; k < n; ++k) // bare points in order: a polygon
      segments.push_back({ int(k), int((k + 1) % n) });
  const int dim = planar ? 2 : 3;
  V = vtkBaryConversion::PointsToMatrix(model, dim);
  if (!segments.empty())
  {
    for (const auto& t : triangles)
      for (int k = 0; k < 3; ++k)
        segments.push_back({ t[k], t[(k + 1) % 3] });
    F.resize(static_cast<Eigen::Index>(segments.size()), 2);
    for (std::size_t i = 0; i < segments.size(); ++i)
      F.row(static_cast<Eigen::Index>(i)) << segments[i][0], segments[i][1];
    return;
  }
  F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t i = 0; i < triangles.size(); ++i)
    F.row(static_cast<Eigen::Index>(i)) << triangles[i][0], triangles[i][1], triangles[i][2];
}
} // namespace

int vtkBaryEnclosingCage::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

int vtkBaryEnclosingCage::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* model = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  this->SetErrorCode(0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  this->MarginUsed = this->VolumeRatio = this->ModelMeasure = this->CageMeasure = nan;
  this->MaximumDistance = this->MeanDistance = this->Diagonal = nan;
  this->Seconds = 0.0;
  this->OffsetVertices = this->Collapses = this->TightenMoves = 0;
  this->StopReason.clear();
  this->ReachedTarget = false;
  if (!model)
  {
    vtkErrorMacro(<< "No model: connect a vtkPolyData to input port 0.");
    return 0;
  }
  try
  {
    Eigen::MatrixXd V;
    Eigen::MatrixXi F;
    double z = 0.0;
    ToModel(model, V, F, z);
    bary::EnclosingCageOptions options;
    options.target_vertices = this->NumberOfVertices;
    options.margin = this->Margin;
    options.margin_fraction = this->MarginFraction;
    options.resolution = this->Resolution;
    options.tighten_rounds = this->TightenRounds;
    options.clearance = this->Clearance;
    auto progress = [this](double f) {
      this->UpdateProgress(f);
      return !this->GetAbortExecute();
    };
    const bary::EnclosingCageResult r = bary::enclosing_cage(V, F, options, progress);
    const bary::Cage& cage = r.cage;
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(cage.V.rows());
    for (Eigen::Index i = 0; i < cage.V.rows(); ++i)
      points->SetPoint(i, cage.V(i, 0), cage.V(i, 1), cage.dimension() == 3 ? cage.V(i, 2) : z);
    vtkNew<vtkCellArray> cells;
    if (cage.dimension() == 3)
      for (Eigen::Index f = 0; f < cage.F.rows(); ++f)
      {
        const vtkIdType t[3] = { cage.F(f, 0), cage.F(f, 1), cage.F(f, 2) };
        cells->InsertNextCell(3, t);
      }
    else
    {
      std::vector<vtkIdType> loop(static_cast<std::size_t>(cage.V.rows()));
      for (std::size_t i = 0; i < loop.size(); ++i)
        loop[i] = static_cast<vtkIdType>(i);
      cells->InsertNextCell(static_cast<vtkIdType>(loop.size()), loop.data());
    }
    vtkNew<vtkPolyData> result;
    result->SetPoints(points);
    result->SetPolys(cells);
    output->ShallowCopy(result);
    this->MarginUsed = r.margin;
    this->OffsetVertices = r.offset_vertices;
    this->ReachedTarget = r.reached_target;
    this->VolumeRatio = r.measure_ratio;
    this->ModelMeasure = r.model_measure;
    this->CageMeasure = r.cage_measure;
    this->MaximumDistance = r.max_distance;
    this->MeanDistance = r.mean_distance;
    this->Diagonal = r.diagonal;
    this->Seconds = r.seconds;
    this->Collapses = r.collapses;
    this->TightenMoves = r.tighten_moves;
    this->StopReason = r.stop_reason;
    if (!r.reached_target)
      vtkWarningMacro(<< "The cage has " << cage.V.rows() << " vertices, not "
                      << this->NumberOfVertices << ": " << r.stop_reason << ".");
  }
  VTKBARY_CATCH_ERRORS
  return 1;
}

void vtkBaryEnclosingCage::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfVertices: " << this->NumberOfVertices << "\n";
  os << indent << "Margin: " << this->Margin << "\n";
  os << indent << "MarginFraction: " << this->MarginFraction << "\n";
  os << indent << "Resolution: " << this->Resolution << "\n";
  os << indent << "TightenRounds: " << this->TightenRounds << "\n";
  os << indent << "Clearance: " << this->Clearance << "\n";
}
