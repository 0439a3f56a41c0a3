#pragma once
/// @file barylabDistributed.h
/// Distributed runs of the command line (`mpirun -np K barylab weights|deform|animate`) on
/// VTK's parallel pipeline: starting MPI and VTK's global controller, this process's piece of a
/// model, VTK's parallel XML files, and the collective agreement that turns one process's error
/// into a failure of all (no process waits forever on a collective the failed one never
/// reaches). The algorithms' share (one solve per cage, sent to all) is vtkBaryCoordinates'.

#include <nlohmann/json.hpp>

#include "vtkSmartPointer.h"

#include <functional>
#include <stdexcept>
#include <string>

class vtkDataSet;
class vtkMultiProcessController;

namespace barylab
{

/// Starts MPI and sets it as VTK's global controller when the program was launched by an MPI
/// launcher (mpirun / mpiexec set OMPI_COMM_WORLD_SIZE or PMI_SIZE) with more than one process;
/// otherwise does nothing (a serial run does not initialise MPI). Finalises on destruction.
class DistributedSession
{
public:
  DistributedSession(int* argc, char*** argv);
  ~DistributedSession();
  DistributedSession(const DistributedSession&) = delete;
  DistributedSession& operator=(const DistributedSession&) = delete;
  /// True when the program was started by an MPI launcher but this build has no MPI.
  bool MissingMPI() const { return this->Missing; }

private:
  vtkMultiProcessController* Controller = nullptr;
  bool Missing = false;
};

/// This process's rank and the number of processes (0 and 1 in a serial run).
int ProcessRank();
int ProcessCount();
inline bool Distributed() { return ProcessCount() > 1; }

/// Thrown on the processes that did not fail when another did (Collective): the failing
/// process reports the error, the others stop with this (exit code 1, one short line).
struct PeerFailure : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/// Runs @p step on every process, then agrees: when @p step threw on some process, the lowest
/// such process rethrows its error (the one line the user sees) and every other process throws
/// PeerFailure naming it. Serial runs just run @p step.
void Collective(const std::function<void()>& step);

/// True for the parallel XML file names (.pvtp, .pvtu).
bool IsParallelFile(const std::string& path);

/// This process's piece of the model in @p path. A .pvtp / .pvtu is read by pieces (VTK's
/// parallel XML readers, each process reads only its own pieces). Any other file is read whole
/// on every process and split: point p belongs to process floor(p K / n) (contiguous ranges),
/// each cell to the process of its first point, and a piece holds its own points first, then
/// the points of its cells that other processes own, flagged as duplicates in vtkGhostType
/// (VTK's ghost convention), with the point array "GlobalPointIds" (the point's index in the
/// file; the piece's global ids). Serial: the file as vtkBaryDataIO reads it.
/// @throws bary::Error for unreadable files and data sets that cannot be split (not
///   vtkPolyData / vtkUnstructuredGrid, polyhedron cells)
vtkSmartPointer<vtkDataSet> ReadPiece(const std::string& path);

/// @p whole (vtkPolyData or vtkUnstructuredGrid) split as ReadPiece splits a file: this
/// process's piece (@p whole itself in a serial run).
vtkSmartPointer<vtkDataSet> SplitPiece(vtkDataSet* whole);

/// @p whole with the point arrays that the filters added to the split pieces (SplitPiece; each
/// process's @p piece) gathered from the owned points of every process, in the whole's point
/// order, on every process, and the piece's field data. Collective. Serial: @p piece.
vtkSmartPointer<vtkDataSet> GatherPointArrays(vtkDataSet* whole, vtkDataSet* piece);

/// The points of @p piece that this process owns (not flagged as duplicate points in
/// vtkGhostType), with their point data: @p piece itself when it has no such flags.
vtkSmartPointer<vtkDataSet> OwnedPoints(vtkDataSet* piece);

/// The "points" block of a weights summary for @p owned (OwnedPoints of a weighted piece):
/// count, inside / outside / on_cage from the location array, undefined (rows of the weights
/// array with a NaN).
nlohmann::json PointCounts(vtkDataSet* owned, const std::string& weights_name,
  const std::string& location_name = "CageLocation");

/// Writes this process's @p piece of @p path (.pvtp for vtkPolyData, .pvtu for
/// vtkUnstructuredGrid): piece files <name>_<rank>.vtp / .vtu beside it, the summary file by
/// process 0. Collective; on any process's failure every process removes what it wrote.
/// A serial run writes one piece. @throws bary::Error(Io)
void WritePiece(vtkDataSet* piece, const std::string& path);

/// Writes @p data to @p path: WritePiece for .pvtp / .pvtu, else vtkBaryDataIO::Write.
void WriteData(vtkDataSet* data, const std::string& path);

/// Throws what WriteData(@p data, @p path) would for the pair's formats (a .pvtp / .pvtu of
/// the wrong type, a surface-only format for a volume mesh, an unknown extension) without
/// writing: commands call it with the data set their result copies before computing.
void CheckWritableData(vtkDataSet* data, const std::string& path);

/// True when this process reports an error the command line caught: every error in a serial
/// run; in a distributed run the lowest failing process's (Collective), or process 0's for
/// errors before any collective step (the same on every process: the same command line).
bool ReportsErrors();

/// " (process r of K)" in a distributed run (point ids in its messages are the piece's),
/// empty in a serial one.
std::string ProcessLabel();

/// The pieces' summaries (ComputeWeights' JSON, "points" from PointCounts, WeightStatisticsJson
/// of the owned points under "statistics") combined on process 0: counts added, extremes kept,
/// means weighted by points, the longest time; "processes": K. Collective. Other processes get
/// an empty object; a serial run gets @p mine.
nlohmann::json CombineSummaries(const nlohmann::json& mine);

} // namespace barylab
