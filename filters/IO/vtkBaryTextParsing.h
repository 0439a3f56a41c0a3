/**
 * @file   vtkBaryTextParsing.h
 * @brief  Number parsing shared by BaryLab's text readers (OFF, OBJ, MEDIT, TGF, .dmat, poses,
 *         number lists); private to the IO module.
 *
 * Locale-independent (std::from_chars: a GUI may set a decimal-comma locale), full double
 * precision, a leading '+' accepted, and three outcomes a reader can name in its message: a
 * number, not a number, or a number that double cannot hold (|x| above 1.8e308, "1e999").
 * Underflow ("1e-400") reads as the nearest double (0 or a denormal), as strtod does.
 */
#ifndef vtkBaryTextParsing_h
#define vtkBaryTextParsing_h

#include "vtkErrorCode.h"

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>

namespace vtkbary
{
/// The error code (vtkAlgorithm::GetErrorCode) of BaryLab's readers for a NaN or infinite
/// coordinate, which vtkBaryDataIO::Read reports as bary::ErrorCode::NonFinite.
constexpr unsigned long NonFiniteErrorCode = vtkErrorCode::UserError + 1;

enum class Parsed
{
  Ok,
  NotANumber,
  OutOfRange, ///< a finite decimal whose magnitude double cannot hold
};

/// Parses all of @p token as a double ("nan" and "inf" parse, as themselves).
inline Parsed ParseDouble(std::string_view token, double& x)
{
  const char* begin = token.data();
  const char* const end = token.data() + token.size();
  if (begin != end && *begin == '+')
    ++begin;
  if (begin == end || *begin == '+' || *begin == ' ')
    return Parsed::NotANumber;
  auto r = std::from_chars(begin, end, x);
  if (r.ec == std::errc::result_out_of_range)
  {
    // overflow or underflow: the wider type tells which (an underflow is a tiny number)
    long double wide = 0.0L;
    r = std::from_chars(begin, end, wide);
    if (r.ec == std::errc::result_out_of_range || std::fabs(wide) > 1.7976931348623157e308L)
      return r.ptr == end ? Parsed::OutOfRange : Parsed::NotANumber;
    x = static_cast<double>(wide);
  }
  if (r.ec != std::errc() || r.ptr != end)
    return Parsed::NotANumber;
  return Parsed::Ok;
}

/// Parses all of @p token as a whole number that fits a long long (no '+', no decimals).
inline bool ParseInteger(std::string_view token, long long& n)
{
  const char* const end = token.data() + token.size();
  const auto r = std::from_chars(token.data(), end, n);
  return r.ec == std::errc() && r.ptr == end && !token.empty();
}

/// @p s with control characters and bytes above 126 written as \xNN and cut to @p max
/// characters (with "..."): a file's token quoted in a one-line message.
inline std::string Printable(std::string_view s, std::size_t max = 40)
{
  static const char* const hex = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i)
  {
    if (out.size() >= max)
    {
      out += "...";
      break;
    }
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 32 && c < 127)
      out += static_cast<char>(c);
    else
    {
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}
} // namespace vtkbary

#endif
