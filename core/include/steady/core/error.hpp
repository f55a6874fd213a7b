#pragma once
/// @file
/// Typed errors of steady. Every public function that can fail throws steady::Error, whose
/// code() says what went wrong and whose what() says what to do about it.

#include <stdexcept>
#include <string>

namespace steady {

/// Why an operation could not be carried out.
enum class ErrorCode {
  NonFinite,           ///< an input holds NaN or an infinity
  NotOrientationPreserving,  ///< det L < 0: a reflection has no real logarithm
  Singular,            ///< det L is zero (or numerically zero): the affinity is not invertible
  NoRealLog,           ///< det L > 0 but no real logarithm exists: there is no SAM (Culver)
  DegenerateInput,     ///< points or vectors that do not determine the requested object
  InvalidArgument,     ///< an argument outside its documented range
  InvalidFile,         ///< a file's content is malformed (the message gives its path inside the file)
  Io,                  ///< a file could not be read or written (the message names it and why)
  Cancelled,           ///< the caller asked a long operation to stop (e.g. SweepOptions::cancel); it returned nothing
};

/// Short stable name of a code ("no-real-log", ...), usable in JSON and logs.
const char* to_string(ErrorCode code) noexcept;

/// The exception type of steady. what() is a full sentence: the cause, then what to do.
class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message);
  /// The typed reason.
  ErrorCode code() const noexcept { return code_; }

 private:
  ErrorCode code_;
};

}  // namespace steady
