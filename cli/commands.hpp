#pragma once
// The commands of the steady tool. Each returns the complete text for standard output, so
// that nothing is printed unless the whole command succeeded. Errors are thrown:
// steady_cli::UsageError for bad arguments, steady::Error for math failures and unreadable
// input files (codes InvalidFile, Io), steady_cli::OutputError when an output file cannot be
// written.

#include <steady/core/ear.hpp>
#include <steady/sweep/envelope.hpp>

#include <optional>
#include <stdexcept>
#include <string>

namespace steady_cli {

/// An output file could not be written (exit status 1, reason "io"); nothing was written.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A run stopped by a signal (SIGINT or SIGTERM) before it wrote anything. The command-line
/// tool exits with status 128 + signal(), as a shell reports a process that the signal ended.
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, const std::string& what) : std::runtime_error(what), signal_(signal) {}
  int signal() const noexcept { return signal_; }

 private:
  int signal_;
};

/// `steady pow`: {"case", "result" (A^t as rows of [L | t]), "log" {"M", "u"}}.
std::string powCommand(const std::string& affinity, double t, int dim, const steady::EarOptions& options);

/// `steady sam`: {"case" (of C B^-1), "pose" (with t) or "poses" (with steps: steps + 1 poses,
/// the regular pattern from B to C), "log" (of C B^-1)}. Exactly one of t and steps is set.
std::string samCommand(const std::string& from, const std::string& to, std::optional<double> t,
                       std::optional<int> steps, int dim, const steady::EarOptions& options);

/// Output of `steady demo`.
struct DemoOutput {
  std::string json;     ///< what `steady sam --from START --to END --copies STEPS` prints
  std::string summary;  ///< one line for people (no newline)
};

/// `steady demo`: the regular pattern between the bundled poses. `data_dir` is the --data
/// value ("" to search the default places).
DemoOutput demoCommand(const std::string& data_dir, int steps);

/// `steady motion sample`: {"interpolation", "poses": [{"t", "pose"}, ...]}, the exact curve of
/// the motion file at `count` (>= 2) equally spaced times from its first to its last key time.
/// `motion` is a path, "-" for standard input (also "@path", "@-"), or inline JSON ('{...}').
std::string motionSampleCommand(const std::string& motion, int count);

/// `steady pattern`: the body mesh placed at `copies` (>= 1) poses of the motion, at equally
/// spaced times from the first to the last key time (both included; 1 copy: the first pose),
/// merged without welding and written atomically to `output` (format from its extension).
/// Returns the one-line summary for standard error.
std::string patternCommand(const std::string& motion, int copies, const std::string& mesh,
                           const std::string& output, bool binary);

/// Arguments of `steady collide`.
struct CollideRequest {
  std::string moving;          ///< mesh file of the moving body (vertices in body coordinates)
  std::string motion;          ///< its motion (a --motion argument: path, "-", "@path", inline JSON)
  std::string against;         ///< mesh file of the second body
  std::string against_motion;  ///< its motion; empty: the second body is static (world coordinates)
  bool all = false;            ///< every contact event instead of the first
};

/// Output of `steady collide`.
struct CollideOutput {
  std::string json;     ///< the answer for standard output
  std::string summary;  ///< one line for people (no newline)
};

/// `steady collide`: the first contact (or, with `all`, every contact event in time order) of
/// the moving mesh along its motion with the second mesh, static or moving along its own
/// motion; without contact, the clearance (minimum distance over the motion) instead:
///   {"contact": true, "t", "t_latest", "span", "span_time", "features": {"type", "moving", "static"},
///    "point", "normal", "crossing", "certain"}
///   {"contact": false, "clearance", "clearance_bounds", "clearance_t", "closest": {"moving", "static"}}
///   {"contact", "contacts": [...]} (with all; plus the clearance members when there is none)
/// "moving" always names the first mesh and "static" the second, also when it moves.
/// @throws UsageError for unreadable or unusable input (a zero-area triangle, motions that share
///   no time), steady::Error for math errors of the motions.
CollideOutput collideCommand(const CollideRequest& request);

/// Arguments of `steady sweep`.
struct SweepRequest {
  std::string body;       ///< mesh file of the body (body coordinates)
  std::string motion;     ///< its motion (a --motion argument: path, "-", "@path", inline JSON)
  std::string output;     ///< the envelope's mesh file; the extension selects the format
  std::string tolerance;  ///< --tolerance as typed: relative to the body's box diagonal; "" = 1e-3
  std::string report;     ///< --report: a JSON file, "-" for standard output, "" for none
  bool repair = false;      ///< repair the body first (steady::sweep::repairMesh)
  bool fill_holes = false;  ///< ... and fill its holes (implies repair)
  bool binary = false;      ///< binary output (.ply, .stl)
  bool check = true;        ///< check the envelope for self-intersections (SweepOptions::check)
  bool progress = false;    ///< draw a progress bar on standard error (when it is a terminal)
  int threads = 0;          ///< worker threads (SweepOptions::threads; 0: every hardware thread)
  int refinements = steady::sweep::SweepOptions{}.refinements;  ///< re-sweeps allowed (SweepOptions::refinements)
};

/// Output of `steady sweep`.
struct SweepOutput {
  std::string json;     ///< the report, for standard output when `report` is "-"; else empty
  std::string summary;  ///< one line for people (no newline)
  /// The envelope failed its own check (open, not manifold or oriented, self-intersecting,
  /// zero-area faces, or an open sweep cycle): the file is written for inspection, and the
  /// command exits with status 4.
  bool defective = false;
};

/// `steady sweep`: the envelope of the body swept along the motion (sweptEnvelope), written
/// atomically to `output`, with the report written atomically to `report` (or returned for
/// standard output). On any failure neither file is written. The output paths are checked
/// before the sweep starts.
/// The first SIGINT or SIGTERM during the sweep or before its files are written stops it
/// (SweepOptions::cancel) and restores the signal's default action, so that a second one ends
/// the process at once; nothing is written then, not even a temporary file. A signal that
/// comes once the files are being written lets them finish.
/// @throws UsageError for bad arguments and for a body that is not a valid closed outward mesh
///   (the tag is the error code of the body validation, e.g. "degenerate-input"); OutputError
///   when a file cannot be written; Interrupted after a signal; steady::Error for unreadable
///   files and math errors.
SweepOutput sweepCommand(const SweepRequest& request);

}  // namespace steady_cli
