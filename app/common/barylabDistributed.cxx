#include "barylabDistributed.h"

#include "vtkBaryDataIO.h"
#include "vtkBaryErrorObserver.h"

#include "core/common/error.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataSetAttributes.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkMultiProcessController.h"
#include "vtkMultiProcessStream.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLPPolyDataReader.h"
#include "vtkXMLPPolyDataWriter.h"
#include "vtkXMLPUnstructuredGridReader.h"
#include "vtkXMLPUnstructuredGridWriter.h"
#ifdef BARYLAB_HAVE_MPI
#include "vtkMPIController.h"
#endif

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <vector>

namespace barylab
{
namespace
{
bool collective_failure_here = false; // this process rethrew the lowest failure (Collective)

vtkMultiProcessController* controller()
{
  vtkMultiProcessController* c = vtkMultiProcessController::GetGlobalController();
  return c && c->GetNumberOfProcesses() > 1 ? c : nullptr;
}

int launcher_size()
{
  for (const char* name : { "OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE" })
    if (const char* value = std::getenv(name))
      return std::atoi(value);
  return 0;
}

std::string lower_extension(const std::string& path)
{
  std::string ext = vtkBaryDataIO::Extension(path);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

/// The process owning each point of @p whole: K slabs of (nearly) equal counts along the
/// longest side of its bounding box (points ordered by that coordinate, ties by id; NaN
/// coordinates as 0, for the readers refuse them anyway), so that a piece's cells bring few
/// points of other pieces.
std::vector<int> slab_owners(vtkDataSet* whole, int K)
{
  const vtkIdType n = whole->GetNumberOfPoints();
  double b[6];
  whole->GetBounds(b);
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (b[2 * k + 1] - b[2 * k] > b[2 * axis + 1] - b[2 * axis])
      axis = k;
  // the K - 1 quantiles by selection (O(n log K), not a sort): (coordinate, id) pairs order
  // every point uniquely, so the slabs do not depend on the file's point order within ties
  std::vector<std::pair<double, vtkIdType>> keys(static_cast<std::size_t>(n));
  for (vtkIdType p = 0; p < n; ++p)
  {
    const double x = whole->GetPoint(p)[axis];
    keys[static_cast<std::size_t>(p)] = { std::isnan(x) ? 0.0 : x, p };
  }
  std::vector<int> owners(static_cast<std::size_t>(n), 0);
  auto begin = keys.begin();
  for (int r = 1; r < K; ++r)
  {
    auto at = keys.begin() + static_cast<std::ptrdiff_t>((static_cast<vtkIdType>(r) * n) / K);
    std::nth_element(begin, at, keys.end());
    for (auto it = begin; it != at; ++it)
      owners[static_cast<std::size_t>(it->second)] = r - 1;
    begin = at;
  }
  for (auto it = begin; it != keys.end(); ++it)
    owners[static_cast<std::size_t>(it->second)] = K - 1;
  return owners;
}

/// Piece @p rank of @p K of @p whole (see ReadPiece).
template <class DataSet>
vtkSmartPointer<vtkDataSet> split(DataSet* whole, int rank, int K)
{
  const vtkIdType n = whole->GetNumberOfPoints();
  const std::vector<int> owners = slab_owners(whole, K);
  const auto owner = [&owners](vtkIdType p) { return owners[static_cast<std::size_t>(p)]; };
  std::vector<vtkIdType> local(static_cast<std::size_t>(n), -1);
  std::vector<vtkIdType> global; // local -> global point id
  for (vtkIdType p = 0; p < n; ++p)
    if (owner(p) == rank)
    {
      local[static_cast<std::size_t>(p)] = static_cast<vtkIdType>(global.size());
      global.push_back(p);
    }
  const vtkIdType owned = static_cast<vtkIdType>(global.size());
  std::vector<vtkIdType> cells;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < whole->GetNumberOfCells(); ++c)
  {
    whole->GetCellPoints(c, ids);
    if (ids->GetNumberOfIds() == 0 || owner(ids->GetId(0)) != rank)
      continue;
    if (whole->GetCellType(c) == VTK_POLYHEDRON)
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "cell " + std::to_string(c) + " is a polyhedron: a distributed run cannot split it "
        "(write the model as a .pvtu of pieces, or run on one process)");
    cells.push_back(c);
  }
  // the points of the piece's cells that other processes own, in increasing id order
  std::vector<vtkIdType> extra;
  for (vtkIdType c : cells)
  {
    whole->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      const vtkIdType p = ids->GetId(k);
      if (local[static_cast<std::size_t>(p)] < 0)
      {
        local[static_cast<std::size_t>(p)] = -2; // marked; numbered below
        extra.push_back(p);
      }
    }
  }
  std::sort(extra.begin(), extra.end());
  for (vtkIdType p : extra)
  {
    local[static_cast<std::size_t>(p)] = static_cast<vtkIdType>(global.size());
    global.push_back(p);
  }
  vtkSmartPointer<DataSet> piece = vtkSmartPointer<DataSet>::New();
  vtkNew<vtkPoints> points;
  points->SetDataType(whole->GetPoints()->GetDataType());
  points->SetNumberOfPoints(static_cast<vtkIdType>(global.size()));
  vtkPointData* in_pd = whole->GetPointData();
  vtkPointData* out_pd = piece->GetPointData();
  out_pd->CopyAllocate(in_pd, static_cast<vtkIdType>(global.size()));
  vtkNew<vtkIdTypeArray> global_ids;
  global_ids->SetName("GlobalPointIds");
  global_ids->SetNumberOfTuples(static_cast<vtkIdType>(global.size()));
  vtkNew<vtkUnsignedCharArray> ghosts;
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  ghosts->SetNumberOfTuples(static_cast<vtkIdType>(global.size()));
  for (vtkIdType i = 0; i < static_cast<vtkIdType>(global.size()); ++i)
  {
    const vtkIdType p = global[static_cast<std::size_t>(i)];
    points->SetPoint(i, whole->GetPoint(p));
    out_pd->CopyData(in_pd, p, i);
    global_ids->SetValue(i, p);
    ghosts->SetValue(i, i < owned ? 0 : vtkDataSetAttributes::DUPLICATEPOINT);
  }
  piece->SetPoints(points);
  out_pd->SetGlobalIds(global_ids);
  out_pd->AddArray(ghosts);
  piece->AllocateEstimate(static_cast<vtkIdType>(cells.size()), 4);
  vtkCellData* in_cd = whole->GetCellData();
  vtkCellData* out_cd = piece->GetCellData();
  out_cd->CopyAllocate(in_cd, static_cast<vtkIdType>(cells.size()));
  std::vector<vtkIdType> corner;
  for (vtkIdType c : cells)
  {
    whole->GetCellPoints(c, ids);
    corner.resize(static_cast<std::size_t>(ids->GetNumberOfIds()));
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      corner[static_cast<std::size_t>(k)] = local[static_cast<std::size_t>(ids->GetId(k))];
    const vtkIdType id = piece->InsertNextCell(
      whole->GetCellType(c), static_cast<vtkIdType>(corner.size()), corner.data());
    out_cd->CopyData(in_cd, c, id);
  }
  piece->GetFieldData()->ShallowCopy(whole->GetFieldData());
  return piece;
}

template <class Reader>
vtkSmartPointer<vtkDataSet> read_pieces(const std::string& path, int rank, int K)
{
  vtkNew<Reader> reader;
  if (!reader->CanReadFile(path.c_str()))
    throw bary::Error(bary::ErrorCode::Io, "cannot read '" + path + "' (missing, or not a " +
        lower_extension(path) + " file)");
  reader->SetFileName(path.c_str());
  vtkNew<vtkBaryErrorObserver> errors;
  errors->Observe(reader);
  reader->UpdatePiece(rank, K, 0);
  errors->Release();
  if (errors->HasError())
    throw bary::Error(bary::ErrorCode::Io, "cannot read '" + path + "': " + errors->GetFirstError());
  vtkSmartPointer<vtkDataSet> out;
  out.TakeReference(vtkDataSet::SafeDownCast(reader->GetOutputDataObject(0)->NewInstance()));
  out->ShallowCopy(reader->GetOutputDataObject(0));
  return out;
}

template <class Writer>
void write_pieces(vtkDataSet* piece, const std::string& path, int rank, int K)
{
  vtkNew<Writer> writer;
  writer->SetInputData(piece);
  writer->SetFileName(path.c_str());
  writer->SetNumberOfPieces(K);
  writer->SetStartPiece(rank);
  writer->SetEndPiece(rank);
  writer->SetController(controller());
  // on for every process (the default): the writer gathers the pieces' flags and process 0
  // alone writes the summary
  writer->SetDataModeToAppended(); // as vtkBaryDataIO::Write: raw appended data, LZ4
  writer->EncodeAppendedDataOff();
  writer->SetCompressorTypeToLZ4();
  vtkNew<vtkBaryErrorObserver> errors;
  errors->Observe(writer);
  const int ok = writer->Write();
  errors->Release();
  if (!ok || errors->HasError())
    throw bary::Error(bary::ErrorCode::Io,
      "cannot write '" + path + "'" + (errors->HasError() ? ": " + errors->GetFirstError() : ""));
}

/// <dir>/<name>_<rank>.<ext>: the piece file VTK's parallel XML writers make for @p path.
std::string piece_file(const std::string& path, int rank)
{
  const std::string ext = lower_extension(path); // ".pvtp"
  const std::string stem = path.substr(0, path.size() - ext.size());
  return stem + "_" + std::to_string(rank) + "." + ext.substr(2);
}
} // namespace

DistributedSession::DistributedSession(int* argc, char*** argv)
{
  if (launcher_size() <= 1)
    return;
#ifdef BARYLAB_HAVE_MPI
  vtkMPIController* mpi = vtkMPIController::New();
  mpi->Initialize(argc, argv);
  vtkMultiProcessController::SetGlobalController(mpi);
  this->Controller = mpi;
#else
  (void)argc;
  (void)argv;
  this->Missing = true;
#endif
}

DistributedSession::~DistributedSession()
{
  if (!this->Controller)
    return;
  this->Controller->Finalize();
  vtkMultiProcessController::SetGlobalController(nullptr);
  this->Controller->Delete();
}

int ProcessRank()
{
  vtkMultiProcessController* c = controller();
  return c ? c->GetLocalProcessId() : 0;
}

int ProcessCount()
{
  vtkMultiProcessController* c = controller();
  return c ? c->GetNumberOfProcesses() : 1;
}

void Collective(const std::function<void()>& step)
{
  vtkMultiProcessController* c = controller();
  if (!c)
  {
    step();
    return;
  }
  std::exception_ptr failure;
  try
  {
    step();
  }
  catch (...)
  {
    failure = std::current_exception();
  }
  // the lowest failing rank, or K when none failed
  const int mine = failure ? c->GetLocalProcessId() : c->GetNumberOfProcesses();
  int lowest = mine;
  c->AllReduce(&mine, &lowest, 1, vtkCommunicator::MIN_OP);
  if (failure && lowest == mine)
  {
    collective_failure_here = true;
    std::rethrow_exception(failure);
  } // the lowest failing process reports its error
  if (lowest < c->GetNumberOfProcesses())
    throw PeerFailure("stopped: process " + std::to_string(lowest) + " failed (its error above)");
}

bool IsParallelFile(const std::string& path)
{
  const std::string ext = lower_extension(path);
  return ext == ".pvtp" || ext == ".pvtu";
}

vtkSmartPointer<vtkDataSet> ReadPiece(const std::string& path)
{
  const int rank = ProcessRank(), K = ProcessCount();
  const std::string ext = lower_extension(path);
  if (ext == ".pvtp")
    return read_pieces<vtkXMLPPolyDataReader>(path, rank, K);
  if (ext == ".pvtu")
    return read_pieces<vtkXMLPUnstructuredGridReader>(path, rank, K);
  return SplitPiece(vtkBaryDataIO::Read(path));
}

vtkSmartPointer<vtkDataSet> SplitPiece(vtkDataSet* whole)
{
  const int rank = ProcessRank(), K = ProcessCount();
  if (K == 1)
    return whole;
  if (auto* poly = vtkPolyData::SafeDownCast(whole))
    return split(poly, rank, K);
  if (auto* grid = vtkUnstructuredGrid::SafeDownCast(whole))
    return split(grid, rank, K);
  throw bary::Error(bary::ErrorCode::InvalidArgument,
    std::string("the model is a ") + whole->GetClassName() +
      ": a distributed run splits polygonal data and unstructured grids only");
}

vtkSmartPointer<vtkDataSet> GatherPointArrays(vtkDataSet* whole, vtkDataSet* piece)
{
  vtkMultiProcessController* c = controller();
  if (!c)
    return piece;
  vtkSmartPointer<vtkDataSet> owned = OwnedPoints(piece);
  vtkDataArray* my_ids = owned->GetPointData()->GetArray("GlobalPointIds");
  if (!my_ids)
    throw bary::Error(bary::ErrorCode::Internal, "the piece has no GlobalPointIds");
  vtkNew<vtkIdTypeArray> ids, mine_ids;
  mine_ids->DeepCopy(my_ids);
  c->AllGatherV(mine_ids, ids);
  const vtkIdType n = whole->GetNumberOfPoints();
  if (ids->GetNumberOfTuples() != n)
    throw bary::Error(bary::ErrorCode::Internal,
      "gathered " + std::to_string(ids->GetNumberOfTuples()) + " points for " +
        std::to_string(n) + " (the pieces are not a split of the model)");
  vtkSmartPointer<vtkDataSet> out;
  out.TakeReference(whole->NewInstance());
  out->ShallowCopy(whole);
  // the same arrays on every process (the same filters ran on every piece)
  for (int k = 0; k < owned->GetPointData()->GetNumberOfArrays(); ++k)
  {
    vtkDataArray* mine = owned->GetPointData()->GetArray(k);
    if (!mine || !mine->GetName() || whole->GetPointData()->HasArray(mine->GetName()) ||
      std::string(mine->GetName()) == "GlobalPointIds" ||
      std::string(mine->GetName()) == vtkDataSetAttributes::GhostArrayName())
      continue;
    vtkSmartPointer<vtkDataArray> gathered, all;
    gathered.TakeReference(mine->NewInstance());
    gathered->SetNumberOfComponents(mine->GetNumberOfComponents());
    c->AllGatherV(mine, gathered);
    all.TakeReference(mine->NewInstance());
    all->SetName(mine->GetName());
    all->SetNumberOfComponents(mine->GetNumberOfComponents());
    all->CopyComponentNames(mine);
    if (mine->HasInformation())
      all->CopyInformation(mine->GetInformation(), /*deep=*/1);
    all->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i)
      all->SetTuple(ids->GetValue(i), i, gathered);
    out->GetPointData()->AddArray(all);
  }
  for (int k = 0; k < piece->GetFieldData()->GetNumberOfArrays(); ++k)
    out->GetFieldData()->AddArray(piece->GetFieldData()->GetAbstractArray(k));
  return out;
}

vtkSmartPointer<vtkDataSet> OwnedPoints(vtkDataSet* piece)
{
  vtkUnsignedCharArray* ghosts = piece->GetPointGhostArray();
  if (!ghosts)
    return piece;
  std::vector<vtkIdType> owned;
  for (vtkIdType i = 0; i < piece->GetNumberOfPoints(); ++i)
    if (!(ghosts->GetValue(i) & vtkDataSetAttributes::DUPLICATEPOINT))
      owned.push_back(i);
  if (static_cast<vtkIdType>(owned.size()) == piece->GetNumberOfPoints())
    return piece;
  vtkNew<vtkPolyData> out;
  vtkNew<vtkPoints> points;
  points->SetNumberOfPoints(static_cast<vtkIdType>(owned.size()));
  out->GetPointData()->CopyGlobalIdsOn(); // the points' ids in the whole (GatherPointArray)
  out->GetPointData()->CopyAllocate(piece->GetPointData(), static_cast<vtkIdType>(owned.size()));
  for (std::size_t k = 0; k < owned.size(); ++k)
  {
    points->SetPoint(static_cast<vtkIdType>(k), piece->GetPoint(owned[k]));
    out->GetPointData()->CopyData(piece->GetPointData(), owned[k], static_cast<vtkIdType>(k));
  }
  out->SetPoints(points);
  out->GetFieldData()->ShallowCopy(piece->GetFieldData());
  return out;
}

namespace
{
/// A parallel XML file holds pieces of one type: .pvtp vtkPolyData, .pvtu vtkUnstructuredGrid.
void check_piece_type(vtkDataSet* piece, const std::string& path)
{
  const std::string ext = lower_extension(path);
  const bool poly = vtkPolyData::SafeDownCast(piece) != nullptr;
  const bool grid = vtkUnstructuredGrid::SafeDownCast(piece) != nullptr;
  // the same decision on every process: the extension and the data type (the same filters)
  if (!(ext == ".pvtp" && poly) && !(ext == ".pvtu" && grid))
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "'" + path + "': " +
        (ProcessCount() > 1
            ? "a distributed run writes VTK's parallel XML files, one piece per process: "
            : "") +
        "give the output a ." + (poly ? "pvtp" : grid ? "pvtu" : "vtk") + " name (the data is a " +
        piece->GetClassName() + ")");
}
} // namespace

void CheckWritableData(vtkDataSet* data, const std::string& path)
{
  if (IsParallelFile(path))
    check_piece_type(data, path);
  else
    vtkBaryDataIO::CheckWritable(data, path);
}

void WriteData(vtkDataSet* data, const std::string& path)
{
  if (IsParallelFile(path))
    WritePiece(data, path);
  else
    vtkBaryDataIO::Write(data, path);
}

std::string ProcessLabel()
{
  return Distributed() ? " (process " + std::to_string(ProcessRank()) + " of " +
      std::to_string(ProcessCount()) + ")"
                       : std::string();
}

bool ReportsErrors()
{
  return !Distributed() || collective_failure_here || ProcessRank() == 0;
}

nlohmann::json PointCounts(
  vtkDataSet* owned, const std::string& weights_name, const std::string& location_name)
{
  long long where[3] = { 0, 0, 0 }, undefined = 0;
  vtkDataArray* location = owned->GetPointData()->GetArray(location_name.c_str());
  vtkDataArray* weights = owned->GetPointData()->GetArray(weights_name.c_str());
  for (vtkIdType i = 0; i < owned->GetNumberOfPoints(); ++i)
  {
    if (location)
    {
      const int k = static_cast<int>(location->GetComponent(i, 0));
      if (k >= 0 && k < 3)
        ++where[k];
    }
    if (weights)
      for (int j = 0; j < weights->GetNumberOfComponents(); ++j)
        if (std::isnan(weights->GetComponent(i, j)))
        {
          ++undefined;
          break;
        }
  }
  return { { "count", owned->GetNumberOfPoints() }, { "inside", where[0] },
    { "outside", where[1] }, { "on_cage", where[2] }, { "undefined", undefined } };
}

void WritePiece(vtkDataSet* piece, const std::string& path)
{
  const int rank = ProcessRank(), K = ProcessCount();
  check_piece_type(piece, path);
  const bool poly = vtkPolyData::SafeDownCast(piece) != nullptr;
  try
  {
    Collective([&]() {
      if (poly)
        write_pieces<vtkXMLPPolyDataWriter>(piece, path, rank, K);
      else
        write_pieces<vtkXMLPUnstructuredGridWriter>(piece, path, rank, K);
    });
  }
  catch (...)
  { // no partial results: every process removes what it wrote
    std::remove(piece_file(path, rank).c_str());
    if (rank == 0)
      std::remove(path.c_str());
    throw;
  }
}

nlohmann::json CombineSummaries(const nlohmann::json& mine)
{
  vtkMultiProcessController* c = controller();
  if (!c)
    return mine;
  vtkMultiProcessStream send;
  send << mine.dump();
  std::vector<vtkMultiProcessStream> received;
  c->Gather(send, received, 0);
  if (c->GetLocalProcessId() != 0)
    return nlohmann::json::object();
  std::vector<nlohmann::json> parts;
  for (vtkMultiProcessStream& stream : received)
  {
    std::string text;
    stream >> text;
    parts.push_back(nlohmann::json::parse(text));
  }
  nlohmann::json all = parts.front();
  all["processes"] = static_cast<int>(parts.size());
  const auto add = [&](const nlohmann::json::json_pointer& key) {
    long long sum = 0;
    for (const auto& p : parts)
      if (p.contains(key))
        sum += p.at(key).get<long long>();
    if (all.contains(key))
      all[key] = sum;
  };
  const auto extreme = [&](const nlohmann::json::json_pointer& key, bool largest) {
    for (const auto& p : parts)
      if (p.contains(key) && all.contains(key) && p.at(key).is_number())
      {
        const double v = p.at(key).get<double>(), a = all[key].get<double>();
        all[key] = largest ? std::max(a, v) : std::min(a, v);
      }
  };
  const auto mean = [&](const nlohmann::json::json_pointer& key, const nlohmann::json::json_pointer& weight) {
    double sum = 0, total = 0;
    for (const auto& p : parts)
      if (p.contains(key) && p.contains(weight) && p.at(key).is_number())
      {
        const double w = p.at(weight).get<double>();
        sum += w * p.at(key).get<double>();
        total += w;
      }
    if (all.contains(key) && total > 0)
      all[key] = sum / total;
  };
  using ptr = nlohmann::json::json_pointer;
  if (all.contains("points") && all["points"].is_number_integer())
    add(ptr("/points"));
  for (const char* key : { "/points/count", "/points/inside", "/points/outside", "/points/on_cage",
         "/points/undefined", "/statistics/points", "/statistics/negative_weights",
         "/statistics/non_finite_rows" })
    add(ptr(key));
  for (const char* key : { "/seconds", "/statistics/max_weight",
         "/statistics/partition_of_unity/max_error", "/statistics/reproduction/max_error",
         "/statistics/significant/max_per_point" })
    extreme(ptr(key), true);
  extreme(ptr("/statistics/min_weight"), false);
  for (const char* key : { "/statistics/partition_of_unity/mean_error",
         "/statistics/reproduction/mean_error", "/statistics/significant/mean_per_point" })
    mean(ptr(key), ptr("/statistics/points"));
  if (all.contains(ptr("/statistics/significant/histogram")))
  {
    std::vector<long long> histogram;
    for (const auto& p : parts)
    {
      const auto h = p.at(ptr("/statistics/significant/histogram")).get<std::vector<long long>>();
      histogram.resize(std::max(histogram.size(), h.size()), 0);
      for (std::size_t k = 0; k < h.size(); ++k)
        histogram[k] += h[k];
    }
    all[ptr("/statistics/significant/histogram")] = histogram;
  }
  return all;
}

} // namespace barylab
