#pragma once
// The cutting step of the refinement of deep mouth fillings (defined in trim.cpp, see "Refined
// fillings" there), declared here for its tests. Internal to steady::sweep.
#include <Eigen/Core>

#include <array>
#include <cstddef>
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

}  // namespace steady::sweep::detail
