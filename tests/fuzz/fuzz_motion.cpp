// Fuzz target of motion files (see tests/fuzz/README.md): the input is the text of a motion
// file. It is parsed, the motion it describes is built and turned into SAM spans for a body in
// the box [-1, 1]^3, as `steady sweep` does, and the motion is evaluated.
//
// Checks, beyond "a result or a steady::Error": a motion built from keys whose entries are
// moderate (at most 1e3) has finite poses at its key times, inside its spans and at the span
// joints, and its spans cover the key times in order.
#include "fuzz_check.hpp"

#include <steady/core/motion.hpp>
#include <steady/io/motion_file.hpp>

#include <cmath>
#include <cstdint>
#include <string>

namespace {

bool moderate(const steady::Affine3& A) {
  return A.linear().cwiseAbs().maxCoeff() <= 1e3 && A.translation().cwiseAbs().maxCoeff() <= 1e3;
}

bool finite(const steady::Affine3& A) { return A.linear().allFinite() && A.translation().allFinite(); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  steady::io::MotionFile file;
  if (!steady::fuzz::typedOrOk("parseMotion", [&] { file = steady::io::parseMotion(text, "fuzz.json"); })) return 0;
  FUZZ_CHECK(file.keys.size() >= 2, "a parsed motion file has fewer than 2 keys");
  bool calm = true;
  for (const auto& k : file.keys) calm = calm && moderate(k.pose) && std::abs(k.t) <= 1e3;
  steady::Box<3> box;
  box.lo = Eigen::Vector3d::Constant(-1);
  box.hi = Eigen::Vector3d::Constant(1);
  steady::fuzz::typedOrOk("motion", [&] {
    const steady::KeyframeMotion3 keys = file.motion();
    for (const auto& k : file.keys) {
      const steady::Affine3 p = keys.pose(k.t);
      if (calm) FUZZ_CHECK(finite(p), "the exact pose at a key time is not finite");
    }
    const steady::Motion3 m = keys.toMotion(box, file.approximation);
    FUZZ_CHECK(m.spanCount() >= 1, "a motion without spans");
    FUZZ_CHECK(m.beginTime() == file.keys.front().t && m.endTime() == file.keys.back().t,
               "the spans do not start and end at the first and last key times");
    for (std::size_t i = 0; i < m.spanCount(); ++i) {
      FUZZ_CHECK(m.spanBegin(i) < m.spanEnd(i), "a span that does not move forward in time");
      if (i > 0) FUZZ_CHECK(m.spanBegin(i) == m.spanEnd(i - 1), "spans that do not join");
      if (!calm) continue;
      for (const double s : {0.0, 0.5, 1.0})
        FUZZ_CHECK(finite(m.span(i).pose(s)), "a span pose of a moderate motion is not finite");
      FUZZ_CHECK(finite(m.pose(0.5 * (m.spanBegin(i) + m.spanEnd(i)))), "a motion pose is not finite");
    }
  });
  return 0;
}
