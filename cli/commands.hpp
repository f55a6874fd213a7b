#pragma once
// The commands of the steady tool. Each returns the complete text for standard output, so
// that nothing is printed unless the whole command succeeded. Errors are thrown:
// steady_cli::UsageError for bad arguments, steady::Error for math failures.

#include <steady/core/ear.hpp>

#include <optional>
#include <string>

namespace steady_cli {

/// `steady pow`: {"case", "result" (A^t as rows of [L | t]), "log" {"M", "u"}}.
std::string powCommand(const std::string& affinity, double t, int dim, const steady::EarOptions& options);

/// `steady sam`: {"case" (of C B^-1), "pose" (with t) or "poses" (with steps: steps + 1 poses,
/// the regular pattern from B to C), "log" (of C B^-1)}. Exactly one of t and steps is set.
std::string samCommand(const std::string& from, const std::string& to, std::optional<double> t,
                       std::optional<int> steps, int dim, const steady::EarOptions& options);

/// Output of `steady demo`.
struct DemoOutput {
  std::string json;     ///< what `steady sam --from START --to END --copies STEPS` prints
  std::string summary;  ///< one line for people (no newline)
};

/// `steady demo`: the regular pattern between the bundled poses. `data_dir` is the --data
/// value ("" to search the default places).
DemoOutput demoCommand(const std::string& data_dir, int steps);

}  // namespace steady_cli
