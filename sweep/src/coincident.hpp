#pragma once
// A test switch of the exact arrangement's merge of coincident faces. Internal to steady::sweep.
//
// The arrangement merges faces that lie on the same three points (coplanar layers) into one face
// with a weight. It compares only the faces cut from cycle triangles that can have such a
// partner: a twin on the same three points, or a crossing pair cut as coplanar (or in general);
// see mergeCoincident in trim.cpp for why no other face can. Tests compare that merge with one
// over every face.

namespace steady::sweep::detail {

/// While an object of this type lives, the sweeps run on the thread that made it compare every
/// face of their arrangements for coincidence, not only the flagged ones. The envelopes must
/// not change. Objects may nest; each restores the setting it found.
class MergeEveryFace {
 public:
  MergeEveryFace();
  ~MergeEveryFace();
  MergeEveryFace(const MergeEveryFace&) = delete;
  MergeEveryFace& operator=(const MergeEveryFace&) = delete;

 private:
  bool before_;
};

}  // namespace steady::sweep::detail
