#include "vtkBaryPLYReader.h"

#include "vtkBaryTextParsing.h"

#include "vtkCellArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkBaryPLYReader);

namespace
{
/// A problem, with the line it is on (header) or 0.
struct PlyError : std::runtime_error
{
  PlyError(const std::string& what, long line = 0)
    : std::runtime_error(what)
    , Line(line)
  {
  }
  long Line;
};

enum class Scalar
{
  Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64
};

bool scalar_of(const std::string& name, Scalar& s)
{
  if (name == "char" || name == "int8") s = Scalar::Int8;
  else if (name == "uchar" || name == "uint8") s = Scalar::UInt8;
  else if (name == "short" || name == "int16") s = Scalar::Int16;
  else if (name == "ushort" || name == "uint16") s = Scalar::UInt16;
  else if (name == "int" || name == "int32") s = Scalar::Int32;
  else if (name == "uint" || name == "uint32") s = Scalar::UInt32;
  else if (name == "float" || name == "float32") s = Scalar::Float32;
  else if (name == "double" || name == "float64") s = Scalar::Float64;
  else
    return false;
  return true;
}

std::size_t size_of(Scalar s)
{
  switch (s)
  {
    case Scalar::Int8: case Scalar::UInt8: return 1;
    case Scalar::Int16: case Scalar::UInt16: return 2;
    case Scalar::Int32: case Scalar::UInt32: case Scalar::Float32: return 4;
    default: return 8;
  }
}

bool is_integer(Scalar s)
{
  return s != Scalar::Float32 && s != Scalar::Float64;
}

struct Property
{
  std::string name;
  bool list = false;
  Scalar count = Scalar::UInt8; // lists
  Scalar item = Scalar::Float32;
};

struct Element
{
  std::string name;
  long long count = 0;
  long line = 0;
  std::vector<Property> properties;
};

/// The body of the file after the header: values one at a time, ASCII or binary.
class Body
{
public:
  Body(const std::string& bytes, std::size_t pos, int format)
    : bytes_(bytes)
    , pos_(pos)
    , format_(format)
  {
  }

  std::size_t left() const { return pos_ < bytes_.size() ? bytes_.size() - pos_ : 0; }

  double value(Scalar s, const std::string& what)
  {
    if (format_ == 0)
    {
      while (pos_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[pos_])))
        ++pos_;
      const std::size_t begin = pos_;
      while (pos_ < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[pos_])))
        ++pos_;
      if (begin == pos_)
        throw PlyError("the file ends inside " + what);
      const std::string_view token(bytes_.data() + begin, pos_ - begin);
      double x = 0.0;
      if (vtkbary::ParseDouble(token, x) != vtkbary::Parsed::Ok)
        throw PlyError(what + ": '" + vtkbary::Printable(token) + "' is not a number");
      if (is_integer(s) && (x != std::floor(x) || !std::isfinite(x)))
        throw PlyError(what + ": '" + vtkbary::Printable(token) + "' is not a whole number");
      return x;
    }
    const std::size_t n = size_of(s);
    if (left() < n)
      throw PlyError("the file ends inside " + what);
    unsigned char b[8];
    for (std::size_t k = 0; k < n; ++k)
      b[k] = static_cast<unsigned char>(bytes_[pos_ + (format_ == 2 ? n - 1 - k : k)]);
    pos_ += n;
    switch (s)
    {
      case Scalar::Int8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
      case Scalar::UInt8: return b[0];
      case Scalar::Int16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      case Scalar::UInt16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      case Scalar::Int32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
      case Scalar::UInt32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
      case Scalar::Float32: { float v; std::memcpy(&v, b, 4); return v; }
      default: { double v; std::memcpy(&v, b, 8); return v; }
    }
  }

private:
  const std::string& bytes_;
  std::size_t pos_;
  int format_; // 0 ascii, 1 little-endian, 2 big-endian
};
} // namespace

vtkBaryPLYReader::vtkBaryPLYReader()
{
  this->SetNumberOfInputPorts(0);
}

int vtkBaryPLYReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  std::ifstream file(this->FileName, std::ios::binary);
  if (!file)
  {
    vtkErrorMacro(<< "Cannot open '" << this->FileName << "' for reading.");
    return 0;
  }
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  try
  {
    // --- header ---
    std::size_t pos = 0;
    long line_number = 0;
    const auto next_line = [&]() -> std::string {
      if (pos >= bytes.size())
        throw PlyError("the file ends before end_header", line_number);
      std::size_t end = bytes.find('\n', pos);
      if (end == std::string::npos)
        end = bytes.size();
      std::string line = bytes.substr(pos, end - pos);
      // past the newline, or at the end of a file whose last line has none (end + 1 was past
      // the end, and the bytes left underflowed: found by libFuzzer)
      pos = end < bytes.size() ? end + 1 : bytes.size();
      ++line_number;
      if (!line.empty() && line.back() == '\r')
        line.pop_back();
      return line;
    };
    if (next_line() != "ply")
      throw PlyError("not a PLY file (the first line is not 'ply')", 1);
    int format = -1;
    std::vector<Element> elements;
    for (;;)
    {
      const std::string line = next_line();
      std::istringstream words(line);
      std::string key;
      words >> key;
      if (key.empty() || key == "comment" || key == "obj_info")
        continue;
      if (key == "end_header")
        break;
      if (key == "format")
      {
        std::string name, version;
        words >> name >> version;
        format = name == "ascii" ? 0 : name == "binary_little_endian" ? 1
          : name == "binary_big_endian" ? 2 : -1;
        if (format < 0 || version != "1.0")
          throw PlyError("unknown format '" + vtkbary::Printable(line) + "'", line_number);
      }
      else if (key == "element")
      {
        Element e;
        std::string count;
        words >> e.name >> count;
        if (e.name.empty() || !vtkbary::ParseInteger(count, e.count) || e.count < 0)
          throw PlyError("an element line is 'element NAME COUNT', not '" + vtkbary::Printable(line) + "'", line_number);
        e.line = line_number;
        elements.push_back(e);
      }
      else if (key == "property")
      {
        if (elements.empty())
          throw PlyError("a property before any element", line_number);
        Property p;
        std::string type;
        words >> type;
        if (type == "list")
        {
          std::string count, item;
          words >> count >> item >> p.name;
          p.list = true;
          if (!scalar_of(count, p.count) || !scalar_of(item, p.item) || !is_integer(p.count))
            throw PlyError("a list property is 'property list COUNTTYPE ITEMTYPE NAME', not '" +
                vtkbary::Printable(line) + "'", line_number);
        }
        else
        {
          words >> p.name;
          if (!scalar_of(type, p.item))
            throw PlyError("unknown property type in '" + vtkbary::Printable(line) + "'", line_number);
        }
        std::string extra;
        if (p.name.empty() || (words >> extra))
          throw PlyError("malformed property line '" + vtkbary::Printable(line) + "'", line_number);
        elements.back().properties.push_back(p);
      }
      else
        throw PlyError("unknown header keyword '" + vtkbary::Printable(key) + "'", line_number);
    }
    if (format < 0)
      throw PlyError("the header has no format line", line_number);

    // --- body ---
    Body body(bytes, pos, format);
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    vtkNew<vtkCellArray> polys, lines;
    std::vector<vtkIdType> ids;
    bool have_vertices = false;
    for (const Element& e : elements)
    {
      // every element takes at least a byte, unless it has no properties (then nothing to read)
      if (e.properties.empty())
        continue;
      if (static_cast<double>(e.count) > static_cast<double>(body.left()))
        throw PlyError("element '" + vtkbary::Printable(e.name) + "' announces " +
          std::to_string(e.count) + " entries, more than the " + std::to_string(body.left()) +
          " bytes left hold", e.line);
      int xyz[3] = { -1, -1, -1 }, face = -1, ends[2] = { -1, -1 };
      for (std::size_t k = 0; k < e.properties.size(); ++k)
      {
        const Property& p = e.properties[k];
        const int index = static_cast<int>(k);
        if (e.name == "vertex" && !p.list && (p.name == "x" || p.name == "y" || p.name == "z"))
          xyz[p.name[0] - 'x'] = index;
        if (e.name == "face" && p.list && (p.name == "vertex_indices" || p.name == "vertex_index"))
          face = index;
        if (e.name == "edge" && !p.list && (p.name == "vertex1" || p.name == "vertex2"))
          ends[p.name.back() - '1'] = index;
      }
      const bool vertex = e.name == "vertex";
      if (vertex)
      {
        if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0)
          throw PlyError("the vertex element has no x, y and z properties", e.line);
        if (have_vertices)
          throw PlyError("a second vertex element", e.line);
        have_vertices = true;
        points->Allocate(static_cast<vtkIdType>(e.count));
      }
      if (e.name == "face" && face < 0)
        throw PlyError("the face element has no vertex_indices list", e.line);
      for (long long i = 0; i < e.count; ++i)
      {
        double x[3] = { 0, 0, 0 }, end_ids[2] = { 0, 0 };
        for (std::size_t k = 0; k < e.properties.size(); ++k)
        {
          const Property& p = e.properties[k];
          const std::string what = e.name + " " + std::to_string(i) + " (" + p.name + ")";
          if (p.list)
          {
            const double n = body.value(p.count, what);
            if (!(n >= 0 && n <= static_cast<double>(body.left())))
            {
              // n as read, never cast (3e102 in an ASCII list: UBSan, found by libFuzzer)
              std::ostringstream text;
              text << what << ": a list of " << n << " values, more than the bytes left hold";
              throw PlyError(text.str());
            }
            if (static_cast<int>(k) == face)
              ids.clear();
            for (long long j = 0; j < static_cast<long long>(n); ++j)
            {
              const double v = body.value(p.item, what);
              if (static_cast<int>(k) == face)
              {
                if (v != std::floor(v) || v < 0 || v > 9e15)
                  throw PlyError(what + ": '" + std::to_string(v) + "' is not a vertex index");
                ids.push_back(static_cast<vtkIdType>(v));
              }
            }
            if (static_cast<int>(k) == face)
              polys->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
            continue;
          }
          const double v = body.value(p.item, what);
          if (vertex)
            for (int c = 0; c < 3; ++c)
              if (static_cast<int>(k) == xyz[c])
                x[c] = v;
          for (int c = 0; c < 2; ++c)
            if (static_cast<int>(k) == ends[c])
              end_ids[c] = v;
        }
        if (vertex)
          points->InsertNextPoint(x);
        if (e.name == "edge" && ends[0] >= 0 && ends[1] >= 0)
        {
          if (end_ids[0] < 0 || end_ids[1] < 0 || end_ids[0] != std::floor(end_ids[0]) ||
            end_ids[1] != std::floor(end_ids[1]) || end_ids[0] > 9e15 || end_ids[1] > 9e15)
            throw PlyError("edge " + std::to_string(i) + " does not join two vertex indices");
          const vtkIdType pair[2] = { static_cast<vtkIdType>(end_ids[0]), static_cast<vtkIdType>(end_ids[1]) };
          lines->InsertNextCell(2, pair);
        }
      }
    }
    output->SetPoints(points);
    if (lines->GetNumberOfCells() > 0)
      output->SetLines(lines);
    if (polys->GetNumberOfCells() > 0)
      output->SetPolys(polys);
  }
  catch (const PlyError& e)
  {
    output->Initialize();
    if (e.Line > 0)
      vtkErrorMacro(<< "'" << this->FileName << "' line " << e.Line << ": " << e.what());
    else
      vtkErrorMacro(<< "'" << this->FileName << "': " << e.what());
    return 0;
  }
  return 1;
}

void vtkBaryPLYReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}
