#pragma once
/// @file filters_test_utils.h
/// Helpers shared by the filter tests: an error observer, data lookup through
/// BARYLAB_DATA_DIR, and small cages built in code (the [-1, 1]^3 cube of data/bad/, the
/// gingerbread polygon of data/cage2d.obj).

#include "vtkBaryDataIO.h"

#include "vtkAlgorithm.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkExecutive.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

namespace barylab_test
{

/// Records the ErrorEvent and WarningEvent messages of every object it observes instead of
/// letting VTK print them. Attach() observes an algorithm and its executive (which emits the
/// "returned failure for request" follow-up error).
class ErrorObserver : public vtkCommand
{
public:
  static ErrorObserver* New() { return new ErrorObserver; }
  vtkTypeMacro(ErrorObserver, vtkCommand);

  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    const std::string message = data ? static_cast<const char*>(data) : "";
    if (event == vtkCommand::ErrorEvent)
      this->Errors.push_back(message);
    else if (event == vtkCommand::WarningEvent)
      this->Warnings.push_back(message);
  }

  void Attach(vtkAlgorithm* algorithm)
  {
    algorithm->AddObserver(vtkCommand::ErrorEvent, this);
    algorithm->AddObserver(vtkCommand::WarningEvent, this);
    algorithm->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, this);
    algorithm->GetExecutive()->AddObserver(vtkCommand::WarningEvent, this);
  }

  /// True if some error message contains @p text.
  bool HasError(const std::string& text) const { return Contains(this->Errors, text); }
  bool HasWarning(const std::string& text) const { return Contains(this->Warnings, text); }
  /// All errors, one per line, for assertion messages.
  std::string AllErrors() const { return Join(this->Errors); }
  std::string AllWarnings() const { return Join(this->Warnings); }
  void Clear()
  {
    this->Errors.clear();
    this->Warnings.clear();
  }

  std::vector<std::string> Errors;
  std::vector<std::string> Warnings;

private:
  static bool Contains(const std::vector<std::string>& list, const std::string& text)
  {
    for (const auto& m : list)
      if (m.find(text) != std::string::npos)
        return true;
    return false;
  }
  static std::string Join(const std::vector<std::string>& list)
  {
    std::string all;
    for (const auto& m : list)
      all += m + "\n";
    return all.empty() ? "(none)" : all;
  }
};

/// Runs the algorithm's pipeline; returns what the executive reports (1 success, 0 failure).
inline int RunPipeline(vtkAlgorithm* algorithm)
{
  return algorithm->GetExecutive()->Update();
}

/// Absolute path of a file in the repository's data/ folder.
inline std::string DataPath(const std::string& name)
{
  return std::string(BARYLAB_DATA_DIR) + "/" + name;
}

/// A data file read through vtkBaryDataIO (fails the test if it throws).
inline vtkSmartPointer<vtkPolyData> ReadData(const std::string& name)
{
  vtkSmartPointer<vtkPolyData> data;
  try
  {
    data = vtkBaryDataIO::ReadPolyData(DataPath(name));
  }
  catch (const std::exception& e)
  {
    ADD_FAILURE() << "reading " << name << ": " << e.what();
  }
  return data;
}

/// Points with no cells.
inline vtkSmartPointer<vtkPolyData> MakePointCloud(const std::vector<std::array<double, 3>>& xs)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const auto& x : xs)
    points->InsertNextPoint(x.data());
  auto cloud = vtkSmartPointer<vtkPolyData>::New();
  cloud->SetPoints(points);
  return cloud;
}

/// A copy of the points of @p data (as doubles) with no cells.
inline vtkSmartPointer<vtkPolyData> PointsOnly(vtkDataSet* data)
{
  std::vector<std::array<double, 3>> xs(static_cast<std::size_t>(data->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
    data->GetPoint(i, xs[static_cast<std::size_t>(i)].data());
  return MakePointCloud(xs);
}

/// The cube [-s, s]^3 (times @p s), corners in the order of data/README.md
/// (---, +--, ++-, -+-, --+, +-+, +++, -++), 12 outward triangles.
inline vtkSmartPointer<vtkPolyData> MakeCube(double s = 1.0)
{
  const double corners[8][3] = { { -1, -1, -1 }, { 1, -1, -1 }, { 1, 1, -1 }, { -1, 1, -1 },
    { -1, -1, 1 }, { 1, -1, 1 }, { 1, 1, 1 }, { -1, 1, 1 } };
  static const vtkIdType faces[12][3] = { { 0, 3, 2 }, { 0, 2, 1 }, { 4, 5, 6 }, { 4, 6, 7 },
    { 0, 1, 5 }, { 0, 5, 4 }, { 1, 2, 6 }, { 1, 6, 5 }, { 2, 3, 7 }, { 2, 7, 6 }, { 3, 0, 4 },
    { 3, 4, 7 } };
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const auto& c : corners)
    points->InsertNextPoint(s * c[0], s * c[1], s * c[2]);
  vtkNew<vtkCellArray> polys;
  for (const auto& f : faces)
    polys->InsertNextCell(3, f);
  auto cube = vtkSmartPointer<vtkPolyData>::New();
  cube->SetPoints(points);
  cube->SetPolys(polys);
  return cube;
}

/// The weights array of @p data (nullptr if absent).
inline vtkDataArray* GetWeights(vtkDataSet* data, const char* name = "Weights")
{
  return data ? data->GetPointData()->GetArray(name) : nullptr;
}

} // namespace barylab_test
