#pragma once
// The last step of the output stage (defined in trim.cpp): vertices of kept walls and inner
// shells that the certificate could not place within ε of the true boundary, moved onto it
// where that is safe (Envelope::uncertified_vertices_moved). Declared here for its tests.
// Internal to steady::sweep.
#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

namespace steady::sweep::detail {

// The bisection bracket (units of ε) of the crossing of the boundary, and how far short of
// the crossing (units of ε) a vertex is placed when the crossing itself is refused, in the
// order tried.
constexpr double kSettleBracket = 1.0 / 64;
constexpr std::array<double, 3> kSettleShort = {{0.0, 0.5, 0.85}};

// Moves vertices of the closed surface (V, T) onto the boundary of the region that `inside`
// tests (the swept volume; the predicate must give the same answer for the same point).
// `across` lists vertices with a point on the other side of the boundary from them (the probe
// their certificate found at its bound, depth_bound.hpp), in the order they are taken.
//
// A vertex x with such a point y moves towards the crossing b of the segment x-y, found by
// bisection to kSettleBracket ε (so b lies within half of that of a point where the answer
// changes). The vertex goes first to b, then to the points kSettleShort ε short of it on the
// segment (still within ε of the crossing), whichever is first allowed. A target on the side
// of the surface that it encloses (against the vertex's normal, the sum of its faces' area
// vectors, when x is inside the region; along it when x is outside) is allowed only within ε
// of x: the move then takes the region's points between the old and new faces out of the
// enclosed part, and each of them lies within the length of the move of the new faces, so a
// point of the region that the surface enclosed is still enclosed or within ε of it. When no
// target is allowed, the same is tried towards the other probes at the distance |y - x| that
// get the other answer: across each face at x (both ways), then the 26 directions of a cube.
// A position is allowed when no face at the vertex turns by a right angle or more, none loses
// its area (exact collinearity test on the double coordinates), and none crosses any other
// face of the surface (exact predicates, shared corners and edges allowed as in the
// arrangement's crossing test). So the surface stays closed, keeps its orientation and gains
// no self-intersection; a vertex moves by at most |y - x|. The vertices are taken one by one,
// each tested against the moves before it.
//
// Returns how many moved; the others keep their coordinates exactly. The caller certifies the
// moved vertices again: a vertex placed short of the crossing is within ε of the boundary, but
// the probes need not find it so.
std::size_t settleVertices(std::vector<Eigen::Vector3d>& V, const std::vector<std::array<int, 3>>& T,
                           const std::vector<std::pair<int, Eigen::Vector3d>>& across,
                           const std::function<bool(const Eigen::Vector3d&)>& inside, double eps);

}  // namespace steady::sweep::detail
