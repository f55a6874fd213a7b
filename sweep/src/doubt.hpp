#pragma once
// How far the re-sweeps (SweepOptions::refinements) measure an envelope they may replace.
// Internal to steady::sweep.
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

#include <cstddef>

namespace steady::sweep::detail {

/// The count of points deeper than ε (kept-wall and cavity vertices and face centroids) past
/// which an envelope that a re-sweep may replace is no longer measured. Far above the largest
/// count seen on the seeded campaign's envelopes that were swept again (118).
constexpr std::size_t kDoubtCap = 256;

/// sweptEnvelope(body, motion, options) with another cap in place of kDoubtCap (>= 1); tests use
/// it to make the cap matter on small cases.
Envelope sweptEnvelope(const Body& body, const Motion3& motion, const SweepOptions& options, std::size_t doubt_cap);

}  // namespace steady::sweep::detail
