// Candidate surfaces: the guaranteed distance of true swept points to their strip (screws,
// translations, general affine spans with shear), exact caps, step counts against the
// tolerance, watertight tubes, polySAMs and bad options.
#include <steady/sweep/candidates.hpp>

#include "support/meshes.hpp"
#include "support/random_affine.hpp"
#include "sweep/sweep_test.hpp"

#include <steady/core/motion.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <map>

namespace {

using steady::Affine3;
using steady::ErrorCode;
using steady::Span3;
using steady::sweep::Body;
using steady::sweep::CandidateKind;
using steady::sweep::CandidateOptions;
using steady::sweep::CandidateSurface;
using steady::sweep::spanCandidates;
using namespace steady_sweep_test;

Body makeBody(const Mesh& m) { return Body(m.v, m.f); }

// Largest distance, over random points of every grazing segment at random span times, from the
// true position A^τ B x to the triangles of that segment's strip, divided by ε.
double worstStripRatio(const CandidateSurface& cs, const Span3& span, std::mt19937_64& rng, int samples) {
  double worst = 0.0;
  const auto& gs = cs.grazing.at(0);
  for (const auto& strip : cs.strips) {
    if (strip.triangle_count == 0) continue;  // (a segment sliding along its own line sweeps no area)
    const auto& seg = gs.segments[strip.segment];
    const V p = gs.points[seg.points[0]].body, q = gs.points[seg.points[1]].body;
    for (int n = 0; n < samples; ++n) {
      const double s = uniform(rng, 0, 1), tau = n == 0 ? 0.5 : uniform(rng, 0, 1);
      const V x = span.pose(tau)((1 - s) * p + s * q);
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t t = strip.first_triangle; t < strip.first_triangle + strip.triangle_count; ++t) {
        const auto& tri = cs.triangles[t];
        best = std::min(best, pointTriangleDistance(x, cs.vertices[tri[0]], cs.vertices[tri[1]], cs.vertices[tri[2]]));
      }
      worst = std::max(worst, best / cs.tolerance);
    }
  }
  return worst;
}

std::size_t totalSteps(const CandidateSurface& cs) {
  std::size_t n = 0;
  for (const auto& g : cs.grids) n += g.tau.size() - 1;
  return n;
}

// A rigid pose: rotation about a random axis, then a translation.
Affine3 randomRigid(std::mt19937_64& rng) {
  return Affine3::translation(V(uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2))) *
         Affine3::rotation(randomUnit(rng), uniform(rng, -3, 3));
}

enum class SpanKind { Screw, Translation, Affine, Shear };

Span3 randomSpan(SpanKind kind, std::mt19937_64& rng) {
  const Affine3 B = kind == SpanKind::Affine ? steady::testing::randomWellPosedAffine<3>(rng) : randomRigid(rng);
  Affine3 A;
  switch (kind) {
    case SpanKind::Screw: {
      const V axis = randomUnit(rng), through(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      A = Affine3::translation(through + uniform(rng, -2, 2) * axis) * Affine3::rotation(axis, uniform(rng, 1.0, 2.5)) *
          Affine3::translation(-through);
      break;
    }
    case SpanKind::Translation:
      A = Affine3::translation(3.0 * randomUnit(rng));
      break;
    case SpanKind::Affine:
      A = steady::testing::randomWellPosedAffine<3>(rng);
      break;
    case SpanKind::Shear: {
      const V s = randomUnit(rng), d = s.unitOrthogonal();
      A = Affine3::translation(randomUnit(rng)) * Affine3::shear(s, d, uniform(rng, 1.0, 2.0)) *
          Affine3::rotation(randomUnit(rng), 0.5);
      break;
    }
  }
  return Span3::between(B, A * B);
}

TEST(Candidates, TrueStripPointsWithinTolerance) {
  std::mt19937_64 rng(99);
  const char* names[] = {"screw", "translation", "affine", "shear"};
  for (SpanKind kind : {SpanKind::Screw, SpanKind::Translation, SpanKind::Affine, SpanKind::Shear}) {
    double worst = 0.0;
    std::size_t triangles = 0, strips = 0;
    for (int trial = 0; trial < 4; ++trial) {
      const Mesh m = trial % 2 ? uvSphere(8, 12, 1.0, V(0.5, 0, -0.3)) : randomConvex(rng, 16);
      const Body body = makeBody(m);
      const Span3 span = randomSpan(kind, rng);
      CandidateOptions o;
      o.relative_tolerance = trial < 2 ? 1e-2 : 1e-3;
      const CandidateSurface cs = spanCandidates(body, span, o);
      ASSERT_FALSE(cs.strips.empty());
      worst = std::max(worst, worstStripRatio(cs, span, rng, 12));
      triangles += cs.triangles.size();
      strips += cs.strips.size();
      if (kind == SpanKind::Translation) {
        for (const auto& g : cs.grids) EXPECT_EQ(g.tau.size(), 2u);  // straight trajectories: one step
      }
    }
    std::printf("[ info     ] %-11s strips %zu, triangles %zu, worst distance / eps %.3f\n", names[static_cast<int>(kind)],
                strips, triangles, worst);
    EXPECT_LE(worst, 1.0) << names[static_cast<int>(kind)];
  }
}

// A pure shear with a translation moves every point along a straight line (M² v = 0), and the
// twist of a strip's cells is exactly h |M e| / 4 (M² e = 0): the tessellation must use that,
// not e^(hμ) times it (9.5x here). With the loose bound, the strips of an L-shaped prism along
// such a span had 1,487 pieces and its sweep took 12 s, most of it on the cap faces fanned to
// their finely cut edges (a sweep fuzz input, tests/fuzz/corpus/sweep/L_shear_fine_pieces).
TEST(Candidates, ShearStripsTakeTheirExactTwist) {
  const Body body = makeBody(box(V(0, 0, 0), V(2, 2, 0.5)));
  Affine3::Linear L = Affine3::Linear::Identity();
  L(2, 1) = 2.25;  // z += 2.25 y
  const Span3 span(Affine3(L, V(1, 0, 0)));
  CandidateOptions o;
  o.tolerance = 0.01;
  const CandidateSurface cs = spanCandidates(body, span, o);
  ASSERT_FALSE(cs.strips.empty());
  for (const auto& g : cs.grids) EXPECT_EQ(g.tau.size(), 2u);  // straight trajectories: one step
  const Eigen::Matrix3d M = span.log().M;
  const auto& gs = cs.grazing.at(0);
  for (const auto& strip : cs.strips) {
    const auto& seg = gs.segments[strip.segment];
    const V e = gs.points[seg.points[1]].body - gs.points[seg.points[0]].body;  // (the start pose is the identity)
    const int exact = std::max(1, static_cast<int>(std::ceil((M * e).norm() / 4 / (0.5 * o.tolerance.value()) * (1 + 1e-9))));
    EXPECT_LE(strip.pieces, exact) << "segment " << strip.segment;
  }
  std::mt19937_64 rng(3);
  EXPECT_LE(worstStripRatio(cs, span, rng, 64), 1.0);
}

TEST(Candidates, CapsAreTheBodyAtBothEnds) {
  std::mt19937_64 rng(5);
  const Mesh m = randomConvex(rng, 20);
  const Body body = makeBody(m);
  const Span3 span = randomSpan(SpanKind::Affine, rng);
  const CandidateSurface cs = spanCandidates(body, span);
  const std::size_t nf = m.f.size();
  const Affine3 P0 = span.pose(0.0), P1 = span.pose(1.0);
  std::size_t start = 0, end = 0;
  for (std::size_t t = 0; t < cs.triangles.size(); ++t) {
    const auto& tag = cs.tags[t];
    if (tag.kind == CandidateKind::Swept) continue;
    const Affine3& P = tag.kind == CandidateKind::StartCap ? P0 : P1;
    (tag.kind == CandidateKind::StartCap ? start : end)++;
    for (int k = 0; k < 3; ++k) {
      const V want = P(m.v[m.f[tag.face][k]]);
      EXPECT_LE((cs.vertices[cs.triangles[t][k]] - want).norm(), 1e-14 * (1 + want.norm()));
    }
  }
  EXPECT_EQ(start, nf);
  EXPECT_EQ(end, nf);
  // The start cap is exactly B p.
  for (std::size_t i = 0; i < m.v.size(); ++i) EXPECT_EQ(cs.vertices[i], span.start()(m.v[i]));
}

TEST(Candidates, StepsDoubleWhenToleranceQuarters) {
  std::mt19937_64 rng(17);
  const Body body = makeBody(uvSphere(8, 12, 1.0));
  for (SpanKind kind : {SpanKind::Screw, SpanKind::Affine}) {
    const Span3 span = randomSpan(kind, rng);
    CandidateOptions o;
    std::vector<std::size_t> steps, pieces;
    for (double eps : {1e-2, 2.5e-3, 6.25e-4, 1.5625e-4}) {
      o.tolerance = eps;
      const CandidateSurface cs = spanCandidates(body, span, o);
      steps.push_back(totalSteps(cs));
      std::size_t p = 0;
      for (const auto& s : cs.strips) p += static_cast<std::size_t>(s.pieces);
      pieces.push_back(p);
      std::printf("[ info     ] %s eps %.3g: %zu grids, %zu tau steps, %zu segment pieces, %zu triangles\n",
                  kind == SpanKind::Screw ? "screw " : "affine", eps, cs.grids.size(), steps.back(), p,
                  cs.triangles.size());
    }
    for (std::size_t i = 1; i < steps.size(); ++i) {
      const double r = static_cast<double>(steps[i]) / static_cast<double>(steps[i - 1]);
      EXPECT_GT(r, 1.6) << i;
      EXPECT_LT(r, 2.5) << i;
    }
    const double rp = static_cast<double>(pieces.back()) / static_cast<double>(pieces[pieces.size() - 2]);
    EXPECT_GT(rp, 1.5);
    EXPECT_LT(rp, 2.7);
  }
}

// In generic position each loop's strips form a tube: every interior edge is shared by exactly
// two triangles; only the rows at τ = 0 and τ = 1 are boundary.
TEST(Candidates, LoopStripsAreWatertightTubes) {
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 3; ++trial) {
    const Body body = makeBody(randomConvex(rng, 18));
    const Span3 span = randomSpan(trial == 0 ? SpanKind::Screw : SpanKind::Affine, rng);
    const CandidateSurface cs = spanCandidates(body, span);
    ASSERT_TRUE(cs.grazing[0].generic);
    ASSERT_EQ(cs.degenerate_dropped, 0u);
    for (std::size_t g = 0; g < cs.grids.size(); ++g) {
      std::map<std::pair<int, int>, int> uses;
      std::set<int> verts;
      for (std::size_t t = 0; t < cs.triangles.size(); ++t) {
        if (cs.tags[t].kind != CandidateKind::Swept || cs.tags[t].group != static_cast<int>(g)) continue;
        const auto& tri = cs.triangles[t];
        for (int k = 0; k < 3; ++k) {
          const int a = tri[k], b = tri[(k + 1) % 3];
          ++uses[{std::min(a, b), std::max(a, b)}];
          verts.insert(a);
        }
      }
      // Rows at τ = 0 and 1: the loop's points posed by the start and end poses.
      std::vector<V> row0, row1;
      for (int q : cs.grids[g].points) {
        row0.push_back(span.start()(cs.grazing[0].points[q].body));
        row1.push_back(span.pose(1.0)(cs.grazing[0].points[q].body));
      }
      auto onRow = [&](const V& x, const std::vector<V>& row, const V& other) {
        // On the polyline of the row (segments between any two row points lie on the caps'
        // surface; here it suffices that x is within rounding of the segment through its
        // neighbours): test against all point pairs of the row.
        (void)other;
        for (std::size_t i = 0; i < row.size(); ++i)
          for (std::size_t j = 0; j < row.size(); ++j) {
            const V d = row[j] - row[i];
            const double s = std::clamp((x - row[i]).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
            if ((row[i] + s * d - x).norm() <= 1e-12 * (1 + x.norm())) return true;
          }
        return false;
      };
      int boundary = 0;
      for (const auto& [e, n] : uses) {
        EXPECT_LE(n, 2);
        if (n == 2) continue;
        ++boundary;
        const V a = cs.vertices[e.first], b = cs.vertices[e.second];
        EXPECT_TRUE((onRow(a, row0, b) && onRow(b, row0, a)) || (onRow(a, row1, b) && onRow(b, row1, a)))
            << "open edge inside the tube of grid " << g;
      }
      EXPECT_GT(boundary, 0);
    }
  }
}

TEST(Candidates, StationarySpanGivesCapsOnly) {
  const Body body = makeBody(box(V(0, 0, 0), V(1, 1, 1)));
  const Affine3 B = Affine3::translation(V(1, 2, 3));
  const CandidateSurface cs = spanCandidates(body, Span3::between(B, B));
  EXPECT_TRUE(cs.grazing[0].stationary);
  EXPECT_EQ(cs.triangles.size(), 24u);
  EXPECT_TRUE(cs.strips.empty());
}

TEST(Candidates, DefaultToleranceIsRelativeToTheBody) {
  const Body body = makeBody(box(V(0, 0, 0), V(2, 3, 6)));  // diagonal 7
  const CandidateSurface cs = spanCandidates(body, Span3(Affine3::rotation(V(0, 0, 1), 1.0)));
  EXPECT_DOUBLE_EQ(cs.tolerance, 7e-3);
}

TEST(Candidates, PolySamConcatenatesSpans) {
  std::mt19937_64 rng(11);
  const Body body = makeBody(randomConvex(rng, 16));
  const std::vector<Affine3> keys = {randomRigid(rng), randomRigid(rng), randomRigid(rng)};
  const steady::Motion3 motion = steady::Motion3::polySam(keys);
  ASSERT_EQ(motion.spanCount(), 2u);
  const CandidateSurface all = steady::sweep::motionCandidates(body, motion);
  std::size_t expected = 0;
  std::map<int, std::size_t> per_span;
  CandidateOptions same;
  same.tolerance = all.tolerance;
  for (std::size_t i = 0; i < motion.spanCount(); ++i)
    expected += spanCandidates(body, motion.span(i), same).triangles.size();
  for (const auto& tag : all.tags) ++per_span[tag.span];
  EXPECT_EQ(all.triangles.size(), expected);
  EXPECT_EQ(per_span.size(), 2u);
  EXPECT_EQ(all.grazing.size(), 2u);
  // The end cap of span 0 is the start cap of span 1 (up to rounding).
  std::vector<V> end0, start1;
  for (std::size_t t = 0; t < all.triangles.size(); ++t) {
    if (all.tags[t].span == 0 && all.tags[t].kind == CandidateKind::EndCap) end0.push_back(all.vertices[all.triangles[t][0]]);
    if (all.tags[t].span == 1 && all.tags[t].kind == CandidateKind::StartCap) start1.push_back(all.vertices[all.triangles[t][0]]);
  }
  ASSERT_EQ(end0.size(), start1.size());
  for (std::size_t i = 0; i < end0.size(); ++i) EXPECT_LT((end0[i] - start1[i]).norm(), 1e-12);
  // Strips index into their own span's grazing set.
  for (const auto& s : all.strips) EXPECT_LT(static_cast<std::size_t>(s.segment), all.grazing[s.span].segments.size());
}

TEST(Candidates, BadOptions) {
  const Body body = makeBody(box(V(0, 0, 0), V(1, 1, 1)));
  const Span3 span(Affine3::rotation(V(0, 0, 1), 1.0));
  for (double eps : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    CandidateOptions o;
    o.tolerance = eps;
    EXPECT_TRUE(throwsError([&] { spanCandidates(body, span, o); }, ErrorCode::InvalidArgument,
                            "CandidateOptions::tolerance must be finite and > 0"));
    CandidateOptions r;
    r.relative_tolerance = eps;
    EXPECT_TRUE(throwsError([&] { spanCandidates(body, span, r); }, ErrorCode::InvalidArgument,
                            "CandidateOptions::relative_tolerance"));
  }
  CandidateOptions o;
  o.max_steps = 0;
  EXPECT_TRUE(throwsError([&] { spanCandidates(body, span, o); }, ErrorCode::InvalidArgument, "max_steps"));
  // A tolerance far below what the step limit allows.
  o.max_steps = 100;
  o.tolerance = 1e-12;
  EXPECT_TRUE(throwsError([&] { spanCandidates(body, span, o); }, ErrorCode::InvalidArgument,
                          "more than 100 .*raise the tolerance"));
  o = CandidateOptions{};
  o.grazing.tolerance = -1;
  EXPECT_TRUE(throwsError([&] { spanCandidates(body, span, o); }, ErrorCode::InvalidArgument, "GrazingOptions"));
}

}  // namespace
