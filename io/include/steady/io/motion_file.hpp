#pragma once
/// @file
/// Motion files: key poses at key times and how to join them, as JSON (the format is
/// documented in io/README.md).
///
/// Minimal example:
///
///     {"keyframes": [{"t": 0, "pose": [[1,0,0,0],[0,1,0,0],[0,0,1,0]]},
///                    {"t": 1, "pose": {"translation": [0, 0, 2], "axis": [0, 0, 1], "angle_deg": 180}}],
///      "interpolation": "polysam"}
///
/// The parser is strict: every fault (a wrong shape, a value that is not a finite number, a
/// pose that mirrors or flattens the body, times that do not increase, an unknown or repeated
/// member name, ...) is an Error(InvalidFile) whose message starts with the source name and
/// the JSON path of the fault, e.g.
/// `m.json: keyframes[2].pose: row 1 has 3 entries, expected 4`.

#include <steady/core/motion.hpp>

#include <string>
#include <vector>

namespace steady::io {

/// The content of a motion file.
struct MotionFile {
  /// The key poses (at least 2), with strictly increasing finite times; every pose is finite
  /// and has `det L > 0` and is not numerically singular (checked by the parser).
  std::vector<steady::Keyframe<3>> keys;
  /// How the keys are joined ("interpolation"; default "polysam").
  steady::Interpolation interpolation = steady::Interpolation::PolySam;
  /// Rounds of four-point subdivision for Interpolation::Subdivide ("rounds", 0..8, default 3;
  /// unused by the other kinds).
  int rounds = 3;
  /// Motion options; the file sets `no_sam` ("no_sam": "fail" or "split"), the rest keeps its
  /// defaults.
  steady::MotionOptions options;
  /// How a curved motion (Bézier, bi-arc) becomes SAM spans: the file sets `tolerance`
  /// ("tolerance", relative to the body box diagonal) or `spans` ("spans", a fixed count).
  steady::ApproximationOptions approximation;

  /// The motion described: `KeyframeMotion3(keys, interpolation, rounds, options)`.
  /// @throws the errors of the KeyframeMotion constructor, e.g. Error(NoRealLog) when two
  ///   consecutive keys of a polySAM have no SAM between them and `no_sam` is "fail". (File
  ///   format faults have been reported by the parser already.)
  steady::KeyframeMotion<3> motion() const;
};

/// Parses the JSON text of a motion file. `source_name` starts every error message (a file
/// name, "<stdin>", ...).
/// @throws Error(InvalidFile) for malformed JSON and for every fault of the format, with the
///   JSON path of the fault (see io/README.md).
MotionFile parseMotion(const std::string& text, const std::string& source_name);

/// Reads and parses a motion file; error messages start with `path`.
/// @throws Error(Io) when the file cannot be opened or read; Error(InvalidFile) as
///   parseMotion().
MotionFile readMotionFile(const std::string& path);

}  // namespace steady::io
