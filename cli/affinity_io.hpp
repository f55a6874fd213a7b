#pragma once
// Reading affinity arguments of the steady tool and writing its JSON answers.
//
// An affinity argument is one of
//   * numbers separated by blanks and/or commas: D*(D+1) of them, the row-major D x (D+1) matrix
//     [L | t], or (D+1)^2 of them, a homogeneous matrix whose last row is 0 .. 0 1;
//   * inline JSON (text starting with '[' or '{'), with the shapes accepted for files;
//   * @FILE (or @- for standard input): a JSON file holding a D x (D+1) array of rows, a
//     (D+1) x (D+1) homogeneous array, a flat array of numbers, or an object whose "pose" member
//     is one of these (other members are ignored).

#include <steady/core/affine.hpp>

#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace steady_cli {

/// A bad command line or an unreadable argument value (exit status 2). The text names the
/// option and what is wrong with its value.
class UsageError : public std::runtime_error {
 public:
  UsageError(std::string tag, const std::string& message)
      : std::runtime_error(message), tag_(std::move(tag)) {}
  /// "usage" for option errors, "parse" for values that could not be read.
  const std::string& tag() const noexcept { return tag_; }

 private:
  std::string tag_;
};

/// The D*(D+1) entries of `[L | t]`, row-major, read from an affinity argument. `option` is the
/// option name used in error messages ("--affinity"). @throws UsageError("parse", ...).
std::vector<double> readAffinityEntries(const std::string& argument, int dim,
                                        const std::string& option);

/// The affinity of an argument (see readAffinityEntries).
template <int D>
steady::Affine<D> readAffinity(const std::string& argument, const std::string& option) {
  const std::vector<double> e = readAffinityEntries(argument, D, option);
  typename steady::Affine<D>::Matrix m;
  for (int r = 0; r < D; ++r)
    for (int c = 0; c <= D; ++c) m(r, c) = e[static_cast<std::size_t>(r * (D + 1) + c)];
  return steady::Affine<D>::fromMatrix(m);
}

/// Reads one real number of the command line (whole text, finite). @throws UsageError.
double readNumber(const std::string& text, const std::string& option);

using Json = nlohmann::ordered_json;

/// A number for output: -0 is written as 0.
inline double outputNumber(double x) { return x + 0.0; }

/// `[L | t]` as an array of D rows of D+1 numbers.
template <int D>
Json matrixJson(const steady::Affine<D>& a) {
  Json rows = Json::array();
  for (int r = 0; r < D; ++r) {
    Json row = Json::array();
    for (int c = 0; c < D; ++c) row.push_back(outputNumber(a.linear()(r, c)));
    row.push_back(outputNumber(a.translation()(r)));
    rows.push_back(std::move(row));
  }
  return rows;
}

/// Formats a JSON value for people and programs: arrays of scalars on one line, everything
/// else indented by two spaces; numbers in the shortest form that reads back to the same
/// double (never more than 17 significant digits, at least one decimal: 1.0). Ends with a
/// newline.
std::string formatJson(const Json& value);

}  // namespace steady_cli
