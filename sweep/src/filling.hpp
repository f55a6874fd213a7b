#pragma once
// The cutting step of the refinement of deep mouth fillings (defined in trim.cpp, see "Refined
// fillings" there), and the shape by which the mouth rounds remember the fillings they probed
// and refined, declared here for their tests. Internal to steady::sweep.
#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace steady::sweep::detail {

// Cuts the inner edges of `faces`, a triangulated filling of the closed polygon `loop` (indices
// into V, as are the faces' corners), into pieces no longer than about h: an edge longer than h
// whose middle lies farther than h/2 from the loop is cut at its middle, longest first, and both
// faces at it are cut in two. The edges on the loop are never cut (the surface around the
// filling shares them). A cut whose middle lies within h/2 of a point of the filling (one of its
// corners or an earlier middle) is skipped: the points thus stay h/2 apart, which bounds their
// number by the filling's area over h² (about 16 / pi per h², plus the loop's strip) and ends
// the cutting. Without that rule, faces whose longest edge lies on the loop could be cut at a
// shorter edge again and again, with middles converging on a point (a bracket polySAM, campaign
// case 2819: a filling of 9 faces and 468 ε² at h = ε ran past 200,000 points).
//
// The new points (middles, on the flat faces) are returned in `fresh`, numbered from V.size()
// on in the faces. Returns false, with `faces` and `fresh` in an unspecified state, when it
// would need more than max_points new points or when the two faces at an edge have the same
// third corner (they fold onto each other).
bool bisectFilling(const std::vector<Eigen::Vector3d>& V, const std::vector<int>& loop,
                   std::vector<std::array<int, 3>>& faces, std::vector<Eigen::Vector3d>& fresh, double h,
                   std::size_t max_points);

// A filling as the depth check of fillings and their refinement see it (trim.cpp: "Deep
// fillings", "Refined fillings"), which is all their results depend on: the points of its loop
// and faces renumbered by first appearance (the loop's first), their coordinates, and the order
// of their original numbers (a refinement cuts the longest edge first, and equally long edges
// in the order of their end points' numbers). The mouth rounds remember both results by it
// (MouthMemory in trim.cpp): a filling met again in a later round, with its points numbered
// anew, has the same shape when its results would be the same.
struct FillingShape {
  std::vector<int> global;  // the points' original numbers (not part of the shape)
  std::vector<Eigen::Vector3d> points;
  std::vector<int> rank;  // per point: its place among the points ordered by original number
  std::vector<int> loop;
  std::vector<std::array<int, 3>> faces;
  std::uint64_t hash = 0;  // of the rest
  // Same shape: the coordinates bit for bit, and the same ranks, loop and faces.
  bool operator==(const FillingShape& o) const {
    return points.size() == o.points.size() &&
           (points.empty() ||
            std::memcmp(points.data(), o.points.data(), points.size() * sizeof(Eigen::Vector3d)) == 0) &&
           rank == o.rank && loop == o.loop && faces == o.faces;
  }
};

// The shape of the filling `faces` of `loop` (indices into V, as are the faces' corners).
FillingShape shapeOf(const std::vector<Eigen::Vector3d>& V, const std::vector<int>& loop,
                     const std::vector<std::array<int, 3>>& faces);

}  // namespace steady::sweep::detail
