#pragma once
// A test switch of the mouth rounds' memory of refills. Internal to steady::sweep.
//
// The rounds that close the mouths of left-out walls refill the loops whose first filling is
// bad. A refill that the round before made for the same loop, with the same surface near it, is
// taken from that round instead of being searched again (see MouthMemory::Refilled in
// trim.cpp). Tests compare the envelopes with those of sweeps that search every refill anew.

#include <cstddef>

namespace steady::sweep::detail {

/// What the sweeps do with the refills of the round before while a RefillMemoryProbe lives.
enum class RefillMemory {
  kTake,    ///< take them where they apply (as without a probe)
  kForget,  ///< take none: search every refill anew (the envelopes must not change)
  kVerify,  ///< take them, and search each one taken anew as well, counting those that differ
};

/// While an object of this type lives, the sweeps run on the thread that made it treat the
/// refills of the round before as its mode says, and count them. Objects may nest; each restores
/// the setting it found, and counts only while no inner one lives.
class RefillMemoryProbe {
 public:
  explicit RefillMemoryProbe(RefillMemory mode);
  ~RefillMemoryProbe();
  RefillMemoryProbe(const RefillMemoryProbe&) = delete;
  RefillMemoryProbe& operator=(const RefillMemoryProbe&) = delete;

  /// The refills taken from the round before.
  std::size_t taken() const { return taken_; }
  /// Of those (kVerify), the ones whose search anew tested other triangles, found another outcome
  /// for one, or gave another filling: none may.
  std::size_t differing() const { return differing_; }

  struct Setting {
    RefillMemory mode;
    RefillMemoryProbe* probe;
  };

 private:
  friend void countRefills(std::size_t taken, std::size_t differing);
  Setting before_;
  std::size_t taken_ = 0, differing_ = 0;
};

}  // namespace steady::sweep::detail
