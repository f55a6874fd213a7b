#pragma once
// Shared by the fuzz targets (see tests/fuzz/README.md): what counts as a finding.
//
// A target calls the library on its input and accepts two outcomes: a result that passes the
// target's checks, or a steady::Error (the library's typed error, the documented answer to bad
// input). Anything else is a finding and aborts the process, so that libFuzzer (and the replay
// tests) report it: a crash or a sanitizer report, an exception of another type, or a broken
// check (FUZZ_CHECK below).
#include <steady/core/error.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>

// Aborts with `what` when `cond` is false.
#define FUZZ_CHECK(cond, what)                                                                 \
  do {                                                                                         \
    if (!(cond)) {                                                                             \
      std::fprintf(stderr, "fuzz check failed at %s:%d: %s (%s)\n", __FILE__, __LINE__, what, \
                   #cond);                                                                     \
      std::abort();                                                                            \
    }                                                                                          \
  } while (0)

namespace steady::fuzz {

// Runs fn(); a steady::Error is an accepted answer (returns false), any other exception aborts
// with its message. Returns true when fn returned normally. With STEADY_FUZZ_VERBOSE set in the
// environment, every outcome is printed (to see what a corpus reaches).
template <class Fn>
bool typedOrOk(const char* what, Fn&& fn) {
  static const bool verbose = std::getenv("STEADY_FUZZ_VERBOSE") != nullptr;
  try {
    fn();
    if (verbose) std::fprintf(stderr, "  %s: ok\n", what);
    return true;
  } catch (const steady::Error& e) {
    if (verbose) std::fprintf(stderr, "  %s: %s: %s\n", what, steady::to_string(e.code()), e.what());
    return false;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz: %s threw a non-steady exception: %s\n", what, e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "fuzz: %s threw a non-exception\n", what);
    std::abort();
  }
}

// Numbers read from a fuzz input, one after the other: as raw doubles (8 bytes each, so NaN,
// infinities, subnormals, huge and tiny values), or as small exact values (one signed byte each,
// divided by 16: exact zeros, halves, repeated eigenvalues, half and quarter turns, and the
// other case borders). `fallback` once the input is used up.
class NumberReader {
 public:
  NumberReader(const std::uint8_t* data, std::size_t size, bool raw) : data_(data), size_(size), raw_(raw) {}
  double next(double fallback) {
    if (raw_) {
      if (at_ + 8 > size_) return fallback;
      double x;
      std::memcpy(&x, data_ + at_, 8);
      at_ += 8;
      return x;
    }
    if (at_ + 1 > size_) return fallback;
    return static_cast<std::int8_t>(data_[at_++]) / 16.0;
  }
  // Bytes read so far.
  std::size_t position() const { return at_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  bool raw_;
  std::size_t at_ = 0;
};

}  // namespace steady::fuzz
