#include "vtkBaryTGFReader.h"

#include "vtkBaryTextParsing.h"

#include "vtkCellArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkBaryTGFReader);

namespace
{
/// Splits @p line into numbers (locale-independent); false if a token is not a number.
bool numbers(const std::string& line, std::vector<double>& out)
{
  out.clear();
  std::istringstream in(line);
  std::string token;
  while (in >> token)
  {
    double x;
    if (vtkbary::ParseDouble(token, x) != vtkbary::Parsed::Ok)
      return false;
    out.push_back(x);
  }
  return true;
}
} // namespace

vtkBaryTGFReader::vtkBaryTGFReader()
{
  this->SetNumberOfInputPorts(0);
}

int vtkBaryTGFReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  std::ifstream file(this->FileName);
  if (!file)
  {
    vtkErrorMacro(<< "Cannot open '" << this->FileName << "' for reading.");
    return 0;
  }
  long number = 0;
  auto error = [&](const std::string& what) {
    vtkErrorMacro(<< "'" << this->FileName << "' line " << number << ": " << what);
    return 0;
  };
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  std::vector<std::pair<vtkIdType, vtkIdType>> bones;
  int section = 0; // 0 vertices, 1 edges, 2 ignored
  std::string line;
  std::vector<double> v;
  while (std::getline(file, line))
  {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos)
      continue;
    if (line.find('#') != std::string::npos)
    {
      ++section;
      continue;
    }
    if (section >= 2)
      continue;
    if (!numbers(line, v))
      return error("expected numbers, got '" + vtkbary::Printable(line, 60) + "' (is this a .tgf skeleton?)");
    if (section == 0)
    {
      if (v.size() < 4)
        return error("a vertex line needs an index and three coordinates");
      if (!std::isfinite(v[1]) || !std::isfinite(v[2]) || !std::isfinite(v[3]))
      {
        this->SetErrorCode(vtkbary::NonFiniteErrorCode);
        return error("vertex coordinate is not finite (NaN or inf)");
      }
      points->InsertNextPoint(v[1], v[2], v[3]);
    }
    else
    {
      if (v.size() < 2)
        return error("an edge line needs two vertex indices");
      const vtkIdType n = points->GetNumberOfPoints();
      // written so that NaN fails too (every comparison with NaN is false)
      const auto vertex = [n](double i) { return i >= 1 && i <= n && i == std::floor(i); };
      if (!vertex(v[0]) || !vertex(v[1]) || v[0] == v[1])
      {
        std::ostringstream edge;
        edge << "edge (" << v[0] << ", " << v[1] << ") does not join two of the " << n
             << " vertices (indices are whole numbers from 1)";
        return error(edge.str());
      }
      bones.emplace_back(static_cast<vtkIdType>(v[0]) - 1, static_cast<vtkIdType>(v[1]) - 1);
    }
  }
  if (points->GetNumberOfPoints() == 0)
    return error("no vertices");
  std::vector<char> on_bone(static_cast<std::size_t>(points->GetNumberOfPoints()), 0);
  vtkNew<vtkCellArray> lines, verts;
  for (const auto& [a, b] : bones)
  {
    const vtkIdType ids[2] = { a, b };
    lines->InsertNextCell(2, ids);
    on_bone[static_cast<std::size_t>(a)] = on_bone[static_cast<std::size_t>(b)] = 1;
  }
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
    if (!on_bone[static_cast<std::size_t>(i)])
      verts->InsertNextCell(1, &i);
  output->SetPoints(points);
  output->SetLines(lines);
  output->SetVerts(verts);
  return 1;
}

void vtkBaryTGFReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}
