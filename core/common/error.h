#pragma once
/// @file error.h
/// The one exception type thrown by BaryLab's core. Every message says what is wrong and,
/// where it can, how to fix it; the code lets callers (filters, CLI) react without parsing text.

#include <stdexcept>
#include <string>
#include <string_view>

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

/// @p text as one printable line: line breaks and tabs become spaces, other control bytes and
/// bytes that are not well-formed UTF-8 become "\xNN"; UTF-8 text is kept.
std::string one_line(std::string_view text);

/// Short stable name of a code ("invalid cage", ...).
const char* to_string(ErrorCode code) noexcept;

/// The project's error type. It carries what is wrong (message()) and, separately where a
/// caller may want to word it in its own terms (its option names, its command line), how to fix
/// it (advice()). what() is the whole text: the message, then "; " and the advice if there is
/// one.
///
/// Messages are one printable line, whatever went into them (a token of a binary file, a
/// reader's multi-line report): the constructor turns line breaks and tabs into spaces and
/// writes other control bytes and bytes that are not UTF-8 as \xNN (one_line()).
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
  Error(ErrorCode code, std::string&& message, std::string&& advice, int);
  ErrorCode code_;
  std::string message_;
  std::string advice_;
};

} // namespace bary
