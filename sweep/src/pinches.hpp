#pragma once
// The step of the sweep's output stage that moves apart the copies of pinched vertices
// (defined in trim.cpp), declared here for its tests. Internal to steady::sweep.
#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <vector>

namespace steady::sweep::detail {

// Moves the copies of every split pinch vertex (vertices of V at equal positions: a group) a
// little, so that the fans of faces of T, which touched at one point, no longer meet.
//
// Each group tries five directions in turn: every copy towards the centroid of its own fan's
// ring (each fan lies on its own side of the point, whether it bounds a solid cone or an empty
// one); where that fails (sheets touching tangentially), every copy into the solid behind its
// fan (against its area-weighted normal), then out of it; then towards its ring the copy whose
// fan opens the widest alone, then the others alone. The step is 1e-3 times the ring distance
// and at most 1e-3 ε (kPinchStep in trim.cpp); a group whose moved faces would cross any face
// (CGAL's exact test on the doubles) halves its step, 20 times per direction.
//
// The groups that no direction separates are taken again in clusters of groups joined by
// edges: where two sheets touch along an edge, both of its ends must move the same sheet, which
// one direction per group may not do. Each copy of a cluster of at most 6 copies stays or takes
// one of the first three directions, every combination in a fixed order, at the full step and
// at 2^-10 of it; the first combination with no crossing is kept, or the cluster is put back.
//
// A group's moves are tested against its neighbours where they stand in the same round, so a
// neighbour put back later can void that test. At the end the faces of the moved copies are
// tested again (as the output check does); the moved groups at a crossing face start over with
// every other group fixed, then the clusters are retried with the groups put back, for at most
// 4 passes. Without a crossing nothing changes.
//
// Returns the number of vertices that still share a position with a vertex before them (one per
// pair of copies left touching: Envelope::pinches_touching). The crossing tests of a round run
// on `threads` threads (as SweepOptions::threads: 0 for all cores); the result does not depend
// on them.
std::size_t separatePinches(std::vector<Eigen::Vector3d>& V, const std::vector<std::array<int, 3>>& T, double eps,
                            int threads);

}  // namespace steady::sweep::detail
