// Test helper of the steady CLI tests: checks a JSON document against expectations.
//
//   steady_cli_json_check ACTUAL_FILE TOL SPEC...
//
// SPEC is one of
//   JSON            the document must contain this value (see below) at its root;
//   /POINTER=JSON   the value at the JSON pointer must contain this value;
//   /POINTER#N      the array or object at the pointer has N elements;
//   /POINTER<=X     the number at the pointer is at most X (exactly: no tolerance);
//   /POINTER>=X     the number at the pointer is at least X (exactly);
//   /POINTER^/SUB   the array at the pointer is in non-decreasing order of the numbers at the
//                   JSON pointer SUB inside its elements (SUB empty: the elements themselves).
// "Contain": objects need every expected member (others are allowed); arrays must have the same
// length and matching elements; numbers must agree within TOL * max(1, |expected|); strings,
// booleans and null must be equal. Exit status 0 when everything matches, 1 otherwise (each
// mismatch is printed with its JSON pointer), 2 for bad usage.

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using nlohmann::json;

namespace {

std::string show(const json& j) {
  if (j.is_number_float()) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", j.get<double>());
    return buf;
  }
  std::string s = j.dump();
  return s.size() > 120 ? s.substr(0, 117) + "..." : s;
}

void compare(const json& actual, const json& expected, const std::string& path, double tol,
             std::vector<std::string>& errors) {
  const std::string where = path.empty() ? "/" : path;
  if (expected.is_object()) {
    if (!actual.is_object()) {
      errors.push_back(where + ": expected an object, got " + show(actual));
      return;
    }
    for (const auto& item : expected.items()) {
      const auto it = actual.find(item.key());
      if (it == actual.end())
        errors.push_back(where + ": missing member \"" + item.key() + "\"");
      else
        compare(*it, item.value(), path + "/" + item.key(), tol, errors);
    }
  } else if (expected.is_array()) {
    if (!actual.is_array() || actual.size() != expected.size()) {
      errors.push_back(where + ": expected an array of " + std::to_string(expected.size()) + " elements, got " +
                       show(actual));
      return;
    }
    for (std::size_t i = 0; i < expected.size(); ++i)
      compare(actual[i], expected[i], path + "/" + std::to_string(i), tol, errors);
  } else if (expected.is_number()) {
    if (!actual.is_number()) {
      errors.push_back(where + ": expected a number, got " + show(actual));
      return;
    }
    const double a = actual.get<double>(), e = expected.get<double>();
    if (!(std::abs(a - e) <= tol * std::max(1.0, std::abs(e))))
      errors.push_back(where + ": got " + show(json(a)) + ", expected " + show(json(e)) + " (tolerance " +
                       show(json(tol)) + ")");
  } else if (actual != expected) {
    errors.push_back(where + ": got " + show(actual) + ", expected " + show(expected));
  }
}

json parseOrDie(const std::string& text, const std::string& what) {
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    std::cerr << "json_check: " << what << " is not valid JSON: " << e.what() << "\n";
    std::exit(what == "the output" ? 1 : 2);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: steady_cli_json_check ACTUAL_FILE TOL SPEC...\n";
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary);
  if (!in) {
    std::cerr << "json_check: cannot read " << argv[1] << "\n";
    return 2;
  }
  std::stringstream text;
  text << in.rdbuf();
  const json actual = parseOrDie(text.str(), "the output");
  const double tol = std::stod(argv[2]);

  std::vector<std::string> errors;
  for (int i = 3; i < argc; ++i) {
    const std::string spec = argv[i];
    std::string pointer;
    std::string value = spec;
    char op = '=';
    if (!spec.empty() && spec[0] == '/') {
      const auto cut = spec.find_first_of("=#<>^");
      if (cut == std::string::npos || ((spec[cut] == '<' || spec[cut] == '>') && spec.compare(cut + 1, 1, "=") != 0)) {
        std::cerr << "json_check: spec '" << spec << "' needs =JSON, #N, <=X, >=X or ^/SUB\n";
        return 2;
      }
      pointer = spec.substr(0, cut);
      op = spec[cut];
      value = spec.substr(op == '<' || op == '>' ? cut + 2 : cut + 1);
    }
    const json::json_pointer ptr(pointer);
    if (!actual.contains(ptr)) {
      errors.push_back(pointer + ": missing");
      continue;
    }
    const json& here = actual.at(ptr);
    if (op == '<' || op == '>') {
      const json bound = parseOrDie(value, "the bound '" + value + "'");
      if (!bound.is_number()) {
        std::cerr << "json_check: the bound in '" << spec << "' is not a number\n";
        return 2;
      }
      const double b = bound.get<double>();
      if (!here.is_number())
        errors.push_back(pointer + ": expected a number, got " + show(here));
      else if (op == '<' ? !(here.get<double>() <= b) : !(here.get<double>() >= b))
        errors.push_back(pointer + ": got " + show(json(here.get<double>())) + ", expected " + (op == '<' ? "<= " : ">= ") +
                         show(json(b)));
    } else if (op == '^') {
      const json::json_pointer sub(value);
      if (!here.is_array()) {
        errors.push_back(pointer + ": expected an array, got " + show(here));
        continue;
      }
      for (std::size_t k = 0; k < here.size(); ++k) {
        const std::string at = pointer + "/" + std::to_string(k) + value;
        if (!here[k].contains(sub) || !here[k].at(sub).is_number()) {
          errors.push_back(at + ": missing or not a number");
          break;
        }
        if (k > 0 && here[k].at(sub).get<double>() < here[k - 1].at(sub).get<double>()) {
          errors.push_back(at + ": " + show(json(here[k].at(sub).get<double>())) + " comes after " +
                           show(json(here[k - 1].at(sub).get<double>())) + ": not in non-decreasing order");
          break;
        }
      }
    } else if (op == '#') {
      const std::size_t n = std::stoul(value);
      if (!here.is_structured() || here.size() != n)
        errors.push_back(pointer + ": expected " + std::to_string(n) + " elements, got " + show(here));
    } else {
      compare(here, parseOrDie(value, "the expectation '" + value + "'"), pointer, tol, errors);
    }
  }
  for (const auto& e : errors) std::cerr << "json_check: mismatch at " << e << "\n";
  return errors.empty() ? 0 : 1;
}
