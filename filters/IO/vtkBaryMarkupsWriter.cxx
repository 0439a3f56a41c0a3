#include "vtkBaryMarkupsWriter.h"

#include "vtkAbstractArray.h"
#include "vtkDataSet.h"
#include "vtkErrorCode.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkVariant.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <string>

vtkStandardNewMacro(vtkBaryMarkupsWriter);

// a named namespace: the module is compiled in unity batches (see vtkBaryMarkupsReader.cxx)
namespace vtkbary_mrk_write
{
/// The shortest decimal that reads back as @p x (a negative zero as "-0.0": JSON parsers read
/// "-0" as the integer 0).
std::string number(double x)
{
  if (x == 0.0 && std::signbit(x))
    return "-0.0";
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), x);
  return std::string(buffer, result.ptr);
}

/// @p s as a JSON string literal (invalid UTF-8 replaced, not thrown on).
std::string quoted(const std::string& s)
{
  return nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

/// @p s as one CSV field: double-quoted when it holds a comma, a quote or outer spaces; line
/// breaks become spaces (an .fcsv row is one line).
std::string csv_field(std::string s)
{
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\r', ' ');
  const bool quote = s.find_first_of(",\"") != std::string::npos ||
    (!s.empty() && (std::isspace(static_cast<unsigned char>(s.front())) ||
                     std::isspace(static_cast<unsigned char>(s.back()))));
  if (!quote)
    return s;
  std::string out = "\"";
  for (char c : s)
  {
    if (c == '"')
      out += '"';
    out += c;
  }
  return out + "\"";
}

/// Value @p i of the one-component point array @p name of @p data, or "" when there is none.
std::string text_at(vtkDataSet* data, const char* name, vtkIdType i, bool& present)
{
  vtkAbstractArray* array = data->GetPointData()->GetAbstractArray(name);
  present = array && array->GetNumberOfComponents() == 1 &&
    array->GetNumberOfTuples() == data->GetNumberOfPoints();
  return present ? array->GetVariantValue(i).ToString() : std::string();
}

/// The markups of @p input's points, as .fcsv or as markups JSON.
void write(std::ostream& out, vtkDataSet* input, bool fcsv)
{
  const vtkIdType n = input->GetNumberOfPoints();
  bool present = false;
  const auto label = [&](vtkIdType i) {
    std::string text = text_at(input, "Label", i, present);
    return present ? text : "F-" + std::to_string(i + 1);
  };
  const auto id = [&](vtkIdType i) {
    std::string text = text_at(input, "Id", i, present);
    return present && !text.empty() ? text : std::to_string(i + 1);
  };
  const auto description = [&](vtkIdType i) { return text_at(input, "Description", i, present); };
  if (fcsv)
  {
    out << "# Markups fiducial file version = 4.11\n"
           "# CoordinateSystem = LPS\n"
           "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n";
    for (vtkIdType i = 0; i < n; ++i)
    {
      double x[3];
      input->GetPoint(i, x);
      // orientation ow,ox,oy,oz = 0,0,0,1: Slicer's identity (RAS) written in LPS
      out << csv_field(id(i)) << ',' << number(x[0]) << ',' << number(x[1]) << ','
          << number(x[2]) << ",0,0,0,1,1,1,0," << csv_field(label(i)) << ','
          << csv_field(description(i)) << ",\n";
    }
  }
  else
  {
    out << "{\n"
           "    \"@schema\": \"https://raw.githubusercontent.com/slicer/slicer/master/Modules/"
           "Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#\",\n"
           "    \"markups\": [\n"
           "        {\n"
           "            \"type\": \"Fiducial\",\n"
           "            \"coordinateSystem\": \"LPS\",\n"
           "            \"coordinateUnits\": \"mm\",\n"
           "            \"locked\": false,\n"
           "            \"fixedNumberOfControlPoints\": false,\n"
           "            \"labelFormat\": \"%N-%d\",\n"
           "            \"lastUsedControlPointNumber\": "
        << n << ",\n"
        << "            \"controlPoints\": [\n";
    for (vtkIdType i = 0; i < n; ++i)
    {
      double x[3];
      input->GetPoint(i, x);
      out << "                {\n"
          << "                    \"id\": " << quoted(id(i)) << ",\n"
          << "                    \"label\": " << quoted(label(i)) << ",\n"
          << "                    \"description\": " << quoted(description(i)) << ",\n"
          << "                    \"associatedNodeID\": \"\",\n"
          << "                    \"position\": [" << number(x[0]) << ", " << number(x[1]) << ", "
          << number(x[2]) << "],\n"
          << "                    \"orientation\": [-1.0, -0.0, -0.0, -0.0, -1.0, -0.0, 0.0, 0.0, "
             "1.0],\n"
          << "                    \"selected\": true,\n"
          << "                    \"locked\": false,\n"
          << "                    \"visibility\": true,\n"
          << "                    \"positionStatus\": \"defined\"\n"
          << "                }" << (i + 1 < n ? ",\n" : "\n");
    }
    out << "            ],\n"
           "            \"measurements\": []\n"
           "        }\n"
           "    ]\n"
           "}\n";
  }
}
} // namespace vtkbary_mrk_write

int vtkBaryMarkupsWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

void vtkBaryMarkupsWriter::WriteData()
{
  vtkDataSet* input = vtkDataSet::SafeDownCast(this->GetInput());
  if (!input)
  {
    vtkErrorMacro(<< "Markups are written from a data set's points: no data set.");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }
  if (this->FileName.empty())
  {
    vtkErrorMacro(<< "No file name set.");
    this->SetErrorCode(vtkErrorCode::NoFileNameError);
    return;
  }
  const vtkIdType n = input->GetNumberOfPoints();
  if (n == 0)
  {
    vtkErrorMacro(<< "no points to write as markups");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }
  for (vtkIdType i = 0; i < n; ++i)
  {
    double x[3];
    input->GetPoint(i, x);
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
    {
      vtkErrorMacro(<< "point " << i << " has a non-finite coordinate (NaN or infinity): markups "
                    << "hold finite positions");
      this->SetErrorCode(vtkErrorCode::UnknownError);
      return;
    }
  }
  std::string lowerName = this->FileName;
  std::transform(lowerName.begin(), lowerName.end(), lowerName.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const bool fcsv = this->Format == FCSV ||
    (this->Format == FromFileName && lowerName.size() >= 5 &&
      lowerName.compare(lowerName.size() - 5, 5, ".fcsv") == 0);

  std::ofstream out(this->FileName, std::ios::binary);
  if (!out)
  {
    vtkErrorMacro(<< "Cannot open '" << this->FileName << "' for writing.");
    this->SetErrorCode(vtkErrorCode::CannotOpenFileError);
    return;
  }
  vtkbary_mrk_write::write(out, input, fcsv);
  out.flush();
  if (!out)
  {
    vtkErrorMacro(<< "Writing '" << this->FileName << "' failed (disk full?).");
    this->SetErrorCode(vtkErrorCode::OutOfDiskSpaceError);
  }
}

void vtkBaryMarkupsWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
  os << indent << "Format: " << this->Format << "\n";
}
