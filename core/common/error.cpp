#include "core/common/error.h"

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

Error::Error(ErrorCode code, std::string message, std::string advice)
  : std::runtime_error(advice.empty() ? message : message + "; " + advice)
  , code_(code)
  , message_(std::move(message))
  , advice_(std::move(advice))
{
}

} // namespace bary
