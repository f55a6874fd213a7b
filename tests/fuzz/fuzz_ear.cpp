// Fuzz target of the EAR core (see tests/fuzz/README.md): real logarithms and powers of
// arbitrary 2D and 3D affinities.
//
// Input: byte 0 chooses the dimension (bit 0) and how the entries are read (bit 1): as raw
// doubles (8 bytes each: NaN, infinities, subnormals, huge and tiny values) or as small exact
// values (one signed byte each, divided by 16: exact repeated eigenvalues, Jordan blocks, half
// turns and other case borders). Missing entries are those of the identity. One more byte
// gives the exponent t (signed, divided by 32).
//
// Checks, beyond "a result or a steady::Error":
// - realLogExists(A) (never throws) agrees with log(A): log throws exactly when no real log
//   exists, with the same error code;
// - a log that exists is finite, and Span(A) builds;
// - when the affinity is moderate (|A| <= 1e3, |M| <= 8, Hadamard ratio of L >= 1e-6), the round
//   trip A^1 and the square of A^(1/2) are within 1e-8 (|A| + 1) of A, and pow(A, t) matches
//   Span(A).power(t) within 1e-8 of |A^t| + 1. These bounds are loose on purpose (the accuracy
//   targets, 5e-15 and 1e-14 on random sets, are checked by tests/oracle): only a gross loss of
//   accuracy near a case border is a finding here.
#include "fuzz_check.hpp"

#include <steady/core/ear.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>

namespace {

template <int D>
double hadamardRatio(const typename steady::Affine<D>::Linear& L) {
  double prod = 1;
  for (int j = 0; j < D; ++j) prod *= L.col(j).norm();
  return prod > 0 ? std::abs(L.determinant()) / prod : 0.0;
}

template <int D>
bool allFinite(const steady::Affine<D>& A) {
  return A.linear().allFinite() && A.translation().allFinite();
}

template <int D>
double distance(const steady::Affine<D>& A, const steady::Affine<D>& B) {
  return std::sqrt((A.linear() - B.linear()).squaredNorm() + (A.translation() - B.translation()).squaredNorm());
}

template <int D>
double size(const steady::Affine<D>& A) {
  return std::sqrt(A.linear().squaredNorm() + A.translation().squaredNorm());
}

template <int D>
void run(const std::uint8_t* data, std::size_t size_in, bool raw) {
  using A_t = steady::Affine<D>;
  typename A_t::Linear L = A_t::Linear::Identity();
  typename A_t::Vector t = A_t::Vector::Zero();
  steady::fuzz::NumberReader in(data, size_in, raw);
  for (int r = 0; r < D; ++r) {
    for (int c = 0; c < D; ++c) L(r, c) = in.next(L(r, c));
    t(r) = in.next(0.0);
  }
  const std::size_t at = in.position();
  const double tt = at < size_in ? static_cast<std::int8_t>(data[at]) / 32.0 : 0.5;
  const A_t A(L, t);

  const steady::Existence e = steady::realLogExists(A);
  steady::AffineLog<D> lg;
  bool threw = false;
  steady::ErrorCode code = steady::ErrorCode::InvalidArgument;
  try {
    lg = steady::log(A);
  } catch (const steady::Error& err) {
    threw = true;
    code = err.code();
  }
  FUZZ_CHECK(threw != e.exists, "realLogExists disagrees with log");
  if (threw) {
    FUZZ_CHECK(code == e.reason, "realLogExists gives another reason than log's error");
    return;
  }
  FUZZ_CHECK(lg.M.allFinite() && lg.u.allFinite(), "log returned a non-finite result");
  steady::Span<D> span(A);  // must not throw: log did not
  const A_t one = span.power(1.0), zero = span.power(0.0);
  const bool moderate = size(A) <= 1e3 && lg.M.norm() <= 8 && hadamardRatio<D>(L) >= 1e-6;
  if (!moderate) return;
  const double scale = size(A) + 1;
  FUZZ_CHECK(allFinite(one) && allFinite(zero), "a power of a moderate affinity is not finite");
  FUZZ_CHECK(distance(zero, A_t()) <= 1e-8, "A^0 is not the identity");
  FUZZ_CHECK(distance(one, A) <= 1e-8 * scale, "A^1 differs from A");
  const A_t half = span.power(0.5);
  FUZZ_CHECK(distance(half * half, A) <= 1e-8 * scale, "(A^(1/2))^2 differs from A");
  A_t p;
  const bool ok = steady::fuzz::typedOrOk("pow", [&] { p = steady::pow(A, tt); });
  FUZZ_CHECK(ok, "pow threw where log did not");
  const A_t q = span.power(tt);
  FUZZ_CHECK(distance(p, q) <= 1e-8 * (size(q) + 1), "pow(A, t) differs from Span(A).power(t)");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool three = data[0] & 1, raw = data[0] & 2;
  if (three) run<3>(data + 1, size - 1, raw);
  else run<2>(data + 1, size - 1, raw);
  return 0;
}
