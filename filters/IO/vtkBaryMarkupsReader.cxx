#include "vtkBaryMarkupsReader.h"

#include "vtkBaryTextParsing.h"

#include "vtkCellArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkBaryMarkupsReader);

// a named namespace: the module is compiled in unity batches, where the helpers of another file's
// anonymous namespace (lower, trim, ...) would clash
namespace vtkbary_mrk_read
{
struct ControlPoint
{
  std::array<double, 3> x{};
  std::string label, id, description;
};

/// A problem with the file: the message (starting with the quoted file name) and whether it is
/// a non-finite coordinate.
struct ReadError
{
  std::string message;
  bool nonFinite = false;
};

std::string lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string trim(const std::string& s)
{
  const std::size_t begin = s.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos)
    return std::string();
  const std::size_t end = s.find_last_not_of(" \t\r\n");
  return s.substr(begin, end - begin + 1);
}

bool ends_with(const std::string& s, const std::string& suffix)
{
  return s.size() >= suffix.size() &&
    s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// "RAS"/"0" -> true, "LPS"/"1" -> false; anything else is refused by the caller.
enum class Space
{
  LPS,
  RAS,
  Unknown
};

Space space_from(const std::string& text, bool numeric)
{
  const std::string t = lower(trim(text));
  if (t == "lps" || (numeric && t == "1"))
    return Space::LPS;
  if (t == "ras" || (numeric && t == "0"))
    return Space::RAS;
  return Space::Unknown;
}

/// A JSON value as text for a label or an id ("" for null or absent).
std::string text_of(const nlohmann::json& object, const char* key)
{
  const auto it = object.find(key);
  if (it == object.end() || it->is_null())
    return std::string();
  return it->is_string() ? it->get<std::string>() : it->dump();
}

std::string named(std::size_t index, const std::string& label)
{
  return "control point " + std::to_string(index) +
    (label.empty() ? std::string() : " ('" + vtkbary::Printable(label, 40) + "')");
}

std::vector<ControlPoint> read_json(const std::string& path)
{
  const std::string file = "'" + path + "'";
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ReadError{ file + " cannot be opened for reading" };
  nlohmann::json root;
  try
  {
    root = nlohmann::json::parse(in);
  }
  catch (const nlohmann::json::exception& e)
  {
    std::string what = e.what();
    const std::size_t bracket = what.find("] ");
    if (what.rfind("[json.exception", 0) == 0 && bracket != std::string::npos)
      what = what.substr(bracket + 2);
    throw ReadError{ file + " is not valid JSON: " + vtkbary::Printable(what, 200) };
  }
  if (!root.is_object())
    throw ReadError{ file + " is not a markups file: its JSON is not an object with a "
                            "\"markups\" list (3D Slicer's .mrk.json)" };
  const auto markups = root.find("markups");
  if (markups == root.end() || !markups->is_array())
    throw ReadError{ file + " is not a markups file: it has no \"markups\" list (3D Slicer's "
                            ".mrk.json)" };
  if (markups->empty())
    throw ReadError{ file + " holds no markups (its \"markups\" list is empty)" };
  std::vector<ControlPoint> points;
  for (std::size_t m = 0; m < markups->size(); ++m)
  {
    const nlohmann::json& markup = (*markups)[m];
    const std::string where = file + " markup " + std::to_string(m);
    if (!markup.is_object())
      throw ReadError{ where + " is not a JSON object" };
    Space space = Space::LPS; // the schema's default
    const auto system = markup.find("coordinateSystem");
    if (system != markup.end())
    {
      space = system->is_string() ? space_from(system->get<std::string>(), false) : Space::Unknown;
      if (space == Space::Unknown)
        throw ReadError{ where + ": unknown coordinate system " + system->dump() +
          " (\"LPS\" or \"RAS\")" };
    }
    const auto units = markup.find("coordinateUnits");
    if (units != markup.end() && !(units->is_string() && units->get<std::string>() == "mm"))
      throw ReadError{ where + ": coordinate units " + units->dump() +
        " are not read (BaryLab reads markups in millimetres, \"mm\")" };
    const auto controls = markup.find("controlPoints");
    if (controls == markup.end() || controls->is_null())
      continue;
    if (!controls->is_array())
      throw ReadError{ where + ": \"controlPoints\" is not a list" };
    for (const nlohmann::json& point : *controls)
    {
      ControlPoint c;
      if (!point.is_object())
        throw ReadError{ where + ", " + named(points.size(), "") + " is not a JSON object" };
      c.label = text_of(point, "label");
      c.id = text_of(point, "id");
      c.description = text_of(point, "description");
      const std::string at = where + ", " + named(points.size(), c.label);
      const auto status = point.find("positionStatus");
      if (status != point.end() &&
        !(status->is_string() && status->get<std::string>() == "defined"))
        throw ReadError{ at + ": its positionStatus is " + status->dump() +
          ", not \"defined\" (place the point in 3D Slicer or delete it: skipping it would shift "
          "the order in which control points are matched)" };
      const auto position = point.find("position");
      if (position == point.end() || position->is_null())
        throw ReadError{ at + " has no position" };
      if (!position->is_array() || position->size() != 3 ||
        !std::all_of(position->begin(), position->end(),
          [](const nlohmann::json& v) { return v.is_number(); }))
        throw ReadError{ at + ": its position " + vtkbary::Printable(position->dump(), 60) +
          " is not three numbers" };
      for (int k = 0; k < 3; ++k)
        c.x[k] = (*position)[k].get<double>();
      if (!std::isfinite(c.x[0]) || !std::isfinite(c.x[1]) || !std::isfinite(c.x[2]))
        throw ReadError{ at + ": its position is not finite (NaN or infinity)", true };
      if (space == Space::RAS)
      {
        c.x[0] = -c.x[0];
        c.x[1] = -c.x[1];
      }
      points.push_back(std::move(c));
    }
  }
  if (points.empty())
    throw ReadError{ file + " holds no control points" };
  return points;
}

/// One CSV row's fields ("" quoting as in RFC 4180); false for an unterminated quote.
bool split_csv(const std::string& line, std::vector<std::string>& fields)
{
  fields.assign(1, std::string());
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i)
  {
    const char c = line[i];
    if (quoted)
    {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"')
      {
        fields.back() += '"';
        ++i;
      }
      else if (c == '"')
        quoted = false;
      else
        fields.back() += c;
    }
    else if (c == '"')
      quoted = true;
    else if (c == ',')
      fields.emplace_back();
    else
      fields.back() += c;
  }
  return !quoted;
}

std::vector<ControlPoint> read_fcsv(const std::string& path)
{
  const std::string file = "'" + path + "'";
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ReadError{ file + " cannot be opened for reading" };
  Space space = Space::RAS; // Slicer's assumption for files without the header
  // column indices of id, x, y, z, label, desc (-1: absent)
  std::array<long, 6> column = { 0, 1, 2, 3, 11, 12 };
  std::vector<ControlPoint> points;
  std::vector<std::string> fields;
  std::string line;
  for (long number = 1; std::getline(in, line); ++number)
  {
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    const std::string at = file + " line " + std::to_string(number);
    if (trim(line).empty())
      continue;
    if (line[0] == '#')
    {
      const std::size_t eq = line.find('=');
      if (eq == std::string::npos)
        continue;
      const std::string key = lower(trim(line.substr(1, eq - 1)));
      const std::string value = trim(line.substr(eq + 1));
      if (key == "coordinatesystem")
      {
        space = space_from(value, true);
        if (space == Space::Unknown)
          throw ReadError{ at + ": unknown coordinate system '" + vtkbary::Printable(value) +
            "' (LPS, RAS, 0 for RAS or 1 for LPS)" };
      }
      else if (key == "columns")
      {
        std::vector<std::string> names;
        if (!split_csv(value, names))
          throw ReadError{ at + ": an unterminated quote in the columns header" };
        const char* const wanted[6] = { "id", "x", "y", "z", "label", "desc" };
        for (int k = 0; k < 6; ++k)
        {
          column[k] = -1;
          for (std::size_t c = 0; c < names.size(); ++c)
            if (lower(trim(names[c])) == wanted[k])
              column[k] = static_cast<long>(c);
        }
        if (column[1] < 0 || column[2] < 0 || column[3] < 0)
          throw ReadError{ at + ": the columns header '" + vtkbary::Printable(value, 80) +
            "' does not name x, y and z" };
      }
      continue;
    }
    if (!split_csv(line, fields))
      throw ReadError{ at + ": an unterminated quote" };
    ControlPoint c;
    const auto field = [&](int k) {
      return column[k] >= 0 && column[k] < static_cast<long>(fields.size())
        ? fields[static_cast<std::size_t>(column[k])]
        : std::string();
    };
    const long needed = std::max({ column[1], column[2], column[3] }) + 1;
    c.label = field(4);
    if (static_cast<long>(fields.size()) < needed)
      throw ReadError{ at + " (" + named(points.size(), c.label) + "): " +
        std::to_string(fields.size()) + " comma-separated fields, too few for x, y and z (" +
        std::to_string(needed) + " needed)" };
    for (int k = 0; k < 3; ++k)
    {
      const std::string token = trim(field(k + 1));
      if (vtkbary::ParseDouble(token, c.x[k]) != vtkbary::Parsed::Ok)
        throw ReadError{ at + " (" + named(points.size(), c.label) + "): " + "xyz"[k] +
          " '" + vtkbary::Printable(token) + "' is not a number double precision holds" };
      if (!std::isfinite(c.x[k]))
        throw ReadError{ at + " (" + named(points.size(), c.label) + "): " + "xyz"[k] +
            " is not finite (NaN or infinity)",
          true };
    }
    if (space == Space::RAS)
    {
      c.x[0] = -c.x[0];
      c.x[1] = -c.x[1];
    }
    c.id = field(0);
    c.description = field(5);
    points.push_back(std::move(c));
  }
  if (points.empty())
    throw ReadError{ file + " holds no control points" };
  return points;
}
} // namespace vtkbary_mrk_read

vtkBaryMarkupsReader::vtkBaryMarkupsReader()
{
  this->SetNumberOfInputPorts(0);
}

bool vtkBaryMarkupsReader::IsMarkupsFile(const char* path)
{
  if (!path)
    return false;
  namespace m = vtkbary_mrk_read;
  const std::string name = m::lower(path);
  return m::ends_with(name, ".mrk.json") || m::ends_with(name, ".fcsv");
}

int vtkBaryMarkupsReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  namespace m = vtkbary_mrk_read;
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  const bool fcsv = this->Format == FCSV ||
    (this->Format == FromFileName && m::ends_with(m::lower(this->FileName), ".fcsv"));
  std::vector<m::ControlPoint> read;
  try
  {
    read = fcsv ? m::read_fcsv(this->FileName) : m::read_json(this->FileName);
  }
  catch (const m::ReadError& e)
  {
    if (e.nonFinite)
      this->SetErrorCode(vtkbary::NonFiniteErrorCode);
    vtkErrorMacro(<< e.message);
    return 0;
  }
  const auto n = static_cast<vtkIdType>(read.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  vtkNew<vtkCellArray> verts;
  vtkNew<vtkStringArray> labels, ids, descriptions;
  labels->SetName("Label");
  ids->SetName("Id");
  descriptions->SetName("Description");
  bool anyId = false, anyDescription = false;
  for (vtkIdType i = 0; i < n; ++i)
  {
    const m::ControlPoint& c = read[static_cast<std::size_t>(i)];
    points->SetPoint(i, c.x.data());
    verts->InsertNextCell(1, &i);
    labels->InsertNextValue(c.label);
    ids->InsertNextValue(c.id);
    descriptions->InsertNextValue(c.description);
    anyId = anyId || !c.id.empty();
    anyDescription = anyDescription || !c.description.empty();
  }
  output->SetPoints(points);
  output->SetVerts(verts);
  output->GetPointData()->AddArray(labels);
  if (anyId)
    output->GetPointData()->AddArray(ids);
  if (anyDescription)
    output->GetPointData()->AddArray(descriptions);
  return 1;
}

void vtkBaryMarkupsReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
  os << indent << "Format: " << this->Format << "\n";
}
