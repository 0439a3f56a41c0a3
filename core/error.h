#pragma once
/// @file error.h
/// The one exception type thrown by BaryLab's core. Every message says what is wrong and,
/// where it can, how to fix it; the code lets callers (filters, CLI) react without parsing text.

#include <stdexcept>
#include <string>

namespace bary
{

/// What kind of problem an Error reports.
enum class ErrorCode
{
  InvalidArgument, ///< an option or argument is out of range
  EmptyInput,      ///< no points, no cage vertices, no faces
  SizeMismatch,    ///< matrices whose shapes do not fit together
  NonFinite,       ///< NaN or infinite coordinates or weights
  InvalidCage,     ///< open, non-manifold, inconsistently oriented, degenerate or self-intersecting cage
  Io,              ///< unreadable or unwritable file, unknown format
  Cancelled,       ///< the progress callback asked to stop
  NotConverged,    ///< an iterative solver did not reach its tolerance
  Internal         ///< a bug: please report it
};

/// Short stable name of a code ("invalid cage", ...).
const char* to_string(ErrorCode code) noexcept;

/// The project's error type.
class Error : public std::runtime_error
{
public:
  Error(ErrorCode code, const std::string& message);
  ErrorCode code() const noexcept { return code_; }

private:
  ErrorCode code_;
};

} // namespace bary
