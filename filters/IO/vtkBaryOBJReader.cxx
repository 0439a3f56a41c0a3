#include "vtkBaryOBJReader.h"

#include "vtkBaryTextParsing.h"

#include "vtkCellArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <cmath>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

vtkStandardNewMacro(vtkBaryOBJReader);

namespace
{
/// The whitespace-separated tokens of @p line (views into it).
void split(std::string_view line, std::vector<std::string_view>& tokens)
{
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size())
  {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r' ||
                                line[i] == '\f' || line[i] == '\v'))
      ++i;
    if (i == line.size())
      break;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r' &&
      line[j] != '\f' && line[j] != '\v')
      ++j;
    tokens.push_back(line.substr(i, j - i));
    i = j;
  }
}

/// One cell while the file is read: its kind and its corners as 1-based positive indices
/// (negative ones already resolved), checked against the vertex count at the end.
struct PendingCell
{
  char kind; // 'p', 'l', 'f'
  long long line;
  std::size_t first, count; // into the corner list
};
} // namespace

vtkBaryOBJReader::vtkBaryOBJReader()
{
  this->SetNumberOfInputPorts(0);
}

int vtkBaryOBJReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (this->FileName.empty())
  {
    vtkErrorMacro(<< "No file name set.");
    return 0;
  }
  std::ifstream file(this->FileName, std::ios::binary);
  if (!file)
  {
    vtkErrorMacro(<< "Cannot open '" << this->FileName << "' for reading.");
    return 0;
  }
  long long number = 0;
  auto error = [&](const std::string& what) {
    vtkErrorMacro(<< "'" << this->FileName << "' line " << number << ": " << what);
    return 0;
  };

  std::vector<double> xyz;
  std::vector<long long> corners;
  std::vector<PendingCell> cells;
  std::vector<std::string_view> tokens;
  std::string line;
  while (std::getline(file, line))
  {
    ++number;
    const std::size_t hash = line.find('#');
    split(std::string_view(line).substr(0, hash), tokens);
    if (tokens.empty())
      continue;
    const std::string_view key = tokens[0];
    if (key == "v")
    {
      if (tokens.size() < 4)
        return error("a vertex line 'v x y z' needs three coordinates, it has " +
          std::to_string(tokens.size() - 1));
      for (int k = 1; k <= 3; ++k)
      {
        double x = 0.0;
        switch (vtkbary::ParseDouble(tokens[k], x))
        {
          case vtkbary::Parsed::NotANumber:
            return error("vertex coordinate '" + vtkbary::Printable(tokens[k]) + "' is not a number");
          case vtkbary::Parsed::OutOfRange:
            this->SetErrorCode(vtkbary::NonFiniteErrorCode);
            return error("vertex coordinate '" + vtkbary::Printable(tokens[k]) +
              "' is beyond the range of double precision (1.8e308)");
          case vtkbary::Parsed::Ok:
            break;
        }
        if (!std::isfinite(x))
        {
          this->SetErrorCode(vtkbary::NonFiniteErrorCode);
          return error("vertex coordinate is not finite (NaN or inf)");
        }
        xyz.push_back(x);
      }
      for (std::size_t k = 4; k < tokens.size(); ++k)
      {
        double ignored = 0.0;
        if (vtkbary::ParseDouble(tokens[k], ignored) == vtkbary::Parsed::NotANumber)
          return error("'" + vtkbary::Printable(tokens[k]) +
            "' after a vertex's coordinates is not a number");
      }
    }
    else if (key == "f" || key == "l" || key == "p")
    {
      const char kind = key[0];
      const std::size_t least = kind == 'f' ? 3 : kind == 'l' ? 2 : 1;
      const char* what = kind == 'f' ? "face" : kind == 'l' ? "line" : "point";
      if (tokens.size() - 1 < least)
        return error(std::string("a ") + what + " needs at least " + std::to_string(least) +
          (least == 1 ? " vertex" : " vertices") + ", it has " + std::to_string(tokens.size() - 1));
      const long long known = static_cast<long long>(xyz.size() / 3);
      PendingCell cell{ kind, number, corners.size(), tokens.size() - 1 };
      for (std::size_t k = 1; k < tokens.size(); ++k)
      {
        // the vertex index is what comes before the first '/' ("7/3/2", "7//2")
        const std::string_view token = tokens[k];
        const std::string_view index = token.substr(0, token.find('/'));
        long long id = 0;
        if (!vtkbary::ParseInteger(index, id))
          return error("'" + vtkbary::Printable(token) + "' is not a vertex index (a whole number, 1-based)");
        if (id == 0)
          return error("vertex index 0: .obj indices start at 1 (negative ones count back)");
        if (id < 0)
        {
          if (id < -known)
            return error("vertex index " + std::to_string(id) + " counts back past the first vertex (" +
              std::to_string(known) + " read so far)");
          id = known + id + 1;
        }
        corners.push_back(id);
      }
      cells.push_back(cell);
    }
    // vt, vn, vp, g, o, s, usemtl, mtllib, curves ...: not read
  }
  if (file.bad())
    return error("the file could not be read to its end");

  const long long nv = static_cast<long long>(xyz.size() / 3);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(nv));
  for (long long i = 0; i < nv; ++i)
    points->SetPoint(static_cast<vtkIdType>(i), xyz.data() + 3 * i);

  vtkNew<vtkCellArray> verts, lines, polys;
  std::vector<vtkIdType> ids;
  for (const PendingCell& cell : cells)
  {
    ids.clear();
    for (std::size_t k = 0; k < cell.count; ++k)
    {
      const long long id = corners[cell.first + k];
      if (id > nv)
      {
        number = cell.line;
        return error("vertex index " + std::to_string(id) + " but the file has " +
          std::to_string(nv) + " vertices (indices are 1-based)");
      }
      ids.push_back(static_cast<vtkIdType>(id - 1));
    }
    vtkCellArray* target = cell.kind == 'f' ? polys.Get() : cell.kind == 'l' ? lines.Get() : verts.Get();
    target->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  }
  output->SetPoints(points);
  if (verts->GetNumberOfCells() > 0)
    output->SetVerts(verts);
  if (lines->GetNumberOfCells() > 0)
    output->SetLines(lines);
  if (polys->GetNumberOfCells() > 0)
    output->SetPolys(polys);
  return 1;
}

void vtkBaryOBJReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}
