#pragma once
// How far the re-sweeps (SweepOptions::refinements) measure an envelope they may replace, and
// which spans they refine. Internal to steady::sweep.
//
// Certifying the walls and inner shells an envelope keeps costs little per point that lies
// within ε of the true boundary, and a great deal per point that does not: the depth bound
// tries every probe before it gives up (depth_bound.hpp). A sweep that leaves many such points
// spends most of its time on them (bunny00's benchmark screw at a relative tolerance of 1e-2:
// 25,624 points, 197 s of a 216 s output stage). So when a re-sweep may replace the envelope,
// measuring stops once kDoubtCap points deeper than ε are found; envelopes with that many or
// more count as equally doubtful when the best one is chosen, and the one returned has its
// certificates finished (its lists are then complete). Whether an envelope reaches the cap
// does not depend on the threads: the count only grows, and reaches the cap exactly when the
// complete count would.

#include <steady/sweep/envelope.hpp>

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <vector>

namespace steady::sweep::detail {

/// The count of points deeper than ε (kept-wall and cavity vertices and face centroids) past
/// which an envelope that a re-sweep may replace is no longer measured. Far above the largest
/// count seen on the seeded campaign's envelopes that were swept again (118).
constexpr std::size_t kDoubtCap = 256;

/// sweptEnvelope(body, motion, options) with another cap in place of kDoubtCap (>= 1); tests use
/// it to make the cap matter on small cases.
Envelope sweptEnvelope(const Body& body, const Motion3& motion, const SweepOptions& options, std::size_t doubt_cap);

/// How far, in units of ε, a doubtful point reaches for the spans a re-sweep refines (see
/// spansNear). The point is on a kept wall or inner shell, which lies on some span's cycle
/// triangles, and the other side of its crack or pocket lies within a few ε (the depth bounds
/// look 8 ε far), so the spans whose triangles come that close are the ones whose tessellation
/// made it.
constexpr double kRefineReach = 8;

/// A re-sweep refines only the spans near the doubtful points when they are at most this share
/// of the spans, and every span otherwise. Refining fewer spans re-tessellates less, but it
/// also changes which cracks a re-sweep happens to close. On the seeded campaign's polySAMs (2
/// or 3 spans; 183 cases, 116 of them re-swept, each run both ways at once) refining the
/// near spans alone saved 6 to 7% of their time while one more case in 61 and one more in 122
/// failed (each reported). Along the bundled `keys.json` (112 spans) the elephant's re-sweeps
/// refined 28 spans, and its sweep took 32 to 33 s instead of 40 to 46 s and 0.70 GB instead
/// of 0.99 GB, with as many points listed (two runs each, alternating).
constexpr double kRefineFew = 0.25;

/// Per span, whether one of `points` lies in the box of one of its triangles grown by `reach`
/// on every side. Span i's triangles are triangles[span_end[i - 1], span_end[i]) (from 0 for
/// span 0), indices into `vertices`; `span_end` is non-decreasing and ends at most at
/// triangles.size(). A box test, so it may pick a span whose triangles pass farther than
/// `reach` from every point (a long strip triangle's box is large), never the other way round.
std::vector<char> spansNear(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& vertices,
                            const std::vector<std::array<int, 3>>& triangles, const std::vector<std::size_t>& span_end,
                            double reach);

}  // namespace steady::sweep::detail
