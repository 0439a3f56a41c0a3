#include "vtkBaryMEDITReader.h"

#include "vtkBaryTextParsing.h"

#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkUnstructuredGrid.h"

#include <cctype>
#include <cmath>
#include <sstream>
#include <fstream>
#include <vector>

vtkStandardNewMacro(vtkBaryMEDITReader);

namespace
{
/// Whitespace-separated tokens of a MEDIT file, `#` comments skipped, with line numbers.
class Tokens
{
public:
  explicit Tokens(std::istream& in)
    : in_(in)
  {
  }
  bool next(std::string& token)
  {
    token.clear();
    int c;
    while ((c = in_.get()) != EOF)
    {
      if (c == '\n')
        ++line_;
      if (c == '#')
      {
        while ((c = in_.get()) != EOF && c != '\n')
          ;
        ++line_;
        continue;
      }
      if (!std::isspace(c))
        break;
    }
    if (c == EOF)
      return false;
    token.push_back(static_cast<char>(c));
    while ((c = in_.peek()) != EOF && !std::isspace(c) && c != '#')
      token.push_back(static_cast<char>(in_.get()));
    return true;
  }
  long line() const { return line_; }

private:
  std::istream& in_;
  long line_ = 1;
};

/// Locale-independent number parsing (vtkbary::ParseDouble); the whole token must be a number.
bool to_number(const std::string& s, double& x)
{
  return vtkbary::ParseDouble(s, x) == vtkbary::Parsed::Ok;
}
} // namespace

vtkBaryMEDITReader::vtkBaryMEDITReader()
{
  this->SetNumberOfInputPorts(0);
}

int vtkBaryMEDITReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  std::ifstream file(this->FileName);
  if (!file)
  {
    vtkErrorMacro(<< "Cannot open '" << this->FileName << "' for reading.");
    return 0;
  }
  Tokens tokens(file);
  std::string token;
  auto error = [&](const std::string& what) {
    vtkErrorMacro(<< "'" << this->FileName << "' line " << tokens.line() << ": " << what);
    return 0;
  };
  auto read_count = [&](const char* section, long long& n) {
    double x;
    // at most 9e15 (a count beyond long long was cast: UBSan, found by libFuzzer); entries are
    // read one by one, so a count larger than the file's is a truncation error
    if (!tokens.next(token) || !to_number(token, x) || !(x >= 0 && x <= 9e15) || x != std::floor(x))
      return false;
    n = static_cast<long long>(x);
    (void)section;
    return true;
  };

  int dimension = 3;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  std::vector<vtkIdType> triangles, tets;
  std::vector<int> triangle_refs, tet_refs;
  bool any = false;
  while (tokens.next(token))
  {
    any = true;
    if (token == "MeshVersionFormatted")
    {
      if (!tokens.next(token))
        return error("missing the version number");
    }
    else if (token == "Dimension")
    {
      double d;
      if (!tokens.next(token) || !to_number(token, d) || (d != 2 && d != 3))
        return error("Dimension must be 2 or 3");
      dimension = static_cast<int>(d);
    }
    else if (token == "Vertices")
    {
      long long n;
      if (!read_count("Vertices", n))
        return error("expected the number of vertices after 'Vertices'");
      for (long long i = 0; i < n; ++i)
      {
        double x[3] = { 0, 0, 0 }, ref;
        for (int k = 0; k < dimension; ++k)
          if (!tokens.next(token) || !to_number(token, x[k]))
            return error("vertex " + std::to_string(i + 1) + " of " + std::to_string(n) +
              " is truncated or not a number");
        if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
        {
          this->SetErrorCode(vtkbary::NonFiniteErrorCode);
          return error("vertex " + std::to_string(i + 1) + " has a non-finite coordinate");
        }
        if (!tokens.next(token) || !to_number(token, ref))
          return error("vertex " + std::to_string(i + 1) + " has no reference number");
        points->InsertNextPoint(x);
      }
    }
    else if (token == "Triangles" || token == "Tetrahedra" || token == "Edges" ||
      token == "Quadrilaterals" || token == "Corners" || token == "Ridges" ||
      token == "RequiredVertices")
    {
      const std::string section = token;
      const int corners = section == "Triangles" ? 3
        : section == "Tetrahedra"                ? 4
        : section == "Edges"                     ? 2
        : section == "Quadrilaterals"            ? 4
                                                 : 0;
      const int per_line = corners > 0 ? corners + 1 : 1; // + reference
      long long n;
      if (!read_count(section.c_str(), n))
        return error("expected the number of entries after '" + section + "'");
      for (long long e = 0; e < n; ++e)
      {
        vtkIdType ids[4];
        double value = 0;
        for (int k = 0; k < per_line; ++k)
        {
          if (!tokens.next(token) || !to_number(token, value))
            return error(section + " entry " + std::to_string(e + 1) + " of " +
              std::to_string(n) + " is truncated");
          if (k < corners)
          {
            // written so that NaN fails too (every comparison with NaN is false)
            if (!(value >= 1 && value <= points->GetNumberOfPoints() && value == std::floor(value)))
            {
              std::ostringstream text;
              text << section << " entry " << e + 1 << " refers to vertex " << value
                   << " but there are " << points->GetNumberOfPoints()
                   << " vertices (indices are whole numbers from 1)";
              return error(text.str());
            }
            ids[k] = static_cast<vtkIdType>(value) - 1;
          }
        }
        // the reference (region) number is an int in the format: checked before the cast (a
        // 1e68 was cast to int: UBSan, found by libFuzzer)
        if (corners > 0 && !(value == std::floor(value) && value >= -2147483648.0 && value <= 2147483647.0))
        {
          std::ostringstream text;
          text << section << " entry " << e + 1 << " has reference number " << value
               << ", not a whole number that fits an int";
          return error(text.str());
        }
        if (section == "Triangles")
        {
          triangles.insert(triangles.end(), ids, ids + 3);
          triangle_refs.push_back(static_cast<int>(value));
        }
        else if (section == "Tetrahedra")
        {
          tets.insert(tets.end(), ids, ids + 4);
          tet_refs.push_back(static_cast<int>(value));
        }
      }
    }
    else if (token == "End")
      break;
    else
      return error("unknown keyword '" + vtkbary::Printable(token) + "' (is this a MEDIT .mesh file?)");
  }
  if (!any)
    return error("the file is empty");

  output->SetPoints(points);
  const bool volume = !tets.empty();
  const std::vector<vtkIdType>& cells = volume ? tets : triangles;
  const std::vector<int>& refs = volume ? tet_refs : triangle_refs;
  const int corners = volume ? 4 : 3;
  output->Allocate(static_cast<vtkIdType>(refs.size()));
  for (std::size_t c = 0; c < refs.size(); ++c)
    output->InsertNextCell(volume ? VTK_TETRA : VTK_TRIANGLE, corners, &cells[c * corners]);
  vtkNew<vtkIntArray> reference;
  reference->SetName("Reference");
  reference->SetNumberOfTuples(static_cast<vtkIdType>(refs.size()));
  for (std::size_t c = 0; c < refs.size(); ++c)
    reference->SetValue(static_cast<vtkIdType>(c), refs[c]);
  output->GetCellData()->AddArray(reference);
  return 1;
}

void vtkBaryMEDITReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}
