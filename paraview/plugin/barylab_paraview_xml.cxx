// barylab_paraview_xml: writes the ParaView server-manager XML of the weight method from BaryLab's
// one table of methods and settings (core/coordinates/weight_methods.h), so that the plugin's
// property names, defaults, ranges, choices and documentation are those of the command line,
// the viewer and vtkBaryWeightMethod, written once.
//
//   barylab_paraview_xml <weight_method.xml> [<template.xml.in> <output.xml>]...
//
// <weight_method.xml> receives the proxy "WeightMethod" (group barylab_weight_methods, class
// vtkBaryPVWeightMethod, the plugin's vtkBaryWeightMethod with list commands for the Numbers
// rows) with one property per setting. Each template is copied to its output
// with the line that is only @BARYLAB_WEIGHT_METHOD@ (indented) replaced by a SubProxy of that proxy
// (command SetWeightMethod) exposing every property, in groups, shown only for the methods the
// setting applies to. Run by the plugin's build (paraview/plugin/CMakeLists.txt); links only
// BaryLab::core.
#include "core/coordinates/weight_methods.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using bary::SettingField;

std::string escape(const std::string& text)
{
  std::string out;
  for (char c : text)
  {
    switch (c)
    {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// Shortest text that reads back as the same double (defaults such as 1e-10 stay 1e-10).
std::string number(double value)
{
  for (int precision = 1; precision <= 17; ++precision)
  {
    char buffer[64];
    std::snprintf(buffer, sizeof(buffer), "%.*g", precision, value);
    if (std::strtod(buffer, nullptr) == value)
      return buffer;
  }
  return std::to_string(value);
}

// Integers as integers ("50000000", never "5e+07", which ParaView's int parser reads as 5).
std::string integer(double value)
{
  return std::to_string(static_cast<long long>(std::llround(value)));
}

std::string method_values(const SettingField& field)
{
  std::string values;
  for (bary::MethodId id : field.methods)
    values += (values.empty() ? "" : " ") + std::to_string(static_cast<int>(id));
  return values;
}

std::string applies_text(const SettingField& field)
{
  if (field.methods.empty())
    return "every method";
  std::string text;
  for (bary::MethodId id : field.methods)
    text += (text.empty() ? "" : ", ") + bary::method_info(id).name;
  return text;
}

bool shown(const SettingField&)
{
  return true; // every row; Numbers rows through vtkBaryPVWeightMethod's list commands
}

// A Numbers row (the T-celestial user weights: an array on vtkBaryWeightMethod) as a list
// property: vtkBaryPVWeightMethod's SetNumberOf<Property>Values and Set<Property>Value.
void write_numbers_property(std::ostream& os, const SettingField& f)
{
  os << "      <DoubleVectorProperty name=\"" << f.property << "\" label=\"" << escape(f.label)
     << "\" command=\"Set" << f.property << "Value\" set_number_command=\"SetNumberOf"
     << f.property << "Values\" use_index=\"1\" repeat_command=\"1\" "
                      "number_of_elements_per_command=\"1\" number_of_elements=\"0\">\n"
     << "        <DoubleRangeDomain name=\"range\" min=\"" << number(f.minimum) << "\"/>\n"
     << "        <Documentation>" << escape(f.help) << " Range: " << escape(f.range_text())
     << "; default none; applies to " << escape(applies_text(f)) << ". (Session key "
     << escape(f.key) << ".)</Documentation>\n";
  if (!f.methods.empty())
    os << "        <Hints>\n          <PropertyWidgetDecorator type=\"GenericDecorator\" "
          "mode=\"visibility\" property=\"Method\" values=\""
       << method_values(f) << "\"/>\n        </Hints>\n";
  os << "      </DoubleVectorProperty>\n";
}

void write_property(std::ostream& os, const SettingField& f)
{
  if (f.kind == SettingField::Kind::Numbers)
  {
    write_numbers_property(os, f);
    return;
  }
  const bool is_double = f.kind == SettingField::Kind::Double;
  const char* element = is_double ? "DoubleVectorProperty" : "IntVectorProperty";
  os << "      <" << element << " name=\"" << f.property << "\" label=\"" << escape(f.label)
     << "\" command=\"Set" << f.property << "\" number_of_elements=\"1\" default_values=\""
     << (is_double ? number(f.default_value()) : integer(f.default_value())) << "\"" << (f.affects_weights ? "" : " panel_visibility=\"advanced\"")
     << ">\n";
  switch (f.kind)
  {
    case SettingField::Kind::Bool:
      os << "        <BooleanDomain name=\"bool\"/>\n";
      break;
    case SettingField::Kind::Choice:
      os << "        <EnumerationDomain name=\"enum\">\n";
      for (std::size_t i = 0; i < f.choices.size(); ++i)
        os << "          <Entry value=\"" << i << "\" text=\"" << escape(f.choices[i]) << "\"/>\n";
      os << "        </EnumerationDomain>\n";
      break;
    case SettingField::Kind::Int:
      if (!f.values.empty())
      {
        os << "        <EnumerationDomain name=\"enum\">\n";
        for (double v : f.values)
          os << "          <Entry value=\"" << integer(v) << "\" text=\"" << integer(v) << "\"/>\n";
        os << "        </EnumerationDomain>\n";
      }
      else
        os << "        <IntRangeDomain name=\"range\" min=\"" << integer(f.minimum) << "\" max=\""
           << integer(f.maximum) << "\"/>\n";
      break;
    case SettingField::Kind::Double:
      // No upper end for the table's "no bound" (1e300): a text field, not a slider to 1e300.
      os << "        <DoubleRangeDomain name=\"range\" min=\"" << number(f.minimum) << "\"";
      if (f.maximum < 1e100)
        os << " max=\"" << number(f.maximum) << "\"";
      os << "/>\n";
      break;
    case SettingField::Kind::Numbers:
      break;
  }
  os << "        <Documentation>" << escape(f.help) << ". Range: " << escape(f.range_text())
     << "; default " << number(f.default_value()) << "; applies to " << escape(applies_text(f))
     << ". (Command line: " << escape(f.flag.empty() ? "no flag" : f.flag) << "; session key "
     << escape(f.key) << ".)</Documentation>\n";
  if (!f.methods.empty())
    os << "        <Hints>\n          <PropertyWidgetDecorator type=\"GenericDecorator\" "
          "mode=\"visibility\" property=\"Method\" values=\""
       << method_values(f) << "\"/>\n        </Hints>\n";
  os << "      </" << element << ">\n";
}

void write_weight_method(std::ostream& os)
{
  os << "<!-- Generated by barylab_paraview_xml from core/coordinates/weight_methods.cpp: do not "
        "edit. -->\n<ServerManagerConfiguration>\n  <ProxyGroup name=\"barylab_weight_methods\">\n"
        "    <Proxy name=\"WeightMethod\" class=\"vtkBaryPVWeightMethod\" label=\"Weight method\">\n"
        "      <Documentation short_help=\"A weight method and all its settings.\">The strategy "
        "that BaryLab's coordinates and deformation filters share (vtkBaryWeightMethod): the "
        "method and every setting of every method, from BaryLab's settings table.</Documentation>\n";
  const bary::WeightsSettings defaults;
  os << "      <IntVectorProperty name=\"Method\" label=\"Method\" command=\"SetMethod\" "
        "number_of_elements=\"1\" default_values=\""
     << static_cast<int>(defaults.method) << "\">\n        <EnumerationDomain name=\"enum\">\n";
  std::string methods_doc;
  for (const bary::MethodInfo& m : bary::method_table())
  {
    std::string title = m.title;
    if (!title.empty())
      title[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(title[0])));
    os << "          <Entry value=\"" << static_cast<int>(m.id) << "\" text=\""
       << escape(title + " (" + m.name + ")") << "\"/>\n";
    methods_doc += " " + m.name + ": " + m.title + ", " + m.reference + ";";
  }
  os << "        </EnumerationDomain>\n        <Documentation>The weight method (command line "
        "--method).";
  os << escape(methods_doc) << " the default is "
     << escape(bary::method_info(defaults.method).name) << ".</Documentation>\n"
     << "      </IntVectorProperty>\n";
  for (const SettingField& f : bary::weights_setting_fields())
    if (shown(f))
      write_property(os, f);
  os << "    </Proxy>\n  </ProxyGroup>\n</ServerManagerConfiguration>\n";
}

void write_sub_proxy(std::ostream& os, const std::string& indent)
{
  os << indent << "<!-- Generated from BaryLab's settings table (barylab_paraview_xml). -->\n"
     << indent << "<SubProxy command=\"SetWeightMethod\">\n"
     << indent << "  <Proxy name=\"WeightMethod\" proxygroup=\"barylab_weight_methods\" "
                  "proxyname=\"WeightMethod\"/>\n"
     << indent << "  <ExposedProperties>\n" << indent << "    <Property name=\"Method\"/>\n";
  for (const SettingField& f : bary::weights_setting_fields())
    if (shown(f))
      os << indent << "    <Property name=\"" << f.property << "\"/>\n";
  os << indent << "  </ExposedProperties>\n" << indent << "</SubProxy>\n";
  // Panel groups: the table's option groups ("" = general, shown with the method).
  std::vector<std::string> groups;
  for (const SettingField& f : bary::weights_setting_fields())
  {
    if (!shown(f))
      continue;
    bool known = false;
    for (const std::string& g : groups)
      known = known || g == f.group;
    if (!known)
      groups.push_back(f.group);
  }
  for (const std::string& group : groups)
  {
    std::string label = group.empty() ? "weight method" : group;
    label[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(label[0])));
    os << indent << "<PropertyGroup label=\"" << escape(label) << "\">\n";
    if (group.empty())
      os << indent << "  <Property name=\"Method\"/>\n";
    for (const SettingField& f : bary::weights_setting_fields())
      if (shown(f) && f.group == group)
        os << indent << "  <Property name=\"" << f.property << "\"/>\n";
    os << indent << "</PropertyGroup>\n";
  }
}

bool expand(const std::string& input, const std::string& output)
{
  std::ifstream in(input);
  if (!in)
  {
    std::cerr << "barylab_paraview_xml: cannot read " << input << "\n";
    return false;
  }
  std::ostringstream out;
  std::string line;
  bool found = false;
  while (std::getline(in, line))
  {
    const std::size_t at = line.find_first_not_of(" ");
    if (at == std::string::npos || line.compare(at, std::string::npos, "@BARYLAB_WEIGHT_METHOD@") != 0)
    {
      out << line << "\n";
      continue;
    }
    found = true;
    write_sub_proxy(out, line.substr(0, at));
  }
  if (!found)
  {
    std::cerr << "barylab_paraview_xml: " << input << " has no @BARYLAB_WEIGHT_METHOD@ line\n";
    return false;
  }
  std::ofstream file(output);
  file << out.str();
  return static_cast<bool>(file);
}
} // namespace

int main(int argc, char** argv)
{
  if (argc < 2 || argc % 2 != 0)
  {
    std::cerr << "usage: barylab_paraview_xml <weight_method.xml> [<template.xml.in> "
                 "<output.xml>]...\n";
    return 2;
  }
  {
    std::ofstream file(argv[1]);
    write_weight_method(file);
    if (!file)
    {
      std::cerr << "barylab_paraview_xml: cannot write " << argv[1] << "\n";
      return 1;
    }
  }
  for (int i = 2; i + 1 < argc; i += 2)
    if (!expand(argv[i], argv[i + 1]))
      return 1;
  return 0;
}
