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
  PointsOutside,   ///< evaluation points outside where the method is defined (hull, domain mesh)
  Internal         ///< a bug: please report it
};

/// Short stable name of a code ("invalid cage", ...).
const char* to_string(ErrorCode code) noexcept;

/// The project's error type. It carries what is wrong (message()) and, separately where a
/// caller may want to word it in its own terms (its option names, its command line), how to fix
/// it (advice()). what() is the whole text: the message, then "; " and the advice if there is
/// one.
class Error : public std::runtime_error
{
public:
  Error(ErrorCode code, std::string message, std::string advice = {});
  ErrorCode code() const noexcept { return code_; }
  /// What is wrong (what() without the advice).
  const std::string& message() const noexcept { return message_; }
  /// How to fix it, in core's terms (option and function names); empty where the message says
  /// it or there is nothing to advise.
  const std::string& advice() const noexcept { return advice_; }

private:
  ErrorCode code_;
  std::string message_;
  std::string advice_;
};

} // namespace bary
