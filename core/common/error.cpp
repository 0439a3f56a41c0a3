#include "core/common/error.h"

#include <string_view>
#include <utility>

namespace bary
{

const char* to_string(ErrorCode code) noexcept
{
  switch (code)
  {
    case ErrorCode::InvalidArgument: return "invalid argument";
    case ErrorCode::EmptyInput: return "empty input";
    case ErrorCode::SizeMismatch: return "size mismatch";
    case ErrorCode::NonFinite: return "non-finite value";
    case ErrorCode::InvalidCage: return "invalid cage";
    case ErrorCode::Io: return "i/o error";
    case ErrorCode::Cancelled: return "cancelled";
    case ErrorCode::NotConverged: return "not converged";
    case ErrorCode::PointsOutside: return "points outside";
    case ErrorCode::Internal: return "internal error";
  }
  return "unknown error";
}

std::string one_line(std::string_view text)
{
  static const char* const hex = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  const auto escape = [&out](unsigned char c) {
    out += "\\x";
    out += hex[c >> 4];
    out += hex[c & 15];
  };
  std::size_t i = 0;
  while (i < text.size())
  {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x80)
    {
      if (c == '\n' || c == '\r' || c == '\t')
        out += ' ';
      else if (c < 0x20 || c == 0x7f)
        escape(c);
      else
        out += static_cast<char>(c);
      ++i;
      continue;
    }
    // a well-formed UTF-8 sequence (a file name in another script) is kept as it is
    const int length = (c & 0xe0) == 0xc0 ? 2 : (c & 0xf0) == 0xe0 ? 3 : (c & 0xf8) == 0xf0 ? 4 : 0;
    bool valid = length > 0 && c >= 0xc2 && c <= 0xf4 && i + length <= text.size();
    for (int k = 1; valid && k < length; ++k)
      valid = (static_cast<unsigned char>(text[i + k]) & 0xc0) == 0x80;
    if (valid)
    {
      out.append(text.substr(i, static_cast<std::size_t>(length)));
      i += static_cast<std::size_t>(length);
    }
    else
    {
      escape(c);
      ++i;
    }
  }
  return out;
}

Error::Error(ErrorCode code, std::string message, std::string advice)
  : Error(code, one_line(message), one_line(advice), 0)
{
}

Error::Error(ErrorCode code, std::string&& message, std::string&& advice, int)
  : std::runtime_error(advice.empty() ? message : message + "; " + advice)
  , code_(code)
  , message_(std::move(message))
  , advice_(std::move(advice))
{
}

} // namespace bary
