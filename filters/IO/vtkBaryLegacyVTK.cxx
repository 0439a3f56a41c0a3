#include "vtkBaryLegacyVTK.h"

#include "vtkBaryTextParsing.h"

#include "core/common/error.h"

#include "vtkBitArray.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCharArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkLongLongArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkRectilinearGrid.h"
#include "vtkShortArray.h"
#include "vtkSignedCharArray.h"
#include "vtkStructuredGrid.h"
#include "vtkTypeInt64Array.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnsignedIntArray.h"
#include "vtkUnsignedLongLongArray.h"
#include "vtkUnsignedShortArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace vtkbary
{
namespace
{
using bary::Error;
using bary::ErrorCode;

constexpr double kMaxGridPoints = 2147483648.0; // 2^31

std::string lower(std::string_view s)
{
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

/// The file, a cursor into it, and the line the cursor is on (for messages).
class Cursor
{
public:
  Cursor(std::string path, std::string bytes)
    : path_(std::move(path))
    , bytes_(std::move(bytes))
  {
  }

  Error fail(const std::string& what) const { return fail_at(line_, what); }
  Error fail_at(long line, const std::string& what) const
  {
    return Error(ErrorCode::Io, "cannot read '" + path_ + "' line " + std::to_string(line) + ": " + what);
  }

  bool at_end()
  {
    skip_space();
    return pos_ >= bytes_.size();
  }

  /// The next whitespace-separated token; "" at the end of the file.
  std::string_view token()
  {
    skip_space();
    const std::size_t begin = pos_;
    while (pos_ < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[pos_])))
      ++pos_;
    return std::string_view(bytes_).substr(begin, pos_ - begin);
  }

  /// The next token, required: @p what names it in the message when the file ends.
  std::string_view need(const char* what)
  {
    const std::string_view t = token();
    if (t.empty())
      throw fail(std::string("the file ends where ") + what + " should be");
    return t;
  }

  /// The next token as a count from 0 to @p most.
  long long count(const char* what, double most = 9e15)
  {
    const std::string_view t = need(what);
    long long n = -1;
    if (!ParseInteger(t, n) || n < 0)
      throw fail(std::string(what) + " must be a whole number from 0, not '" + Printable(t) + "'");
    if (static_cast<double>(n) > most)
      throw fail(std::string(what) + " " + std::to_string(n) + " is more than the file can hold");
    return n;
  }

  /// The next token as a finite double.
  double number(const char* what)
  {
    const std::string_view t = need(what);
    double x = 0.0;
    if (ParseDouble(t, x) != Parsed::Ok || !std::isfinite(x))
      throw fail(std::string(what) + " must be a finite number, not '" + Printable(t) + "'");
    return x;
  }

  /// The rest of the current line (binary data start on the next one).
  void end_of_line()
  {
    while (pos_ < bytes_.size() && bytes_[pos_] != '\n')
      ++pos_;
    if (pos_ < bytes_.size())
    {
      ++pos_;
      ++line_;
    }
  }

  /// The whole next line (the header's first three lines).
  std::string_view line()
  {
    const std::size_t begin = pos_;
    end_of_line();
    std::string_view l = std::string_view(bytes_).substr(begin, pos_ - begin);
    while (!l.empty() && (l.back() == '\n' || l.back() == '\r'))
      l.remove_suffix(1);
    return l;
  }

  /// @p n raw bytes (binary data); nullptr if the file has fewer left.
  const unsigned char* raw(std::size_t n)
  {
    if (n > bytes_.size() - pos_)
      return nullptr;
    const auto* p = reinterpret_cast<const unsigned char*>(bytes_.data() + pos_);
    for (std::size_t k = 0; k < n; ++k)
      if (bytes_[pos_ + k] == '\n')
        ++line_; // keep counting lines through binary data, for the messages after it
    pos_ += n;
    return p;
  }

  /// The bytes left (a bound on how many values the rest of the file can hold).
  std::size_t left() const { return bytes_.size() - pos_; }

  /// The next token without consuming it.
  std::string_view peek()
  {
    const std::size_t pos = pos_;
    const long line = line_;
    const std::string_view t = token();
    pos_ = pos;
    line_ = line;
    return t;
  }

  /// Skips lines until an empty one (the end of a METADATA block).
  void skip_block()
  {
    end_of_line();
    while (pos_ < bytes_.size())
    {
      const std::string_view l = line();
      if (l.find_first_not_of(" \t\r") == std::string_view::npos)
        return;
    }
  }

private:
  void skip_space()
  {
    while (pos_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[pos_])))
    {
      if (bytes_[pos_] == '\n')
        ++line_;
      ++pos_;
    }
  }

  std::string path_;
  std::string bytes_;
  std::size_t pos_ = 0;
  long line_ = 1;
};

/// A numeric legacy type: its array and its size in binary files (big-endian).
struct Type
{
  int vtk; // VTK_FLOAT, ...
  std::size_t bytes; // 0: bits
  bool integer;
  bool is_signed;
};

bool type_of(const std::string& name, Type& t)
{
  if (name == "bit") t = { VTK_BIT, 0, true, false };
  else if (name == "char") t = { VTK_SIGNED_CHAR, 1, true, true };
  else if (name == "unsigned_char") t = { VTK_UNSIGNED_CHAR, 1, true, false };
  else if (name == "short") t = { VTK_SHORT, 2, true, true };
  else if (name == "unsigned_short") t = { VTK_UNSIGNED_SHORT, 2, true, false };
  else if (name == "int" || name == "vtkidtype") t = { VTK_INT, 4, true, true };
  else if (name == "unsigned_int") t = { VTK_UNSIGNED_INT, 4, true, false };
  else if (name == "long" || name == "vtktypeint64") t = { VTK_LONG_LONG, 8, true, true };
  else if (name == "unsigned_long" || name == "vtktypeuint64") t = { VTK_UNSIGNED_LONG_LONG, 8, true, false };
  else if (name == "float") t = { VTK_FLOAT, 4, false, true };
  else if (name == "double") t = { VTK_DOUBLE, 8, false, true };
  else
    return false;
  return true;
}

vtkSmartPointer<vtkDataArray> make_array(int type)
{
  switch (type)
  {
    case VTK_BIT: return vtkSmartPointer<vtkBitArray>::New();
    case VTK_SIGNED_CHAR: return vtkSmartPointer<vtkSignedCharArray>::New();
    case VTK_UNSIGNED_CHAR: return vtkSmartPointer<vtkUnsignedCharArray>::New();
    case VTK_SHORT: return vtkSmartPointer<vtkShortArray>::New();
    case VTK_UNSIGNED_SHORT: return vtkSmartPointer<vtkUnsignedShortArray>::New();
    case VTK_INT: return vtkSmartPointer<vtkIntArray>::New();
    case VTK_UNSIGNED_INT: return vtkSmartPointer<vtkUnsignedIntArray>::New();
    case VTK_LONG_LONG: return vtkSmartPointer<vtkLongLongArray>::New();
    case VTK_UNSIGNED_LONG_LONG: return vtkSmartPointer<vtkUnsignedLongLongArray>::New();
    case VTK_FLOAT: return vtkSmartPointer<vtkFloatArray>::New();
    default: return vtkSmartPointer<vtkDoubleArray>::New();
  }
}

class LegacyReader
{
public:
  LegacyReader(const std::string& path, std::string bytes)
    : in_(path, std::move(bytes))
  {
  }

  vtkSmartPointer<vtkDataSet> read();

private:
  /// A type word, checked.
  Type type(const char* what)
  {
    const std::string name = lower(in_.need(what));
    Type t;
    if (name == "string" || name == "utf8_string" || name == "variant")
      throw in_.fail(std::string(what) + " '" + name + "': text arrays are not read (numeric only)");
    if (!type_of(name, t))
      throw in_.fail(std::string(what) + " '" + Printable(name) + "' is not a VTK data type");
    return t;
  }

  /// @p tuples x @p components values of @p t, checked against the bytes left first.
  vtkSmartPointer<vtkDataArray> values(const Type& t, long long tuples, long long components,
    const std::string& what)
  {
    if (components < 1)
      throw in_.fail(what + " has " + std::to_string(components) + " components");
    const double n = static_cast<double>(tuples) * static_cast<double>(components);
    const double bytes = binary_ ? (t.bytes ? n * static_cast<double>(t.bytes) : std::ceil(n / 8.0)) : n;
    if (bytes > static_cast<double>(in_.left()))
      throw in_.fail(what + ": " + std::to_string(tuples) + " x " + std::to_string(components) +
        " values announced, more than the " + std::to_string(in_.left()) + " bytes left hold");
    vtkSmartPointer<vtkDataArray> a = make_array(t.vtk);
    a->SetNumberOfComponents(static_cast<int>(components));
    a->SetNumberOfTuples(static_cast<vtkIdType>(tuples));
    const auto count = static_cast<vtkIdType>(n);
    if (binary_)
    {
      in_.end_of_line();
      const std::size_t size = t.bytes ? static_cast<std::size_t>(count) * t.bytes
                                       : static_cast<std::size_t>((count + 7) / 8);
      const unsigned char* p = in_.raw(size);
      if (!p)
        throw in_.fail(what + ": the file ends inside its binary data");
      if (t.vtk == VTK_BIT)
      {
        auto* bits = static_cast<vtkBitArray*>(a.Get());
        for (vtkIdType i = 0; i < count; ++i)
          bits->SetValue(i, (p[i / 8] >> (7 - i % 8)) & 1);
        return a;
      }
      auto* out = static_cast<unsigned char*>(a->GetVoidPointer(0));
      for (vtkIdType i = 0; i < count; ++i)
        for (std::size_t b = 0; b < t.bytes; ++b) // big-endian to the machine's little-endian
          out[static_cast<std::size_t>(i) * t.bytes + b] = p[static_cast<std::size_t>(i) * t.bytes + t.bytes - 1 - b];
      return a;
    }
    for (vtkIdType i = 0; i < count; ++i)
    {
      const std::string_view token = in_.need((what + " values").c_str());
      if (t.integer)
      {
        long long v = 0;
        double d = 0.0;
        bool ok = ParseInteger(token, v);
        if (!ok && ParseDouble(token, d) == Parsed::Ok && d == std::floor(d) && std::fabs(d) < 9e15)
        {
          v = static_cast<long long>(d); // "3.0" for an integer, as VTK's >> reads it
          ok = true;
        }
        if (!ok || (!t.is_signed && v < 0) ||
          (t.bytes && t.bytes < 8 && (v > (1LL << (8 * t.bytes - (t.is_signed ? 1 : 0))) - 1 ||
                                       v < (t.is_signed ? -(1LL << (8 * t.bytes - 1)) : 0))))
          throw in_.fail(what + ": '" + Printable(token) + "' is not a value of its type");
        a->SetComponent(i / components, static_cast<int>(i % components), static_cast<double>(v));
      }
      else
      {
        double v = 0.0;
        if (ParseDouble(token, v) != Parsed::Ok)
          throw in_.fail(what + ": '" + Printable(token) + "' is not a number double precision holds");
        a->SetComponent(i / components, static_cast<int>(i % components), v);
      }
    }
    return a;
  }

  /// An optional METADATA block after an array: skipped.
  void metadata()
  {
    if (lower(in_.peek()) == "metadata")
    {
      in_.token();
      in_.skip_block();
    }
  }

  vtkSmartPointer<vtkPoints> points()
  {
    const long long n = in_.count("the number of points", static_cast<double>(in_.left()));
    const Type t = type("the points' type");
    if (t.vtk == VTK_BIT)
      throw in_.fail("points of type bit");
    vtkSmartPointer<vtkDataArray> xyz = values(t, n, 3, "POINTS");
    metadata();
    auto p = vtkSmartPointer<vtkPoints>::New();
    p->SetDataTypeToDouble();
    p->SetNumberOfPoints(static_cast<vtkIdType>(n));
    for (vtkIdType i = 0; i < static_cast<vtkIdType>(n); ++i)
      p->SetPoint(i, xyz->GetTuple3(i));
    return p;
  }

  /// A cell keyword's data: classic `n size` + size ints, or 5.x `OFFSETS`/`CONNECTIVITY`.
  vtkSmartPointer<vtkCellArray> cells(const std::string& keyword)
  {
    const long long a = in_.count((keyword + "'s first count").c_str(), static_cast<double>(in_.left()));
    const long long b = in_.count((keyword + "'s second count").c_str(), static_cast<double>(in_.left()));
    vtkNew<vtkIdTypeArray> offsets, connectivity;
    if (version_ >= 5)
    {
      // a = number of offsets (cells + 1), b = connectivity size
      for (const char* word : { "offsets", "connectivity" })
      {
        const std::string_view k = in_.need(word);
        if (lower(k) != word)
          throw in_.fail(keyword + ": expected " + upper(word) + ", not '" + Printable(k) + "'");
        const Type t = type((std::string(word) + "' type").c_str());
        vtkSmartPointer<vtkDataArray> v = values(t, std::string(word) == "offsets" ? a : b, 1, keyword + " " + upper(word));
        vtkIdTypeArray* target = std::string(word) == "offsets" ? offsets.Get() : connectivity.Get();
        target->SetNumberOfValues(v->GetNumberOfTuples());
        for (vtkIdType i = 0; i < v->GetNumberOfTuples(); ++i)
          target->SetValue(i, static_cast<vtkIdType>(v->GetComponent(i, 0)));
      }
      if (a == 0 && b == 0)
        offsets->InsertNextValue(0);
      if (offsets->GetNumberOfValues() < 1 || offsets->GetValue(0) != 0 ||
        offsets->GetValue(offsets->GetNumberOfValues() - 1) != connectivity->GetNumberOfValues())
        throw in_.fail(keyword + ": the offsets do not span the connectivity");
      for (vtkIdType i = 1; i < offsets->GetNumberOfValues(); ++i)
        if (offsets->GetValue(i) < offsets->GetValue(i - 1))
          throw in_.fail(keyword + ": the offsets decrease at cell " + std::to_string(i - 1));
    }
    else
    {
      // a = number of cells, b = size of the list (each cell: its size, then its ids)
      const Type t{ VTK_INT, 4, true, true };
      vtkSmartPointer<vtkDataArray> list = values(t, b, 1, keyword);
      offsets->InsertNextValue(0);
      vtkIdType at = 0;
      for (long long c = 0; c < a; ++c)
      {
        if (at >= list->GetNumberOfTuples())
          throw in_.fail(keyword + ": the list of " + std::to_string(b) + " numbers ends at cell " +
            std::to_string(c) + " of " + std::to_string(a));
        const auto n = static_cast<vtkIdType>(list->GetComponent(at, 0));
        if (n < 0 || n > list->GetNumberOfTuples() - at - 1)
          throw in_.fail(keyword + ": cell " + std::to_string(c) + " has " + std::to_string(n) +
            " points, more than the list holds");
        for (vtkIdType k = 0; k < n; ++k)
          connectivity->InsertNextValue(static_cast<vtkIdType>(list->GetComponent(at + 1 + k, 0)));
        at += n + 1;
        offsets->InsertNextValue(connectivity->GetNumberOfValues());
      }
      if (at != list->GetNumberOfTuples())
        throw in_.fail(keyword + ": " + std::to_string(a) + " cells use " + std::to_string(at) +
          " numbers of the " + std::to_string(b) + " announced");
    }
    metadata();
    auto cells = vtkSmartPointer<vtkCellArray>::New();
    cells->SetData(offsets, connectivity);
    return cells;
  }

  static std::string upper(std::string s)
  {
    std::transform(s.begin(), s.end(), s.begin(),
      [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    return s;
  }

  /// FIELD name n, then n arrays "name components tuples type" with their values.
  void field(vtkFieldData* into)
  {
    in_.need("the field's name");
    const long long n = in_.count("the field's number of arrays", static_cast<double>(in_.left()));
    for (long long k = 0; k < n; ++k)
    {
      const std::string name(in_.need("a field array's name"));
      const long long components = in_.count("a field array's components", static_cast<double>(in_.left()));
      const long long tuples = in_.count("a field array's tuples", static_cast<double>(in_.left()));
      const Type t = type("a field array's type");
      vtkSmartPointer<vtkDataArray> a = values(t, tuples, components, "FIELD array '" + Printable(name) + "'");
      a->SetName(name == "NULL_ARRAY" ? nullptr : name.c_str());
      metadata();
      into->AddArray(a);
    }
  }

  /// The attributes after POINT_DATA n or CELL_DATA n, until the other one or the end.
  void attributes(vtkDataSetAttributes* into, long long n)
  {
    while (!in_.at_end())
    {
      const std::string key = lower(in_.peek());
      if (key == "point_data" || key == "cell_data")
        return;
      in_.token();
      const auto named = [&](const char* what) {
        std::string name(in_.need(what));
        return name;
      };
      if (key == "scalars")
      {
        const std::string name = named("the scalars' name");
        const Type t = type("the scalars' type");
        long long components = 1;
        // an optional component count before LOOKUP_TABLE
        const std::string_view next = in_.peek();
        long long c = 0;
        if (ParseInteger(next, c))
          components = in_.count("the scalars' components", 4096.0);
        const std::string_view lut = in_.need("LOOKUP_TABLE");
        if (lower(lut) != "lookup_table")
          throw in_.fail("SCALARS '" + Printable(name) + "': expected LOOKUP_TABLE, not '" + Printable(lut) + "'");
        in_.need("the lookup table's name");
        add(into, values(t, n, components, "SCALARS '" + Printable(name) + "'"), name, vtkDataSetAttributes::SCALARS);
      }
      else if (key == "lookup_table")
      {
        in_.need("the lookup table's name");
        const long long size = in_.count("the lookup table's size", static_cast<double>(in_.left()));
        values(binary_ ? Type{ VTK_UNSIGNED_CHAR, 1, true, false } : Type{ VTK_FLOAT, 4, false, true },
          size, 4, "LOOKUP_TABLE"); // read and dropped
      }
      else if (key == "color_scalars")
      {
        const std::string name = named("the color scalars' name");
        const long long components = in_.count("the color scalars' components", 4096.0);
        vtkSmartPointer<vtkDataArray> v = values(binary_ ? Type{ VTK_UNSIGNED_CHAR, 1, true, false }
                                                          : Type{ VTK_FLOAT, 4, false, true },
          n, components, "COLOR_SCALARS '" + Printable(name) + "'");
        vtkNew<vtkUnsignedCharArray> colors;
        colors->SetNumberOfComponents(static_cast<int>(components));
        colors->SetNumberOfTuples(v->GetNumberOfTuples());
        for (vtkIdType i = 0; i < v->GetNumberOfTuples(); ++i)
          for (int k = 0; k < static_cast<int>(components); ++k)
          {
            const double x = v->GetComponent(i, k);
            colors->SetComponent(i, k, binary_ ? x : std::clamp(std::round(255.0 * x), 0.0, 255.0));
          }
        add(into, colors, name, vtkDataSetAttributes::SCALARS);
      }
      else if (key == "vectors" || key == "normals" || key == "tensors" || key == "tensors6" ||
        key == "global_ids" || key == "pedigree_ids" || key == "texture_coordinates")
      {
        const std::string name = named("the attribute's name");
        long long components = key == "tensors" ? 9 : key == "tensors6" ? 6
          : (key == "vectors" || key == "normals") ? 3 : 1;
        if (key == "texture_coordinates")
          components = in_.count("the texture coordinates' dimension", 3.0);
        const Type t = type("the attribute's type");
        const int attribute = key == "vectors" ? vtkDataSetAttributes::VECTORS
          : key == "normals"                   ? vtkDataSetAttributes::NORMALS
          : key == "tensors" || key == "tensors6" ? vtkDataSetAttributes::TENSORS
          : key == "global_ids"                ? vtkDataSetAttributes::GLOBALIDS
          : key == "pedigree_ids"              ? vtkDataSetAttributes::PEDIGREEIDS
                                               : vtkDataSetAttributes::TCOORDS;
        add(into, values(t, n, components, upper(key) + " '" + Printable(name) + "'"), name, attribute);
      }
      else if (key == "field")
        field(into);
      else if (key == "metadata")
        in_.skip_block();
      else
        throw in_.fail("unknown attribute keyword '" + Printable(key) + "'");
    }
  }

  void add(vtkDataSetAttributes* into, vtkDataArray* a, const std::string& name, int attribute)
  {
    a->SetName(name.c_str());
    metadata();
    into->AddArray(a);
    if (!into->GetAttribute(attribute) && attribute != vtkDataSetAttributes::TENSORS)
      into->SetActiveAttribute(a->GetName(), attribute);
  }

  int dimensions(int dims[3])
  {
    double product = 1.0;
    for (int k = 0; k < 3; ++k)
    {
      dims[k] = static_cast<int>(in_.count("a dimension", 2147483647.0));
      product *= dims[k];
    }
    if (product > kMaxGridPoints)
      throw in_.fail("the grid's dimensions make " + std::to_string(static_cast<long long>(product)) +
        " points, more than BaryLab reads (2^31)");
    return 1;
  }

  vtkSmartPointer<vtkDataSet> make(const std::string& kind, vtkPoints* pts, vtkCellArray* verts,
    vtkCellArray* lines, vtkCellArray* polys, vtkCellArray* strips, vtkCellArray* cells,
    vtkDataArray* types, const int dims[3], const double spacing[3], const double origin[3],
    vtkSmartPointer<vtkDataArray> coords[3])
  {
    const auto need_dims = [&] {
      if (dims[0] < 0)
        throw in_.fail(upper(kind) + " without DIMENSIONS");
    };
    if (kind == "polydata")
    {
      auto poly = vtkSmartPointer<vtkPolyData>::New();
      poly->SetPoints(pts ? pts : vtkSmartPointer<vtkPoints>::New().Get());
      if (verts)
        poly->SetVerts(verts);
      if (lines)
        poly->SetLines(lines);
      if (polys)
        poly->SetPolys(polys);
      if (strips)
        poly->SetStrips(strips);
      return poly;
    }
    if (kind == "unstructured_grid")
    {
      auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
      grid->SetPoints(pts ? pts : vtkSmartPointer<vtkPoints>::New().Get());
      if (cells && cells->GetNumberOfCells() > 0)
      {
        if (!types || types->GetNumberOfTuples() != cells->GetNumberOfCells())
          throw in_.fail("the grid has " + std::to_string(cells->GetNumberOfCells()) + " cells but " +
            std::to_string(types ? types->GetNumberOfTuples() : 0) + " CELL_TYPES");
        vtkNew<vtkUnsignedCharArray> t;
        t->SetNumberOfValues(types->GetNumberOfTuples());
        for (vtkIdType i = 0; i < types->GetNumberOfTuples(); ++i)
        {
          const double v = types->GetComponent(i, 0);
          if (v < 0 || v > 255)
            throw in_.fail("cell type " + std::to_string(static_cast<long long>(v)) + " of cell " +
              std::to_string(i) + " is not a VTK cell type");
          t->SetValue(i, static_cast<unsigned char>(v));
        }
        grid->SetCells(t, cells);
      }
      return grid;
    }
    if (kind == "structured_points")
    {
      need_dims();
      auto image = vtkSmartPointer<vtkImageData>::New();
      image->SetDimensions(dims[0], dims[1], dims[2]);
      image->SetSpacing(spacing[0], spacing[1], spacing[2]);
      image->SetOrigin(origin[0], origin[1], origin[2]);
      return image;
    }
    if (kind == "structured_grid")
    {
      need_dims();
      auto grid = vtkSmartPointer<vtkStructuredGrid>::New();
      grid->SetDimensions(dims[0], dims[1], dims[2]);
      grid->SetPoints(pts ? pts : vtkSmartPointer<vtkPoints>::New().Get());
      return grid;
    }
    need_dims();
    auto grid = vtkSmartPointer<vtkRectilinearGrid>::New();
    grid->SetDimensions(dims[0], dims[1], dims[2]);
    for (int k = 0; k < 3; ++k)
    {
      if (!coords[k])
        throw in_.fail(std::string("RECTILINEAR_GRID without ") + "XYZ"[k] + "_COORDINATES");
      coords[k]->SetNumberOfComponents(1);
    }
    grid->SetXCoordinates(coords[0]);
    grid->SetYCoordinates(coords[1]);
    grid->SetZCoordinates(coords[2]);
    return grid;
  }

  Cursor in_;
  bool binary_ = false;
  int version_ = 3;
};

vtkSmartPointer<vtkDataSet> LegacyReader::read()
{
  const std::string_view first = in_.line();
  const std::string_view magic = "# vtk DataFile Version";
  if (first.substr(0, magic.size()) != magic)
    throw in_.fail_at(1, "not a legacy VTK file: it starts with '" + Printable(first) + "', not '# vtk DataFile Version'");
  {
    std::string_view v = first.substr(magic.size());
    while (!v.empty() && v.front() == ' ')
      v.remove_prefix(1);
    version_ = v.empty() ? 0 : v.front() - '0';
    if (version_ < 1 || version_ > 5)
      throw in_.fail_at(1, "unknown legacy version '" + Printable(v) + "'");
  }
  in_.line(); // the title
  const std::string mode = lower(in_.need("ASCII or BINARY"));
  if (mode != "ascii" && mode != "binary")
    throw in_.fail("the third line must say ASCII or BINARY, not '" + Printable(mode) + "'");
  binary_ = mode == "binary";

  vtkSmartPointer<vtkDataSet> data;
  std::string kind;
  vtkNew<vtkFieldData> field_data;
  vtkSmartPointer<vtkPoints> pts;
  vtkSmartPointer<vtkCellArray> verts, lines, polys, strips, cells;
  vtkSmartPointer<vtkDataArray> types, coords[3];
  int dims[3] = { -1, -1, -1 };
  double spacing[3] = { 1, 1, 1 }, origin[3] = { 0, 0, 0 };
  while (!in_.at_end())
  {
    const std::string key = lower(in_.token());
    if (key == "dataset")
    {
      if (!kind.empty())
        throw in_.fail("a second DATASET");
      kind = lower(in_.need("the data set type"));
      if (kind != "polydata" && kind != "unstructured_grid" && kind != "structured_points" &&
        kind != "structured_grid" && kind != "rectilinear_grid")
        throw in_.fail("data set type '" + Printable(kind) + "' is not read (POLYDATA, "
          "UNSTRUCTURED_GRID, STRUCTURED_POINTS, STRUCTURED_GRID, RECTILINEAR_GRID are)");
      continue;
    }
    if (kind.empty() && key != "field")
      throw in_.fail("expected DATASET, not '" + Printable(key) + "'");
    if (key == "field")
      field(field_data);
    else if (key == "points" && kind != "structured_points" && kind != "rectilinear_grid")
      pts = points();
    else if (kind == "polydata" && (key == "vertices" || key == "lines" || key == "polygons" ||
                                     key == "triangle_strips"))
    {
      auto c = this->cells(upper(key));
      (key == "vertices" ? verts : key == "lines" ? lines : key == "polygons" ? polys : strips) = c;
    }
    else if (kind == "unstructured_grid" && key == "cells")
      cells = this->cells("CELLS");
    else if (kind == "unstructured_grid" && key == "cell_types")
    {
      const long long n = in_.count("the number of cell types", static_cast<double>(in_.left()));
      types = values(Type{ VTK_INT, 4, true, true }, n, 1, "CELL_TYPES");
      metadata();
    }
    else if ((kind == "structured_points" || kind == "structured_grid" || kind == "rectilinear_grid") &&
      key == "dimensions")
      dimensions(dims);
    else if (kind == "structured_points" && (key == "spacing" || key == "aspect_ratio" || key == "origin"))
      for (double& x : key == "origin" ? origin : spacing)
        x = in_.number(key == "origin" ? "an origin coordinate" : "a spacing");
    else if (kind == "rectilinear_grid" &&
      (key == "x_coordinates" || key == "y_coordinates" || key == "z_coordinates"))
    {
      const long long n = in_.count("the number of coordinates", static_cast<double>(in_.left()));
      const Type t = type("the coordinates' type");
      coords[key[0] - 'x'] = values(t, n, 1, upper(key));
      metadata();
    }
    else if (key == "point_data" || key == "cell_data")
    {
      if (!data)
        data = make(kind, pts, verts, lines, polys, strips, cells, types, dims, spacing, origin, coords);
      const long long n = in_.count((upper(key) + "'s count").c_str(), kMaxGridPoints);
      const vtkIdType expected = key == "point_data" ? data->GetNumberOfPoints() : data->GetNumberOfCells();
      if (n != expected)
        throw in_.fail(upper(key) + " " + std::to_string(n) + " but the data set has " +
          std::to_string(expected) + (key == "point_data" ? " points" : " cells"));
      attributes(key == "point_data" ? static_cast<vtkDataSetAttributes*>(data->GetPointData())
                                     : static_cast<vtkDataSetAttributes*>(data->GetCellData()),
        n);
    }
    else if (key == "metadata")
      in_.skip_block();
    else
      throw in_.fail("unknown keyword '" + Printable(key) + "' in " + upper(kind));
  }
  if (kind.empty())
    throw in_.fail("no DATASET");
  if (!data)
    data = make(kind, pts, verts, lines, polys, strips, cells, types, dims, spacing, origin, coords);
  for (int i = 0; i < field_data->GetNumberOfArrays(); ++i)
    data->GetFieldData()->AddArray(field_data->GetAbstractArray(i));
  return data;
}
} // namespace

vtkSmartPointer<vtkDataSet> ReadLegacyVTK(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw Error(ErrorCode::Io, "cannot read '" + path + "': no such file or not readable");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return LegacyReader(path, std::move(bytes)).read();
}
} // namespace vtkbary
