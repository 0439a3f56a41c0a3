#include "vtkBaryOFFReader.h"

#include "vtkBaryTextParsing.h"

#include "vtkCellArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkBaryOFFReader);

namespace
{
/// Line reader that skips blank lines and `#` comments and counts lines for messages.
struct LineReader
{
  std::istream& in;
  long line = 0;
  bool next(std::istringstream& out)
  {
    std::string s;
    while (std::getline(in, s))
    {
      ++line;
      const auto hash = s.find('#');
      if (hash != std::string::npos)
        s.erase(hash);
      if (s.find_first_not_of(" \t\r") == std::string::npos)
        continue;
      out.clear();
      out.str(s);
      return true;
    }
    return false;
  }
};
} // namespace

vtkBaryOFFReader::vtkBaryOFFReader()
{
  this->SetNumberOfInputPorts(0);
}

int vtkBaryOFFReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (this->FileName.empty())
  {
    vtkErrorMacro(<< "No file name set.");
    return 0;
  }
  std::ifstream file(this->FileName);
  if (!file)
  {
    vtkErrorMacro(<< "Cannot open '" << this->FileName << "' for reading.");
    return 0;
  }
  LineReader reader{ file };
  std::istringstream line;
  auto error = [&](const std::string& what) {
    vtkErrorMacro(<< "'" << this->FileName << "' line " << reader.line << ": " << what);
    return 0;
  };
  if (!reader.next(line))
    return error("the file is empty");

  std::string first;
  line >> first;
  bool colors = false, normals = false;
  if (first.size() >= 3 && first.compare(first.size() - 3, 3, "OFF") == 0)
  {
    const std::string prefix = first.substr(0, first.size() - 3);
    for (char c : prefix)
    {
      if (c == 'C')
        colors = true;
      else if (c == 'N')
        normals = true;
      else if (c != 'S' && c != 'T')
        return error("unsupported OFF variant '" + first + "'");
    }
    if (!(line >> std::ws).eof())
    {
      // counts on the header line ("OFF 8 6 0")
    }
    else if (!reader.next(line))
      return error("missing the vertex/face counts line");
  }
  else
  {
    line.clear();
    line.str(line.str()); // no header: this line already holds the counts
    line.seekg(0);
  }
  long long nv = -1, nf = -1;
  if (!(line >> nv >> nf) || nv < 0 || nf < 0)
    return error("expected 'number_of_vertices number_of_faces [number_of_edges]' (is this an OFF file?)");

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  // Grow as vertices are read: the counts line is not trusted for allocation (a corrupt count
  // must give the truncation error below, not std::bad_alloc).
  points->Allocate(static_cast<vtkIdType>(std::min<long long>(nv, 1LL << 20)));
  for (long long i = 0; i < nv; ++i)
  {
    if (!reader.next(line))
      return error("the file ends after " + std::to_string(i) + " of " + std::to_string(nv) +
        " vertices");
    // tokens parsed by vtkbary::ParseDouble (locale-independent, accepts "nan"/"inf", which
    // operator>> fails on and would report as a missing coordinate)
    double x[3];
    for (int k = 0; k < 3; ++k)
    {
      std::string token;
      if (!(line >> token))
        return error("vertex " + std::to_string(i) + " does not have three coordinates");
      switch (vtkbary::ParseDouble(token, x[k]))
      {
        case vtkbary::Parsed::OutOfRange:
          this->SetErrorCode(vtkbary::NonFiniteErrorCode);
          return error("vertex " + std::to_string(i) + ": '" + vtkbary::Printable(token) +
            "' is beyond the range of double precision (1.8e308)");
        case vtkbary::Parsed::NotANumber:
          return error("vertex " + std::to_string(i) + ": '" + vtkbary::Printable(token) +
            "' is not a number");
        case vtkbary::Parsed::Ok:
          break;
      }
    }
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
    {
      this->SetErrorCode(vtkbary::NonFiniteErrorCode);
      return error("vertex " + std::to_string(i) + " has a non-finite coordinate (NaN or inf)");
    }
    points->InsertNextPoint(x);
  }
  (void)colors;
  (void)normals;
  vtkNew<vtkCellArray> polys, lines;
  std::vector<vtkIdType> ids;
  for (long long f = 0; f < nf; ++f)
  {
    if (!reader.next(line))
      return error("the file ends after " + std::to_string(f) + " of " + std::to_string(nf) +
        " faces");
    long long k;
    if (!(line >> k) || k < 1)
      return error("face " + std::to_string(f) + " does not start with its vertex count");
    ids.clear();
    for (long long j = 0; j < k; ++j)
    {
      long long id;
      if (!(line >> id))
        return error("face " + std::to_string(f) + " lists fewer than " + std::to_string(k) +
          " vertex indices");
      if (id < 0 || id >= nv)
        return error("face " + std::to_string(f) + " refers to vertex " + std::to_string(id) +
          " but there are " + std::to_string(nv) + " vertices (indices are 0-based)");
      ids.push_back(static_cast<vtkIdType>(id));
    }
    if (k >= 3)
      polys->InsertNextCell(static_cast<vtkIdType>(k), ids.data());
    else if (k == 2)
      lines->InsertNextCell(2, ids.data());
  }
  output->SetPoints(points);
  if (polys->GetNumberOfCells() > 0)
    output->SetPolys(polys);
  if (lines->GetNumberOfCells() > 0)
    output->SetLines(lines);
  return 1;
}

void vtkBaryOFFReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}
