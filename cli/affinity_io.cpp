// Reading affinity arguments (numbers, inline JSON, @file) and formatting JSON output.

#include "affinity_io.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

namespace steady_cli {

namespace {

std::string trim(const std::string& s) {
  const char* blanks = " \t\r\n\f\v";
  const auto b = s.find_first_not_of(blanks);
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(blanks);
  return s.substr(b, e - b + 1);
}

[[noreturn]] void fail(const std::string& message) { throw UsageError("parse", message); }

// What an affinity of dimension `dim` looks like, for error messages.
std::string shapeHelp(int dim) {
  const int n = dim * (dim + 1);
  const int h = (dim + 1) * (dim + 1);
  std::string rows = dim == 3 ? "r00 r01 r02 tx r10 r11 r12 ty r20 r21 r22 tz" : "r00 r01 tx r10 r11 ty";
  return "expected " + std::to_string(n) + " numbers (the " + std::to_string(dim) + "x" +
         std::to_string(dim + 1) + " matrix [L | t] row by row: " + rows + ") or " +
         std::to_string(h) + " (a " + std::to_string(dim + 1) + "x" + std::to_string(dim + 1) +
         " homogeneous matrix)";
}

enum class NumberStatus { Ok, NotANumber, NotFinite, TooLarge };

// Whole-token strtod in the "C" locale (the tool never changes the locale).
NumberStatus parseDouble(const std::string& token, double& out) {
  if (token.empty() || std::isspace(static_cast<unsigned char>(token[0]))) return NumberStatus::NotANumber;
  errno = 0;
  char* end = nullptr;
  out = std::strtod(token.c_str(), &end);
  if (end != token.c_str() + token.size()) return NumberStatus::NotANumber;
  if (!std::isfinite(out)) return errno == ERANGE ? NumberStatus::TooLarge : NumberStatus::NotFinite;
  return NumberStatus::Ok;  // underflow to a subnormal or zero is accepted
}

std::string formatShort(double x) {
  std::ostringstream os;
  os.precision(6);
  os << x;
  return os.str();
}

// D*(D+1) entries from a flat list, which may also be a homogeneous matrix.
std::vector<double> entriesFromFlat(std::vector<double> v, int dim, const std::string& context) {
  const std::size_t n = static_cast<std::size_t>(dim * (dim + 1));
  const std::size_t h = static_cast<std::size_t>((dim + 1) * (dim + 1));
  if (v.size() == n) return v;
  if (v.size() == h) {
    bool affine = true;
    for (int c = 0; c <= dim; ++c) {
      const double want = c == dim ? 1.0 : 0.0;
      if (!(std::abs(v[n + static_cast<std::size_t>(c)] - want) <= 1e-12)) affine = false;
    }
    if (!affine) {
      std::string row;
      for (int c = 0; c <= dim; ++c) row += (c ? ", " : "") + formatShort(v[n + static_cast<std::size_t>(c)]);
      fail(context + ": the last row of the homogeneous matrix is (" + row + "), expected (" +
           (dim == 3 ? "0, 0, 0, 1" : "0, 0, 1") + "): a projective map is not an affinity");
    }
    v.resize(n);
    return v;
  }
  fail(context + ": " + shapeHelp(dim) + ", got " + (v.empty() ? std::string("none") : std::to_string(v.size())));
}

std::vector<double> entriesFromText(const std::string& text, int dim, const std::string& context) {
  std::vector<std::string> tokens;
  std::string current;
  for (char ch : text) {
    if (ch == ',' || ch == ';' || std::isspace(static_cast<unsigned char>(ch))) {
      if (!current.empty()) tokens.push_back(current);
      current.clear();
    } else {
      current += ch;
    }
  }
  if (!current.empty()) tokens.push_back(current);

  std::vector<double> v;
  v.reserve(tokens.size());
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    double x = 0;
    const std::string where = context + ": number " + std::to_string(i + 1) + " '" + tokens[i] + "'";
    switch (parseDouble(tokens[i], x)) {
      case NumberStatus::Ok: break;
      case NumberStatus::NotANumber: fail(where + " is not a number");
      case NumberStatus::NotFinite: fail(where + " is not finite: an affinity needs finite entries");
      case NumberStatus::TooLarge: fail(where + " is too large for a double");
    }
    v.push_back(x);
  }
  return entriesFromFlat(std::move(v), dim, context);
}

double jsonNumber(const nlohmann::json& j, const std::string& context, const std::string& index) {
  if (!j.is_number())
    fail(context + ": entry " + index + " is " + (j.is_null() ? std::string("null") : "a " + std::string(j.type_name())) +
         ", expected a number");
  const double x = j.get<double>();
  if (!std::isfinite(x)) fail(context + ": entry " + index + " is not finite (too large for a double)");
  return x;
}

std::vector<double> entriesFromJson(const nlohmann::json& j, int dim, const std::string& context, bool top) {
  const std::string shape = std::to_string(dim) + "x" + std::to_string(dim + 1);
  if (j.is_object()) {
    if (!top) fail(context + ": \"pose\" holds an object, expected a " + shape + " array of rows");
    const auto it = j.find("pose");
    if (it == j.end())
      fail(context + ": the JSON object has no \"pose\" member (expected a " + shape +
           " array of rows, or {\"pose\": [[...], ...]})");
    return entriesFromJson(*it, dim, context + ", member \"pose\"", false);
  }
  if (!j.is_array())
    fail(context + ": expected a " + shape + " array of rows, got " +
         (j.is_null() ? std::string("null") : "a " + std::string(j.type_name())));

  bool allRows = !j.empty();
  bool allScalars = true;
  for (const auto& e : j) {
    if (!e.is_array()) allRows = false;
    if (e.is_structured()) allScalars = false;
  }
  std::vector<double> v;
  if (allScalars) {  // a flat list of numbers (or an empty array)
    for (std::size_t i = 0; i < j.size(); ++i) v.push_back(jsonNumber(j[i], context, "[" + std::to_string(i) + "]"));
    return entriesFromFlat(std::move(v), dim, context);
  }
  if (!allRows) fail(context + ": the array mixes rows and other values, expected a " + shape + " array of rows");
  const std::size_t nrows = j.size();
  if (nrows != static_cast<std::size_t>(dim) && nrows != static_cast<std::size_t>(dim + 1))
    fail(context + ": expected " + std::to_string(dim) + " rows (a " + shape + " matrix [L | t]) or " +
         std::to_string(dim + 1) + " (homogeneous), got " + std::to_string(nrows));
  for (std::size_t r = 0; r < nrows; ++r) {
    const auto& row = j[r];
    if (row.size() != static_cast<std::size_t>(dim + 1))
      fail(context + ": row " + std::to_string(r) + " has " + std::to_string(row.size()) + " entries, expected " +
           std::to_string(dim + 1) + " (a " + shape + " matrix [L | t])");
    for (std::size_t c = 0; c < row.size(); ++c)
      v.push_back(jsonNumber(row[c], context, "[" + std::to_string(r) + "][" + std::to_string(c) + "]"));
  }
  return entriesFromFlat(std::move(v), dim, context);
}

std::vector<double> entriesFromJsonText(const std::string& text, int dim, const std::string& context) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // Drop the "[json.exception.parse_error.101] " prefix; keep "parse error at line L, column C: ...".
    std::string what = e.what();
    const auto close = what.find("] ");
    if (what.rfind("[json.exception.", 0) == 0 && close != std::string::npos) what = what.substr(close + 2);
    fail(context + ": malformed JSON: " + what);
  }
  return entriesFromJson(j, dim, context, true);
}

std::string readWholeFile(const std::string& path, const std::string& option) {
  if (path == "-") {
    std::string text((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
    if (std::cin.bad()) fail(option + ": cannot read standard input");
    return text;
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) fail(option + ": cannot read '" + path + "': it is a directory");
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    fail(option + ": cannot read '" + path + "': " + (err ? std::strerror(err) : "cannot open the file"));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) fail(option + ": error while reading '" + path + "'");
  return text.str();
}

void writeJson(std::string& out, const Json& j, int indent) {
  const std::string pad(static_cast<std::size_t>(indent), ' ');
  const std::string inner(static_cast<std::size_t>(indent + 2), ' ');
  if (j.is_array()) {
    if (j.empty()) {
      out += "[]";
      return;
    }
    bool scalars = true;
    for (const auto& e : j) scalars = scalars && !e.is_structured();
    if (scalars) {
      out += '[';
      for (std::size_t i = 0; i < j.size(); ++i) out += (i ? ", " : "") + j[i].dump();
      out += ']';
      return;
    }
    out += "[\n";
    for (std::size_t i = 0; i < j.size(); ++i) {
      out += inner;
      writeJson(out, j[i], indent + 2);
      out += i + 1 < j.size() ? ",\n" : "\n";
    }
    out += pad + ']';
  } else if (j.is_object()) {
    if (j.empty()) {
      out += "{}";
      return;
    }
    out += "{\n";
    std::size_t i = 0;
    for (const auto& item : j.items()) {
      out += inner + Json(item.key()).dump() + ": ";
      writeJson(out, item.value(), indent + 2);
      out += ++i < j.size() ? ",\n" : "\n";
    }
    out += pad + '}';
  } else {
    out += j.dump();  // numbers: shortest text that reads back to the same double
  }
}

}  // namespace

std::vector<double> readAffinityEntries(const std::string& argument, int dim, const std::string& option) {
  const std::string text = trim(argument);
  if (text.empty()) fail(option + ": the affinity is empty; " + shapeHelp(dim));
  if (text[0] == '@') {
    const std::string path = text.substr(1);
    if (path.empty()) fail(option + ": missing file name after '@'");
    const std::string content = readWholeFile(path, option);
    return entriesFromJsonText(content, dim, option + ": '" + path + "'");
  }
  if (text[0] == '[' || text[0] == '{') return entriesFromJsonText(text, dim, option + " (inline JSON)");
  return entriesFromText(text, dim, option);
}

double readNumber(const std::string& text, const std::string& option) {
  const std::string t = trim(text);
  double x = 0;
  switch (parseDouble(t, x)) {
    case NumberStatus::Ok: return x;
    case NumberStatus::NotANumber: fail(option + ": '" + t + "' is not a number");
    case NumberStatus::NotFinite: fail(option + ": '" + t + "' is not finite");
    case NumberStatus::TooLarge: fail(option + ": '" + t + "' is too large for a double");
  }
  return x;
}

std::string formatJson(const Json& value) {
  std::string out;
  writeJson(out, value, 0);
  out += '\n';
  return out;
}

}  // namespace steady_cli
