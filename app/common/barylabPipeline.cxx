#include "barylabPipeline.h"

#include "vtkBaryCageDeformation.h"
#include "vtkBaryCageMesher.h"
#include "vtkBaryConversion.h"
#include "vtkBaryCoordinates.h"
#include "vtkBaryMixedHandles.h"
#include "vtkBaryErrorObserver.h"
#include "vtkBaryDataIO.h"
#include "vtkBaryLinearBlendSkinning.h"
#include "vtkBaryLocalityStatistics.h"
#include "vtkBaryReduceWeights.h"
#include "vtkBaryWeightStatistics.h"


#include "vtkAppendPolyData.h"
#include "vtkCallbackCommand.h"
#include "vtkCellData.h"
#include "vtkContourFilter.h"
#include "vtkGenericCell.h"
#include "vtkGradientFilter.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkFieldData.h"
#include "vtkPoints.h"
#include "vtkTable.h"
#include "vtkVariant.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace barylab
{
namespace
{
/// Forwards progress to the callbacks and applies cancellation.
class ProgressObserver : public vtkCommand
{
public:
  static ProgressObserver* New() { return new ProgressObserver; }
  void Execute(vtkObject* caller, unsigned long, void* data) override
  {
    if (Callbacks->progress && data)
      Callbacks->progress(*static_cast<double*>(data));
    if (Callbacks->cancel && Callbacks->cancel())
      if (auto* a = vtkAlgorithm::SafeDownCast(caller))
        a->SetAbortExecute(1);
  }
  const RunCallbacks* Callbacks = nullptr;
};

double seconds_since(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
} // namespace

void RunAlgorithm(vtkAlgorithm* algorithm, const RunCallbacks& callbacks, bary::ErrorCode code)
{
  vtkNew<vtkBaryErrorObserver> errors;
  errors->WarningCallback = callbacks.warning;
  errors->Observe(algorithm);
  vtkNew<ProgressObserver> progress;
  progress->Callbacks = &callbacks;
  const unsigned long tag = algorithm->AddObserver(vtkCommand::ProgressEvent, progress);
  algorithm->SetAbortExecute(0);
  algorithm->Update();
  const bool aborted = algorithm->GetAbortExecute() != 0;
  algorithm->RemoveObserver(tag);
  errors->Release();
  if (errors->HasError())
    throw bary::Error(vtkBaryConversion::ErrorCodeOf(algorithm->GetErrorCode(), code),
      errors->GetFirstError());
  if (aborted)
    throw bary::Error(bary::ErrorCode::Cancelled, "the computation was cancelled");
}

std::string MethodName(const WeightsParameters& parameters)
{
  return bary::method_info(parameters.method).name;
}

bool IsPointBasedMethod(bary::MethodId method)
{
  return bary::method_info(method).controls == bary::ControlKind::FreePoints;
}

namespace
{
/// The method and settings of @p p on @p filter's weight method (ranges checked: the filters
/// clamp silently, the parameter object must not), and the array name.
template <class Filter>
void Configure(Filter* filter, const WeightsParameters& p)
{
  vtkBaryWeightMethod* method = filter->GetWeightMethod();
  method->SetSettings(p);
  if (p.user_weights.empty())
    method->SetUserWeights(nullptr);
  else
  {
    vtkNew<vtkDoubleArray> s;
    s->SetName("UserWeights");
    s->SetNumberOfTuples(static_cast<vtkIdType>(p.user_weights.size()));
    for (std::size_t i = 0; i < p.user_weights.size(); ++i)
      s->SetValue(static_cast<vtkIdType>(i), p.user_weights[i]);
    method->SetUserWeights(s);
  }
  filter->SetWeightsArrayName(p.weights_name.c_str());
}
} // namespace

vtkSmartPointer<vtkUnstructuredGrid> MeshCage(vtkPolyData* cage, vtkPointSet* points,
  const MeshParameters& parameters, const RunCallbacks& callbacks, nlohmann::json* summary)
{
  vtkNew<vtkBaryCageMesher> mesher;
  mesher->SetCageDimension(parameters.cage_dimension);
  mesher->SetTargetNumberOfCells(parameters.target_cells);
  mesher->SetMaximumCellSize(parameters.max_cell_size);
  mesher->SetMinimumAngle(parameters.min_angle);
  mesher->SetRadiusEdgeRatio(parameters.radius_edge_ratio);
  mesher->SetPreserveBoundary(parameters.preserve_boundary);
  mesher->SetCageData(cage);
  if (points)
    mesher->SetPointsData(points);
  const auto t0 = std::chrono::steady_clock::now();
  RunAlgorithm(mesher, callbacks, bary::ErrorCode::InvalidCage);
  vtkSmartPointer<vtkUnstructuredGrid> grid = mesher->GetOutput();
  if (summary)
  {
    (*summary)["vertices"] = grid->GetNumberOfPoints();
    (*summary)["cells"] = grid->GetNumberOfCells();
    (*summary)["skipped_points"] = mesher->GetNumberOfSkippedPoints();
    (*summary)["seconds"] = seconds_since(t0);
  }
  return grid;
}

int CageDimension(vtkPolyData* cage, int requested)
{
  return vtkBaryConversion::ToCage(cage, requested).Cage.dimension();
}

vtkSmartPointer<vtkDataSet> ComputeWeights(vtkDataSet* points, vtkPolyData* cage,
  const WeightsParameters& parameters, const RunCallbacks& callbacks, nlohmann::json* summary,
  vtkDataSet* domain)
{
  vtkNew<vtkBaryCoordinates> filter;
  Configure(filter.Get(), parameters);
  filter->SetInputData(0, points);
  filter->SetCageData(cage);
  if (domain)
    filter->SetDomainData(domain);
  const auto t0 = std::chrono::steady_clock::now();
  RunAlgorithm(filter, callbacks, bary::ErrorCode::InvalidCage);
  const double elapsed = seconds_since(t0);
  vtkSmartPointer<vtkDataSet> out = vtkDataSet::SafeDownCast(filter->GetOutputDataObject(0));
  if (summary)
  {
    (*summary)["method"] = MethodName(parameters);
    const bool mixed = parameters.method == bary::MethodId::BBW &&
      vtkBaryMixedHandles::UsesMixedHandles(cage, domain);
    if (mixed || filter->GetWeightMethod()->IsSkeleton(cage, domain))
    {
      const int dim = vtkBaryConversion::DomainDimension(domain);
      const bary::Skeleton s = vtkBaryMixedHandles::ToHandles(cage, dim);
      const auto vertex_regions =
        static_cast<bary::Index>(vtkBaryMixedHandles::RegionVertices(domain).size());
      (*summary)["handles"] = { { "dimension", dim },
        { "count", s.handle_count() + vertex_regions }, { "point_handles", s.P.size() },
        { "bones", s.BE.rows() }, { "cage_vertices", s.cage_joints().size() },
        { "regions", static_cast<bary::Index>(s.regions.size()) + vertex_regions },
        { "joints", s.C.rows() },
        { "shape_preservation",
          domain->GetPointData()->GetArray(vtkBaryMixedHandles::ShapePreservationArrayName()) !=
            nullptr } };
    }
    else if (IsPointBasedMethod(parameters.method))
    {
      const vtkBaryCage c = vtkBaryConversion::ToControlPoints(cage, parameters.cage_dimension);
      (*summary)["cage"] = { { "dimension", c.Cage.dimension() },
        { "control_points", c.Cage.num_controls() }, { "faces", 0 }, { "free_points", true } };
    }
    else
    {
      const vtkBaryCage c = vtkBaryConversion::ToCage(cage, parameters.cage_dimension);
      (*summary)["cage"] = { { "dimension", c.Cage.dimension() },
        { "control_points", c.Cage.num_controls() }, { "faces", c.Cage.F.rows() } };
    }
    if (filter->GetNumberOfStatistics() > 0)
    {
      nlohmann::json solver = nlohmann::json::object();
      for (int i = 0; i < filter->GetNumberOfStatistics(); ++i)
        solver[filter->GetStatisticName(i)] = filter->GetStatisticValue(i);
      (*summary)["solver"] = solver;
    }
    (*summary)["points"] = { { "count", points->GetNumberOfPoints() },
      { "inside", filter->GetNumberOfInsidePoints() },
      { "outside", filter->GetNumberOfOutsidePoints() },
      { "on_cage", filter->GetNumberOfBoundaryPoints() },
      { "undefined", filter->GetNumberOfUndefinedPoints() } };
    (*summary)["weights_array"] = parameters.weights_name;
    // control points the method added (celestial hull points): the weights' last columns
    if (vtkDataArray* added = out && out->GetFieldData()
          ? out->GetFieldData()->GetArray("AddedControlPoints")
          : nullptr)
    {
      nlohmann::json list = nlohmann::json::array();
      for (vtkIdType k = 0; k < added->GetNumberOfTuples(); ++k)
      {
        const double* x = added->GetTuple3(k);
        list.push_back({ x[0], x[1], x[2] });
      }
      (*summary)["added_control_points"] = list;
    }
    (*summary)["seconds"] = elapsed;
  }
  return out;
}

namespace
{
/// Bare points: @p points, then the tuples of @p added (a method's added control points).
vtkSmartPointer<vtkPolyData> with_added_controls(vtkPoints* points, vtkDataArray* added)
{
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> all;
  all->SetDataTypeToDouble();
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
    all->InsertNextPoint(points->GetPoint(i));
  for (vtkIdType k = 0; k < added->GetNumberOfTuples(); ++k)
    all->InsertNextPoint(added->GetTuple3(k));
  poly->SetPoints(all);
  return poly;
}
} // namespace

vtkSmartPointer<vtkPointSet> Deform(vtkPointSet* model, vtkPolyData* rest_cage,
  vtkPointSet* posed_cage, const WeightsParameters& parameters, const RunCallbacks& callbacks,
  nlohmann::json* summary)
{
  // Free control points: weights first, so that the hull points the method may add are known.
  vtkSmartPointer<vtkPointSet> weighted = model;
  if (model && rest_cage && IsPointBasedMethod(parameters.method) &&
    !vtkBaryConversion::FindPointArray(model, parameters.weights_name) &&
    !model->GetPointData()->GetArray((parameters.weights_name + "Indices").c_str()))
    weighted = vtkPointSet::SafeDownCast(ComputeWeights(model, rest_cage, parameters, callbacks));
  // The added control points (celestial hull points) stay where they are: appended to the
  // rest and the posed controls, matching the weights' last columns.
  vtkSmartPointer<vtkPolyData> rest = rest_cage;
  vtkSmartPointer<vtkPointSet> posed = posed_cage;
  vtkDataArray* added = weighted && weighted->GetFieldData()
    ? weighted->GetFieldData()->GetArray("AddedControlPoints")
    : nullptr;
  vtkDataArray* given = weighted ? vtkBaryConversion::FindPointArray(weighted, parameters.weights_name) : nullptr;
  if (added && rest_cage && posed_cage && given &&
    given->GetNumberOfComponents() == rest_cage->GetNumberOfPoints() + added->GetNumberOfTuples())
  {
    rest = with_added_controls(rest_cage->GetPoints(), added);
    posed = with_added_controls(posed_cage->GetPoints(), added);
  }
  vtkNew<vtkBaryCageDeformation> filter;
  Configure(filter.Get(), parameters);
  filter->SetInputData(0, weighted);
  filter->SetRestCageData(rest);
  filter->SetDeformedCageData(posed);
  const auto t0 = std::chrono::steady_clock::now();
  RunAlgorithm(filter, callbacks, bary::ErrorCode::InvalidCage);
  if (summary)
  {
    (*summary)["method"] = MethodName(parameters);
    (*summary)["weights_computed"] = filter->GetNumberOfWeightComputations() > 0;
    (*summary)["points"] = model->GetNumberOfPoints();
    (*summary)["seconds"] = seconds_since(t0);
  }
  return filter->GetOutput();
}

vtkSmartPointer<vtkPointSet> Skin(vtkPointSet* weighted, const std::vector<Eigen::MatrixXd>& pose,
  const WeightsParameters& parameters, const RunCallbacks& callbacks, nlohmann::json* summary)
{
  vtkNew<vtkDoubleArray> transforms;
  transforms->SetName("Transforms");
  transforms->SetNumberOfComponents(12);
  transforms->SetNumberOfTuples(static_cast<vtkIdType>(pose.size()));
  for (std::size_t j = 0; j < pose.size(); ++j)
  {
    if (pose[j].rows() != 3 || pose[j].cols() != 4)
      throw bary::Error(bary::ErrorCode::SizeMismatch,
        "transform " + std::to_string(j) + " is not 3 by 4 ([A | t])");
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        transforms->SetComponent(static_cast<vtkIdType>(j), 4 * r + c, pose[j](r, c));
  }
  vtkNew<vtkBaryLinearBlendSkinning> filter;
  filter->SetInputData(weighted);
  filter->SetTransforms(transforms);
  filter->SetWeightsArrayName(parameters.weights_name.c_str());
  filter->SetNumberOfThreads(parameters.threads);
  const auto t0 = std::chrono::steady_clock::now();
  RunAlgorithm(filter, callbacks, bary::ErrorCode::InvalidArgument);
  if (summary)
  {
    (*summary)["method"] = "linear blend skinning";
    (*summary)["handles"] = pose.size();
    (*summary)["points"] = weighted->GetNumberOfPoints();
    (*summary)["seconds"] = seconds_since(t0);
  }
  return filter->GetOutput();
}

std::string WriteTimeSeries(const std::vector<vtkSmartPointer<vtkDataSet>>& frames,
  const std::string& output_dir, const std::string& prefix, double period, bool write_collection)
{
  if (frames.empty())
    throw bary::Error(bary::ErrorCode::EmptyInput, "no frames to write");
  namespace fs = std::filesystem;
  fs::create_directories(output_dir);
  std::ostringstream pvd;
  pvd << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <Collection>\n";
  for (std::size_t f = 0; f < frames.size(); ++f)
  {
    char name[64];
    std::snprintf(name, sizeof(name), "_%03zu.vtp", f);
    const std::string file = prefix + name;
    if (frames[f]) // null: another process's frame
      vtkBaryDataIO::Write(frames[f], (fs::path(output_dir) / file).string());
    pvd << "    <DataSet timestep=\"" << period * static_cast<double>(f) / static_cast<double>(frames.size())
        << "\" group=\"\" part=\"0\" file=\"" << file << "\"/>\n";
  }
  pvd << "  </Collection>\n</VTKFile>\n";
  const std::string path = (fs::path(output_dir) / (prefix + ".pvd")).string();
  if (!write_collection)
    return path;
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    out << pvd.str();
    if (!out)
      throw bary::Error(bary::ErrorCode::Io, "cannot write '" + path + "'");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw bary::Error(bary::ErrorCode::Io, "cannot write '" + path + "'");
  return path;
}

std::string WriteAnimation(vtkPointSet* weighted, vtkPolyData* rest_cage,
  const std::vector<vtkSmartPointer<vtkPointSet>>& frames, const WeightsParameters& parameters,
  const std::string& output_dir, const std::string& prefix, double period, nlohmann::json* summary,
  bool write_collection)
{
  if (frames.empty())
    throw bary::Error(bary::ErrorCode::EmptyInput, "no frames to animate");
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<vtkSmartPointer<vtkDataSet>> deformed;
  std::size_t mine = 0;
  for (const auto& frame : frames)
  {
    deformed.push_back(frame ? Deform(weighted, rest_cage, frame, parameters) : nullptr);
    mine += frame ? 1 : 0;
  }
  const std::string path = WriteTimeSeries(deformed, output_dir, prefix, period, write_collection);
  if (summary)
  {
    (*summary)["frames"] = frames.size();
    (*summary)["frames_written_here"] = mine;
    (*summary)["pvd"] = path;
    (*summary)["seconds_per_frame"] = seconds_since(t0) / static_cast<double>(std::max<std::size_t>(mine, 1));
  }
  return path;
}

nlohmann::json LocalityStatisticsJson(vtkDataSet* data, const std::string& array_name,
  double threshold, bool use_mesh_measure)
{
  vtkNew<vtkBaryLocalityStatistics> filter;
  filter->SetInputData(data);
  filter->SetWeightsArrayName(array_name.c_str());
  filter->SetThreshold(threshold);
  filter->SetUseMeshMeasure(use_mesh_measure);
  RunAlgorithm(filter, {});
  auto column = [](vtkTable* table, const char* name) {
    std::vector<double> v;
    vtkDataArray* a = vtkDataArray::SafeDownCast(table->GetColumnByName(name));
    for (vtkIdType i = 0; a && i < a->GetNumberOfTuples(); ++i)
      v.push_back(a->GetComponent(i, 0));
    return v;
  };
  nlohmann::json j;
  j["array"] = array_name;
  j["points"] = data->GetNumberOfPoints();
  j["controls"] = filter->GetInfluenceTable()->GetNumberOfRows();
  j["threshold"] = filter->GetThresholdUsed();
  j["measure"] = filter->GetMeasureUsedAsString();
  j["mean_support"] = filter->GetMeanSupport();
  j["max_support"] = filter->GetMaxSupport();
  j["t"] = column(filter->GetPTable(), "t");
  j["P"] = column(filter->GetPTable(), "P");
  std::vector<int> k;
  for (double x : column(filter->GetQTable(), "k"))
    k.push_back(static_cast<int>(x));
  j["k"] = k;
  j["Q"] = column(filter->GetQTable(), "Q");
  j["influence_fraction"] = column(filter->GetInfluenceTable(), "influence_fraction");
  return j;
}

vtkSmartPointer<vtkDataSet> ReduceWeights(vtkDataSet* weighted, vtkPolyData* cage,
  const ReduceParameters& parameters, const RunCallbacks& callbacks, nlohmann::json* summary)
{
  vtkNew<vtkBaryReduceWeights> filter;
  filter->SetInputData(weighted);
  if (cage)
    filter->SetCageData(cage);
  filter->SetWeightsArrayName(parameters.weights_name.c_str());
  filter->SetThreshold(parameters.threshold);
  if (parameters.renormalize == "none")
    filter->SetRenormalizationToNone();
  else if (parameters.renormalize == "affine")
    filter->SetRenormalizationToAffine();
  else if (parameters.renormalize == "rowsum")
    filter->SetRenormalizationToRowSum();
  else
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "unknown renormalisation '" + parameters.renormalize + "' (rowsum, affine or none)");
  filter->SetKeepDenseArray(parameters.keep_dense);
  const auto t0 = std::chrono::steady_clock::now();
  RunAlgorithm(filter, callbacks);
  if (summary)
  {
    auto finite_or_null = [](double x) {
      return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
    };
    vtkDataArray* dense = weighted->GetPointData()->GetArray(parameters.weights_name.c_str());
    (*summary)["points"] = weighted->GetNumberOfPoints();
    (*summary)["controls"] = dense ? dense->GetNumberOfComponents() : 0;
    (*summary)["threshold"] = filter->GetThresholdUsed();
    (*summary)["renormalization"] = parameters.renormalize;
    (*summary)["K"] = filter->GetMaximumSupport();
    (*summary)["nonzeros"] = filter->GetNumberOfNonzeros();
    (*summary)["mean_support"] = weighted->GetNumberOfPoints() > 0
      ? static_cast<double>(filter->GetNumberOfNonzeros()) / weighted->GetNumberOfPoints()
      : 0.0;
    (*summary)["partition_error"] = filter->GetPartitionError();
    (*summary)["reproduction_error"] = finite_or_null(filter->GetReproductionError());
    (*summary)["max_dropped"] = filter->GetMaxDropped();
    (*summary)["memory_fraction"] = filter->GetMemoryFraction();
    (*summary)["csr_memory_fraction"] = filter->GetCSRMemoryFraction();
    (*summary)["arrays"] = { parameters.weights_name + "Indices",
      parameters.weights_name + "Values" };
    (*summary)["seconds"] = seconds_since(t0);
  }
  vtkSmartPointer<vtkDataSet> out;
  out.TakeReference(vtkDataSet::SafeDownCast(filter->GetOutputDataObject(0)->NewInstance()));
  out->ShallowCopy(filter->GetOutputDataObject(0));
  return out;
}

nlohmann::json WeightStatisticsJson(vtkDataSet* data, const std::string& array_name,
  vtkPolyData* cage, double threshold, int cage_dimension)
{
  vtkNew<vtkBaryWeightStatistics> filter;
  filter->SetInputData(0, data);
  // control points the method added (celestial hull points) count as controls
  vtkDataArray* added = data && cage && data->GetFieldData()
    ? data->GetFieldData()->GetArray("AddedControlPoints")
    : nullptr;
  vtkDataArray* weights = data ? data->GetPointData()->GetArray(array_name.c_str()) : nullptr;
  vtkSmartPointer<vtkPolyData> controls = cage;
  if (added && weights && cage->GetNumberOfPolys() == 0 && cage->GetNumberOfLines() == 0 &&
    weights->GetNumberOfComponents() == cage->GetNumberOfPoints() + added->GetNumberOfTuples())
    controls = with_added_controls(cage->GetPoints(), added);
  if (controls)
    filter->SetCageData(controls);
  filter->SetWeightsArrayName(array_name.c_str());
  filter->SetThreshold(threshold);
  filter->SetCageDimension(cage_dimension);
  RunAlgorithm(filter, {}, bary::ErrorCode::InvalidArgument);
  vtkTable* figures = filter->GetOutput(0);
  const auto value = [figures](const char* name) {
    return figures->GetColumnByName(name)->GetVariantValue(0).ToDouble();
  };
  const auto count = [&value](const char* name) { return static_cast<long long>(value(name)); };
  nlohmann::json j;
  j["points"] = count("points");
  j["controls"] = count("controls");
  j["min_weight"] = value("min_weight");
  j["max_weight"] = value("max_weight");
  j["negative_weights"] = count("negative_weights");
  j["non_finite_rows"] = count("non_finite_rows");
  j["partition_of_unity"] = { { "max_error", value("max_partition_error") },
    { "mean_error", value("mean_partition_error") } };
  if (figures->GetColumnByName("max_reproduction_error"))
    j["reproduction"] = { { "max_error", value("max_reproduction_error") },
      { "mean_error", value("mean_reproduction_error") },
      { "relative_to", "cage bounding-box diagonal" } };
  // Green coordinates: reproduction of x by sum w_i c_i + sum psi_j n_j (the FaceWeights array)
  if (j.contains("reproduction") && figures->GetColumnByName("face_coefficients"))
    j["reproduction"]["face_coefficients"] = count("face_coefficients");
  // histogram of the number of significant weights per point: count -> number of points
  vtkTable* histogram = filter->GetOutput(1);
  std::vector<long long> points_with(static_cast<std::size_t>(histogram->GetNumberOfRows()));
  for (vtkIdType k = 0; k < histogram->GetNumberOfRows(); ++k)
    points_with[static_cast<std::size_t>(k)] =
      histogram->GetColumnByName("points")->GetVariantValue(k).ToLongLong();
  j["significant"] = { { "threshold", value("threshold") },
    { "mean_per_point", value("mean_significant") }, { "max_per_point", count("max_significant") },
    { "histogram", points_with } };
  return j;
}

void WriteJson(const nlohmann::json& json, const std::string& path)
{
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out)
      throw bary::Error(bary::ErrorCode::Io, "cannot write '" + path + "'");
    out << json.dump(2) << '\n';
    if (!out)
    {
      std::remove(tmp.c_str());
      throw bary::Error(bary::ErrorCode::Io, "cannot write '" + path + "' (disk full?)");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
  {
    std::remove(tmp.c_str());
    throw bary::Error(bary::ErrorCode::Io, "cannot write '" + path + "'");
  }
}

namespace
{
vtkDataArray* weights_array(vtkDataSet* data, const std::string& name)
{
  if (!data)
    throw bary::Error(bary::ErrorCode::InvalidArgument, "no dataset");
  vtkDataArray* w = vtkBaryConversion::RequirePointArray(data, name);
  for (vtkIdType p = 0; p < w->GetNumberOfTuples(); ++p)
    for (int c = 0; c < w->GetNumberOfComponents(); ++c)
      if (!std::isfinite(w->GetComponent(p, c)))
        throw bary::Error(bary::ErrorCode::NonFinite,
          "the weights of point " + std::to_string(p) + " hold NaN or infinity (weights outside "
          "the domain computed with --outside nan?)");
  return w;
}

/// Largest dimension of the cells of @p data (0 for a point cloud).
int max_cell_dimension(vtkDataSet* data)
{
  int dim = 0;
  vtkNew<vtkGenericCell> cell;
  for (vtkIdType c = 0; c < data->GetNumberOfCells() && dim < 3; ++c)
  {
    data->GetCell(c, cell);
    dim = std::max(dim, cell->GetCellDimension());
  }
  return dim;
}
} // namespace

vtkSmartPointer<vtkDataSet> WeightGradientNorms(vtkDataSet* weighted, const std::string& weights_name,
  nlohmann::json* summary)
{
  vtkDataArray* w = weights_array(weighted, weights_name);
  if (max_cell_dimension(weighted) < 2)
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "gradient norms need a mesh (triangles, polygons or 3D cells); the dataset has " +
        std::to_string(weighted->GetNumberOfCells()) +
        " cells of dimension < 2 (a point cloud has no gradient: compute the weights at the "
        "vertices of a mesh, e.g. without --points for mesh-based methods)");
  vtkNew<vtkGradientFilter> gradient;
  gradient->SetInputData(weighted);
  gradient->SetInputScalars(vtkDataObject::FIELD_ASSOCIATION_POINTS, weights_name.c_str());
  gradient->SetResultArrayName("barylab_weight_gradient");
  RunAlgorithm(gradient, {});
  vtkDataSet* out = vtkDataSet::SafeDownCast(gradient->GetOutputDataObject(0));
  vtkDataArray* g = out->GetPointData()->GetArray("barylab_weight_gradient");
  const int n = w->GetNumberOfComponents();
  auto norms = vtkSmartPointer<vtkDoubleArray>::New();
  norms->SetName((weights_name + "GradientNorm").c_str());
  norms->SetNumberOfComponents(n);
  norms->SetNumberOfTuples(weighted->GetNumberOfPoints());
  std::vector<double> max_norm(static_cast<std::size_t>(n), 0.0), sum(static_cast<std::size_t>(n), 0.0);
  for (vtkIdType p = 0; p < weighted->GetNumberOfPoints(); ++p)
    for (int i = 0; i < n; ++i)
    {
      double s = 0.0;
      for (int k = 0; k < 3; ++k)
      {
        const double v = g->GetComponent(p, 3 * i + k);
        s += v * v;
      }
      const double norm = std::sqrt(s);
      norms->SetComponent(p, i, norm);
      max_norm[static_cast<std::size_t>(i)] = std::max(max_norm[static_cast<std::size_t>(i)], norm);
      sum[static_cast<std::size_t>(i)] += norm;
    }
  auto result = vtkSmartPointer<vtkDataSet>::Take(weighted->NewInstance());
  result->ShallowCopy(weighted);
  result->GetPointData()->AddArray(norms);
  if (summary)
  {
    const double np = std::max<double>(1.0, static_cast<double>(weighted->GetNumberOfPoints()));
    std::vector<double> mean;
    for (double v : sum)
      mean.push_back(v / np);
    (*summary)["gradient_norm"] = { { "array", weights_name + "GradientNorm" },
      { "max", max_norm }, { "mean", mean } };
  }
  return result;
}

vtkSmartPointer<vtkPolyData> WeightLevelSets(vtkDataSet* weighted, int component,
  std::vector<double> levels, const std::string& weights_name)
{
  vtkDataArray* w = weights_array(weighted, weights_name);
  const int n = w->GetNumberOfComponents();
  if (component < 0 || component >= n)
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "control " + std::to_string(component) + " does not exist (the weights have " +
        std::to_string(n) + " components)");
  if (levels.empty())
    levels.push_back(1e-3 / n);
  // one scalar array: the chosen component
  auto single = vtkSmartPointer<vtkDataSet>::Take(weighted->NewInstance());
  single->CopyStructure(weighted);
  auto values = vtkSmartPointer<vtkDoubleArray>::New();
  values->SetName("weight");
  values->SetNumberOfTuples(weighted->GetNumberOfPoints());
  for (vtkIdType p = 0; p < weighted->GetNumberOfPoints(); ++p)
    values->SetValue(p, w->GetComponent(p, component));
  single->GetPointData()->SetScalars(values);
  vtkNew<vtkAppendPolyData> append;
  for (double level : levels)
  {
    if (!std::isfinite(level))
      throw bary::Error(bary::ErrorCode::NonFinite, "a level value is not finite");
    vtkNew<vtkContourFilter> contour;
    contour->SetInputData(single);
    contour->SetValue(0, level);
    contour->SetComputeScalars(true);
    RunAlgorithm(contour, {});
    auto piece = vtkSmartPointer<vtkPolyData>::New();
    piece->ShallowCopy(contour->GetOutput());
    auto tag = vtkSmartPointer<vtkDoubleArray>::New();
    tag->SetName("level");
    tag->SetNumberOfTuples(piece->GetNumberOfCells());
    tag->FillValue(level);
    piece->GetCellData()->AddArray(tag);
    append->AddInputData(piece);
  }
  RunAlgorithm(append, {});
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->ShallowCopy(append->GetOutput());
  return result;
}

} // namespace barylab
