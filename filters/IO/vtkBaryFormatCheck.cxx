#include "vtkBaryFormatCheck.h"

#include "vtkBaryTextParsing.h"

#include "core/common/error.h"

#include <vtksys/SystemTools.hxx>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace vtkbary
{
namespace
{
using bary::Error;
using bary::ErrorCode;

} // namespace

void CheckSTLCount(const std::string& path, std::uintmax_t size)
{
  std::ifstream in(path, std::ios::binary);
  char head[84];
  if (!in.read(head, sizeof head))
    return; // shorter than a binary header: VTK's reader refuses or reads it as text
  // binary or text as vtkSTLReader decides it (vtksys' share of non-text bytes in the first
  // 256): a binary file may start with "solid" too
  if (vtksys::SystemTools::DetectFileType(path.c_str()) != vtksys::SystemTools::FileTypeBinary)
    return;
  const auto* b = reinterpret_cast<const unsigned char*>(head + 80);
  const std::uint64_t count = b[0] | (b[1] << 8) | (b[2] << 16) | (std::uint64_t(b[3]) << 24);
  if (84 + 50 * count > size)
    throw Error(ErrorCode::Io,
      "cannot read '" + path + "': a binary STL of " + std::to_string(size) + " bytes cannot hold "
        "the " + std::to_string(count) + " triangles its header announces (50 bytes each)");
}

void CheckXMLCounts(const std::string& path, std::uintmax_t size)
{
  std::ifstream in(path, std::ios::binary);
  // the header: up to the appended data (raw bytes after it are not markup)
  std::string header;
  header.reserve(static_cast<std::size_t>(std::min<std::uintmax_t>(size, 1u << 20)));
  std::string line;
  while (std::getline(in, line))
  {
    const std::size_t appended = line.find("<AppendedData");
    if (appended != std::string::npos)
    {
      header.append(line, 0, appended);
      break;
    }
    header += line;
    header += '\n';
  }
  const double room = 1100.0 * static_cast<double>(size) + 1e6;
  double largest = 0.0, components = 1.0;
  std::string largest_name;
  std::size_t at = 0;
  while ((at = header.find("Number", at)) != std::string::npos)
  {
    std::size_t name_end = at;
    while (name_end < header.size() && std::isalpha(static_cast<unsigned char>(header[name_end])))
      ++name_end;
    const std::string name = header.substr(at, name_end - at);
    at = name_end;
    if (name_end + 1 >= header.size() || header[name_end] != '=' ||
      (header[name_end + 1] != '"' && header[name_end + 1] != '\''))
      continue;
    const char quote = header[name_end + 1];
    const std::size_t close = header.find(quote, name_end + 2);
    if (close == std::string::npos)
      continue; // unterminated: the XML parser reports it
    const std::string value = header.substr(name_end + 2, close - name_end - 2);
    long long n = -1;
    if (!ParseInteger(value, n) || n < 0)
      throw Error(ErrorCode::Io,
        "cannot read '" + path + "': " + name + "=\"" + Printable(value) +
          "\" is not a count (a whole number from 0)");
    if (name == "NumberOfComponents")
      components = std::max(components, static_cast<double>(n));
    else if (static_cast<double>(n) > largest)
    {
      largest = static_cast<double>(n);
      largest_name = name;
    }
  }
  if (largest * components > room || components > room)
    throw Error(ErrorCode::Io,
      "cannot read '" + path + "': its header announces " + largest_name + "=" +
        std::to_string(static_cast<long long>(largest)) + " with up to " +
        std::to_string(static_cast<long long>(components)) +
        " components, more values than a file of " + std::to_string(size) +
        " bytes holds even compressed");
}

namespace
{
/// The value of attribute @p name in the tag text @p tag ("" when absent).
std::string attribute(std::string_view tag, std::string_view name)
{
  std::size_t at = 0;
  while ((at = tag.find(name, at)) != std::string_view::npos)
  {
    const bool starts = at > 0 && std::isspace(static_cast<unsigned char>(tag[at - 1]));
    std::size_t eq = at + name.size();
    while (eq < tag.size() && std::isspace(static_cast<unsigned char>(tag[eq])))
      ++eq;
    at += name.size();
    if (!starts || eq >= tag.size() || tag[eq] != '=')
      continue;
    std::size_t q = eq + 1;
    while (q < tag.size() && std::isspace(static_cast<unsigned char>(tag[q])))
      ++q;
    if (q >= tag.size() || (tag[q] != '"' && tag[q] != '\''))
      continue;
    const std::size_t close = tag.find(tag[q], q + 1);
    if (close == std::string_view::npos)
      return "";
    return std::string(tag.substr(q + 1, close - q - 1));
  }
  return "";
}

int base64_value(char c)
{
  if (c >= 'A' && c <= 'Z')
    return c - 'A';
  if (c >= 'a' && c <= 'z')
    return c - 'a' + 26;
  if (c >= '0' && c <= '9')
    return c - '0' + 52;
  if (c == '+')
    return 62;
  if (c == '/')
    return 63;
  return -1;
}

/// Decodes base64 from @p text at @p at (whitespace skipped) until @p bytes bytes are out or
/// the text ends; returns what was decoded.
std::string base64_prefix(std::string_view text, std::size_t at, std::size_t bytes)
{
  std::string out;
  unsigned buffer = 0;
  int bits = 0;
  for (; at < text.size() && out.size() < bytes; ++at)
  {
    const char c = text[at];
    if (std::isspace(static_cast<unsigned char>(c)))
      continue;
    const int v = base64_value(c);
    if (v < 0)
      break; // '=' padding or the end of the data
    buffer = (buffer << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8)
    {
      bits -= 8;
      out += static_cast<char>((buffer >> bits) & 0xff);
    }
  }
  return out;
}

/// Word @p k of @p bytes (@p width 4 or 8 bytes, @p big endian).
std::uint64_t word(const std::string& bytes, std::size_t k, std::size_t width, bool big)
{
  std::uint64_t v = 0;
  for (std::size_t b = 0; b < width; ++b)
  {
    const auto byte = static_cast<std::uint8_t>(bytes[k * width + (big ? b : width - 1 - b)]);
    v = (v << 8) | byte;
  }
  return v;
}
} // namespace

void CheckXMLCompression(const std::string& path, std::uintmax_t size)
{
  // The markup: the file up to the '_' that opens its appended data, or all of it when it has
  // none (inline data). Read in blocks and never past that point: a file of appended arrays
  // (what BaryLab writes: 600 MB for 10^6 points x 72 weights) is not read here beyond the
  // compression headers of its arrays, read at their offsets below.
  std::ifstream in(path, std::ios::binary);
  std::string file;
  {
    std::vector<char> block(1 << 16);
    std::size_t searched = 0, tag = std::string::npos;
    while (in)
    {
      in.read(block.data(), static_cast<std::streamsize>(block.size()));
      file.append(block.data(), static_cast<std::size_t>(in.gcount()));
      if (tag == std::string::npos)
      {
        tag = file.find("<AppendedData", searched);
        searched = file.size() > 16 ? file.size() - 16 : 0;
      }
      if (tag != std::string::npos)
      {
        const std::size_t tag_end = file.find('>', tag);
        const std::size_t underscore =
          tag_end == std::string::npos ? std::string::npos : file.find('_', tag_end);
        if (underscore != std::string::npos)
        {
          file.resize(underscore + 1);
          break;
        }
      }
    }
  }
  // n bytes of the file from @p start (fewer at its end)
  const auto bytes_at = [&path](std::size_t start, std::size_t n) {
    std::ifstream f(path, std::ios::binary);
    std::string bytes(n, '\0');
    f.seekg(static_cast<std::streamoff>(start));
    f.read(bytes.data(), static_cast<std::streamsize>(n));
    bytes.resize(f ? n : static_cast<std::size_t>(std::max<std::streamsize>(f.gcount(), 0)));
    return bytes;
  };
  const std::size_t root = file.find("<VTKFile");
  if (root == std::string::npos)
    return; // the XML reader refuses it
  const std::size_t root_end = file.find('>', root);
  const std::string_view root_tag = std::string_view(file).substr(root, root_end - root);
  // Every data array's type must be one VTK's XML readers know: VTK 9.1 dereferences a null
  // array for an unknown one in field data (found by the spline fuzz target: type="-nanFloat64").
  {
    static const char* const known[] = { "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32",
      "Int64", "UInt64", "Float32", "Float64", "String", "IdType", "Bit" };
    std::size_t at = 0;
    while ((at = file.find("<DataArray", at)) != std::string::npos)
    {
      const std::size_t tag_end = file.find('>', at);
      if (tag_end == std::string::npos)
        break;
      const std::string_view tag = std::string_view(file).substr(at, tag_end - at);
      at = tag_end;
      const std::string type = attribute(tag, "type");
      if (std::find(std::begin(known), std::end(known), type) == std::end(known))
        throw Error(ErrorCode::Io, "cannot read '" + path + "': the data array '" +
            Printable(attribute(tag, "Name")) + "' has type '" + Printable(type) +
            "', which is not a VTK XML data type");
    }
  }
  if (attribute(root_tag, "compressor").empty())
    return; // uncompressed data: VTK's reader clips reads to the sizes it finds
  const std::size_t width = attribute(root_tag, "header_type") == "UInt64" ? 8 : 4;
  const bool big = attribute(root_tag, "byte_order") == "BigEndian";
  const auto refuse = [&path](const std::string& what) {
    return Error(ErrorCode::Io, "cannot read '" + path + "': " + what);
  };

  // where appended data start (after the '_' that follows <AppendedData ...>)
  std::size_t appended = std::string::npos;
  bool appended_base64 = true;
  const std::size_t appended_tag = file.find("<AppendedData");
  if (appended_tag != std::string::npos)
  {
    const std::size_t tag_end = file.find('>', appended_tag);
    if (tag_end != std::string::npos)
    {
      appended_base64 = attribute(std::string_view(file).substr(appended_tag, tag_end - appended_tag),
                          "encoding") != "raw";
      const std::size_t underscore = file.find('_', tag_end);
      if (underscore != std::string::npos)
        appended = underscore + 1;
    }
  }
  const std::size_t markup_end = appended_tag == std::string::npos ? file.size() : appended_tag;
  const double room = 1100.0 * static_cast<double>(size) + 65536.0;

  std::size_t at = 0;
  while ((at = file.find("<DataArray", at)) != std::string::npos && at < markup_end)
  {
    const std::size_t tag_end = file.find('>', at);
    if (tag_end == std::string::npos)
      return;
    const std::string_view tag = std::string_view(file).substr(at, tag_end - at);
    at = tag_end;
    const std::string format = attribute(tag, "format");
    const std::string name = attribute(tag, "Name");
    // the compression header: 3 words, then one compressed size a block
    std::string header;
    const auto read = [&](std::size_t bytes) -> std::string {
      if (format == "binary")
        return base64_prefix(file, tag_end + 1, bytes);
      if (format != "appended" || appended == std::string::npos)
        return std::string(bytes, '\0'); // ascii: no header
      long long offset = -1;
      if (!ParseInteger(attribute(tag, "offset"), offset) || offset < 0 ||
        static_cast<std::uintmax_t>(offset) >= size - std::min<std::uintmax_t>(size, appended))
        throw refuse("the data array '" + Printable(name) + "' has no offset inside the appended data");
      const std::size_t start = appended + static_cast<std::size_t>(offset);
      if (!appended_base64)
        return bytes_at(start, bytes);
      // base64: 4 characters per 3 bytes, more where the text has whitespace
      const std::size_t least = 4 * (bytes / 3 + 2) + 64;
      for (std::size_t chars = least;; chars *= 2)
      {
        const std::string text = bytes_at(start, chars);
        std::string decoded = base64_prefix(text, 0, bytes);
        if (decoded.size() >= bytes || text.size() < chars || chars >= 16 * least)
          return decoded; // complete, the file's end, or not base64 (padding, other text)
      }
    };
    if (format != "binary" && format != "appended")
      continue;
    header = read(3 * width);
    if (header.size() < 3 * width)
      throw refuse("the data array '" + Printable(name) + "' ends inside its compression header");
    const std::uint64_t blocks = word(header, 0, width, big);
    const std::uint64_t block_size = word(header, 1, width, big);
    const std::uint64_t last_size = word(header, 2, width, big);
    if (static_cast<double>(blocks) * static_cast<double>(width) > static_cast<double>(size))
      throw refuse("the data array '" + Printable(name) + "' announces " + std::to_string(blocks) +
        " compressed blocks, more than the file holds");
    // no blocks with a partial last block: VTK's total size underflows and it reads block 0
    // of an empty table
    if (blocks == 0 && last_size == 0)
      continue;
    if (blocks == 0 || block_size == 0 || last_size > block_size ||
      static_cast<double>(block_size) > room)
      throw refuse("the data array '" + Printable(name) + "' has an invalid compression header "
        "(block size " + std::to_string(block_size) + ", last block " + std::to_string(last_size) + ")");
    header = read((3 + blocks) * width);
    if (header.size() < (3 + blocks) * width)
      throw refuse("the data array '" + Printable(name) + "' ends inside its compression header");
    double compressed = 0.0;
    for (std::uint64_t b = 0; b < blocks; ++b)
      compressed += static_cast<double>(word(header, 3 + b, width, big));
    if (compressed > static_cast<double>(size))
      throw refuse("the data array '" + Printable(name) + "' announces " +
        std::to_string(static_cast<long long>(compressed)) + " compressed bytes, more than the "
        "file's " + std::to_string(size));
  }
}
} // namespace vtkbary
