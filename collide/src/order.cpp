// The orders that make the contact queries deterministic, whatever the order in which Embree's
// threads report candidate pairs: broad-phase pairs by feature, contacts by time and then
// features (see internal.hpp).
#include "internal.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <tuple>
#include <vector>

namespace steady::detail {

void sortPairs(std::vector<PairHit>& pairs) {
  auto before = [](const PairHit& x, const PairHit& y) {
    return x.moving != y.moving ? x.moving < y.moving : x.fixed < y.fixed;
  };
  std::sort(pairs.begin(), pairs.end(), before);
  pairs.erase(std::unique(pairs.begin(), pairs.end(),
                          [](const PairHit& x, const PairHit& y) { return x.moving == y.moving && x.fixed == y.fixed; }),
              pairs.end());
}

namespace {
// A double's bits as an integer in the order of the doubles (-0 just before +0; NaNs, which no
// contact holds, at the ends): a total order with no floating-point comparison.
std::int64_t orderedBits(double x) {
  std::int64_t i;
  std::memcpy(&i, &x, sizeof i);
  return i < 0 ? std::numeric_limits<std::int64_t>::min() - i - 1 : i;
}
}  // namespace

bool contactBefore(const Contact& x, const Contact& y) {
  // At equal times: certain before uncertain, crossing before touching (a touch is often a
  // sliding vertex on the plane of a face that other features cross at that very time).
  auto key = [](const Contact& c) {
    return std::make_tuple(orderedBits(c.t), !c.certain, c.crossing == 0, c.span, orderedBits(c.span_time),
                           static_cast<int>(c.type), c.a, c.b, c.crossing, orderedBits(c.point.x()),
                           orderedBits(c.point.y()), orderedBits(c.point.z()), orderedBits(c.normal.x()),
                           orderedBits(c.normal.y()), orderedBits(c.normal.z()), orderedBits(c.t_latest));
  };
  return key(x) < key(y);
}

}  // namespace steady::detail
