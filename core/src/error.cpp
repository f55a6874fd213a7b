#include <steady/core/error.hpp>

namespace steady {

const char* to_string(ErrorCode code) noexcept {
  switch (code) {
    case ErrorCode::NonFinite: return "non-finite";
    case ErrorCode::NotOrientationPreserving: return "not-orientation-preserving";
    case ErrorCode::Singular: return "singular";
    case ErrorCode::NoRealLog: return "no-real-log";
    case ErrorCode::DegenerateInput: return "degenerate-input";
    case ErrorCode::InvalidArgument: return "invalid-argument";
    case ErrorCode::InvalidFile: return "invalid-file";
    case ErrorCode::Io: return "io";
    case ErrorCode::Cancelled: return "cancelled";
  }
  return "unknown";
}

Error::Error(ErrorCode code, const std::string& message) : std::runtime_error(message), code_(code) {}

}  // namespace steady
