// steady: the command-line tool. Real powers of affinities and steady affine morphs as JSON,
// contacts, swept volumes.

#include "affinity_io.hpp"
#include "commands.hpp"

#include <steady/core/ear.hpp>
#include <steady/core/error.hpp>

#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cstdio>
#include <exception>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#ifndef STEADY_VERSION
#define STEADY_VERSION "unknown"
#endif

namespace {

const char* const kAffinityHelp =
    "AFFINITY (for --affinity, --from, --to), one of:\n"
    "  12 numbers: the 3x4 matrix [L | t] row by row, \"r00 r01 r02 tx r10 r11 r12 ty r20 r21 r22 tz\",\n"
    "     separated by blanks, commas or semicolons (quote them as one argument);\n"
    "  16 numbers: a 4x4 homogeneous matrix with last row 0 0 0 1;\n"
    "  inline JSON starting with '[' or '{', as in a file;\n"
    "  @FILE: a JSON file holding a 3x4 array of rows [[r00, r01, r02, tx], ...], a 4x4\n"
    "     homogeneous array, a flat array of 12 numbers, or an object {\"pose\": <one of these>}\n"
    "     (other members are ignored). @- reads standard input.\n"
    "  With --dim 2: 6 numbers (the 2x3 matrix [L | t]) or 9, and 2x3 arrays.\n"
    "  A pose maps body coordinates to world coordinates: p -> L p + t.\n";

const char* const kMotionHelp =
    "MOTION (for --motion): a JSON motion file (format: io/README.md), \"-\" for standard input\n"
    "  (\"@FILE\" and \"@-\" work too), or the JSON itself starting with '{':\n"
    "    {\"keyframes\": [{\"t\": 0, \"pose\": [[r00, r01, r02, tx], [r10, r11, r12, ty], [r20, r21, r22, tz]]},\n"
    "                   {\"t\": 1, \"pose\": {\"translation\": [x, y, z], \"axis\": [ax, ay, az], \"angle_deg\": a,\n"
    "                                    \"scale\": s}}, ...],\n"
    "     \"interpolation\": \"polysam\" | \"bezier\" | \"biarc\" | \"subdivide\"}\n"
    "  Optional: \"rounds\" (subdivide, 0..8), \"no_sam\": \"fail\" | \"split\", \"tolerance\" or \"spans\"\n"
    "  (curved motions as SAM spans), \"description\". Unknown members are errors. A fault is reported\n"
    "  with its JSON path, e.g. \"m.json: keyframes[2].pose: row 1 has 3 entries, expected 4\".\n";

const char* const kOutputHelp =
    "OUTPUT: JSON on standard output; numbers in the shortest form that reads back to the same\n"
    "  double (at most 17 significant digits). Matrices are arrays of rows of [L | t].\n"
    "EXIT STATUS: 0 success; 2 usage error or unreadable argument (including a missing or malformed\n"
    "  motion or mesh file, for collide a mesh with a zero-area triangle or two motions that share\n"
    "  no time, and for sweep a body that is not a closed outward manifold mesh); 3 math error (no\n"
    "  real logarithm, reflection, singular pose, overflow);\n"
    "  4 sweep only: the envelope was written but failed its own check (open, not manifold,\n"
    "  self-intersecting): do not use it as a solid;\n"
    "  130, 143 sweep only: interrupted by SIGINT (Ctrl-C) or SIGTERM before its files were written:\n"
    "  nothing was written (a second signal ends the process at once);\n"
    "  1 anything else (e.g. an output file that cannot be written). Errors are reported on standard\n"
    "  error as \"steady: error [<reason>]: <message>\" and nothing is printed on standard output.\n";

int report(const std::string& tag, const std::string& message, int status) {
  std::fprintf(stderr, "steady: error [%s]: %s\n", tag.c_str(), message.c_str());
  return status;
}

steady::EarOptions earOptions(const std::string& half_turn) {
  steady::EarOptions o;
  o.half_turn = half_turn == "cw" ? steady::HalfTurn::Clockwise : steady::HalfTurn::CounterClockwise;
  return o;
}

// An option's check: a whole number from 0 to `most` (`note` explains 0, or is empty).
CLI::Validator wholeNumber(long most, const std::string& note) {
  return CLI::Validator(
      [most, note](const std::string& text) -> std::string {
        std::size_t used = 0;
        long n = -1;
        try {
          n = std::stol(text, &used);
        } catch (const std::exception&) {
        }
        if (used != text.size() || n < 0 || n > most)
          return "'" + text + "' is not a whole number from 0 to " + std::to_string(most) + note;
        return std::string();
      },
      "N >= 0");
}

// Writes the whole answer at once; a failing stdout (full disk, closed pipe) is an error.
int emit(const std::string& text) {
  const bool ok = std::fwrite(text.data(), 1, text.size(), stdout) == text.size() && std::fflush(stdout) == 0;
  return ok ? 0 : report("io", "cannot write to standard output", 1);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"steady " STEADY_VERSION
               ": real logarithms and powers of affinities (EAR) and steady affine morphs (SAMs).",
               "steady"};
  app.set_version_flag("--version", "steady " STEADY_VERSION, "Print the version and exit");
  app.require_subcommand(0, 1);
  app.footer(std::string("Run 'steady <command> --help' for the options of a command.\n\n") + kAffinityHelp + "\n" +
             kMotionHelp + "\n" + kOutputHelp);

  // Every command gets its own variables; only the parsed one is used.
  std::string pow_affinity, pow_t, pow_half = "ccw";
  int pow_dim = 3;
  CLI::App* pow = app.add_subcommand(
      "pow", "A^t = exp(t log A), a real power of an affinity, with its logarithm and case");
  pow->add_option("-a,--affinity", pow_affinity, "The affinity A (see AFFINITY)")
      ->type_name("AFFINITY")
      ->required();
  pow->add_option("-t,--t", pow_t, "The exponent t, any real number (0.5: the square root)")
      ->type_name("T")
      ->required();
  pow->add_option("--dim", pow_dim, "Dimension of the affinity: 3 (3x4) or 2 (2x3)")
      ->check(CLI::IsMember({2, 3}))
      ->capture_default_str();
  pow->add_option("--half-turn", pow_half, "Logarithm chosen for a half turn: ccw (+pi J) or cw (-pi J)")
      ->check(CLI::IsMember({"ccw", "cw"}))
      ->capture_default_str();
  pow->footer(std::string("Prints {\"case\", \"result\": A^t as 3 rows of [L | t], \"log\": {\"M\", \"u\"}}.\n\n") +
              kAffinityHelp + "\n" + kOutputHelp);

  std::string sam_from, sam_to, sam_t, sam_half = "ccw";
  int sam_steps = 0, sam_dim = 3;
  CLI::App* sam = app.add_subcommand(
      "sam", "Steady affine morph S(t) = (C B^-1)^t B: one pose, or a regular pattern");
  sam->add_option("-f,--from", sam_from, "The start pose B, at t = 0 (see AFFINITY)")
      ->type_name("AFFINITY")
      ->required();
  sam->add_option("--to", sam_to, "The end pose C, at t = 1 (see AFFINITY)")
      ->type_name("AFFINITY")
      ->required();
  CLI::Option* sam_t_opt =
      sam->add_option("-t,--t", sam_t, "One pose, at time t (0: B, 1: C; any real number)")->type_name("T");
  CLI::Option* sam_n_opt =
      sam->add_option("-n,--copies,--steps", sam_steps,
                      "The regular pattern of N steps: N+1 poses S(i/N), i = 0..N, from B to C included")
          ->type_name("N")
          ->check(CLI::Range(1, 1000000));
  sam_t_opt->excludes(sam_n_opt);
  sam->add_option("--dim", sam_dim, "Dimension of the poses: 3 (3x4) or 2 (2x3)")
      ->check(CLI::IsMember({2, 3}))
      ->capture_default_str();
  sam->add_option("--half-turn", sam_half, "Logarithm chosen when C B^-1 is a half turn: ccw or cw")
      ->check(CLI::IsMember({"ccw", "cw"}))
      ->capture_default_str();
  sam->footer(std::string("Prints {\"case\": of C B^-1, \"pose\": S(t) (with --t) or \"poses\": the N+1 poses\n"
                          "(with --copies N, N steps), \"log\": {\"M\", \"u\"} of C B^-1}.\n"
                          "Example: steady sam --from @data/poses/start.json --to @data/poses/end.json --copies 8\n\n") +
              kAffinityHelp + "\n" + kOutputHelp);

  std::string demo_data;
  int demo_steps = 8;
  CLI::App* demo = app.add_subcommand(
      "demo", "The regular pattern of 8 steps between the bundled demo poses, with a summary");
  demo->add_option("--data", demo_data,
                   "Folder holding poses/start.json and poses/end.json (default: ./data, the installed "
                   "share/steady, then the source tree's data/)")
      ->type_name("DIR");
  demo->add_option("-n,--copies,--steps", demo_steps, "Number of steps N (N+1 poses)")
      ->type_name("N")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  demo->footer(std::string("The bundled end pose scales the body by (1.5, 1, 0.8) along its axes, turns it by 120\n"
                           "degrees about the tilted axis (1, 2, 2)/3 and moves it by (4, 1, 2); the start pose is\n"
                           "the identity. Prints the same JSON as\n"
                           "  steady sam --from @data/poses/start.json --to @data/poses/end.json --copies 8\n"
                           "and a one-line summary on standard error: the case of the motion, its axis and turn,\n"
                           "its fixed point.\n\n") +
               kOutputHelp);

  CLI::App* motion = app.add_subcommand("motion", "Motions from key poses (a motion file): 'steady motion sample'");
  motion->require_subcommand(1);
  std::string sample_motion;
  int sample_count = 0;
  CLI::App* sample = motion->add_subcommand(
      "sample", "The exact motion curve at N equally spaced times from the first to the last key time");
  sample->add_option("-m,--motion", sample_motion, "The motion file (see MOTION)")->type_name("MOTION")->required();
  sample->add_option("-n,--count", sample_count, "Number of poses N (at least 2: the first and last key times included)")
      ->type_name("N")
      ->required()
      ->check(CLI::Range(2, 1000000));
  sample->footer(std::string("Prints {\"interpolation\", \"poses\": [{\"t\", \"pose\": 3 rows of [L | t]}, ...]}: the\n"
                             "poses of the exact curve (KeyframeMotion::pose) at t_i = t_first + i (t_last - t_first) / (N - 1).\n"
                             "Example: steady motion sample --motion data/motions/keys.json --count 9\n\n") +
                 kMotionHelp + "\n" + kOutputHelp);
  motion->footer(std::string("Run 'steady motion sample --help' for its options.\n\n") + kMotionHelp);

  std::string pattern_motion, pattern_mesh, pattern_output;
  int pattern_copies = 0;
  bool pattern_binary = false;
  CLI::App* pattern = app.add_subcommand(
      "pattern", "A mesh placed at N poses of a motion, merged into one mesh file");
  pattern->add_option("-m,--motion", pattern_motion, "The motion file (see MOTION)")->type_name("MOTION")->required();
  pattern->add_option("-n,--copies", pattern_copies,
                      "Number of copies N: poses at N equally spaced times from the first to the last key time, "
                      "both included (N = 1: the first pose)")
      ->type_name("N")
      ->required()
      ->check(CLI::Range(1, 1000000));
  pattern->add_option("--mesh", pattern_mesh, "The body: a triangle mesh file (.off, .ply, .obj, .stl)")
      ->type_name("FILE")
      ->required();
  pattern->add_option("-o,--output", pattern_output, "The output mesh file; its extension (.off, .ply, .obj, .stl) selects the format")
      ->type_name("FILE")
      ->required();
  pattern->add_flag("--binary", pattern_binary, "Binary output (.ply, .stl)");
  pattern->footer(std::string("The copies are not welded: the output holds N x the body's vertices and triangles, copy i\n"
                              "at the pose of time t_i = t_first + i (t_last - t_first) / (N - 1). For a polySAM with two keys\n"
                              "B and C this is the regular pattern (C B^-1)^(i/(N-1)) B. The file is written atomically (a\n"
                              "temporary file in the same directory, then renamed): on failure nothing is left behind.\n"
                              "Prints nothing on standard output and a one-line summary on standard error.\n"
                              "Example: steady pattern --motion data/motions/screw.json --copies 8 \\\n"
                              "           --mesh data/meshes/tetrahedron.off -o pattern.ply\n\n") +
                  kMotionHelp + "\n" + kOutputHelp);

  steady_cli::CollideRequest collide_request;
  CLI::App* collide = app.add_subcommand(
      "collide", "When a mesh moving along a motion first touches another mesh, static or moving; or how close they come");
  collide->add_option("MOVING", collide_request.moving,
                      "The moving body: a triangle mesh file (.off, .ply, .obj, .stl), vertices in body coordinates")
      ->type_name("FILE")
      ->required();
  collide->add_option("-m,--motion", collide_request.motion, "The motion of MOVING (see MOTION)")
      ->type_name("MOTION")
      ->required();
  collide->add_option("--against", collide_request.against,
                      "The other body: a triangle mesh file; static (world coordinates) unless --against-motion")
      ->type_name("FILE")
      ->required();
  collide->add_option("--against-motion", collide_request.against_motion,
                      "The motion of the --against body (see MOTION); then its vertices are body coordinates")
      ->type_name("MOTION");
  collide->add_flag("--all", collide_request.all, "Every contact event in time order, not only the first");
  collide->footer(std::string(
      "Both meshes are surfaces: contact means the surfaces touch (a body inside the other does not).\n"
      "The first contact is the earliest time over the motion (with --against-motion: over the times\n"
      "both motions share) at which they touch. Prints\n"
      "  {\"contact\": true, \"t\": T, \"t_latest\": T2, \"span\": S, \"span_time\": s,\n"
      "   \"features\": {\"type\": \"vertex-face\", \"moving\": 3, \"static\": 10},\n"
      "   \"point\": [x, y, z], \"normal\": [x, y, z], \"crossing\": -1, \"certain\": true}\n"
      "  t: the contact time on the motion's time scale, never later than the true time by more than\n"
      "     1e-12 of a span. t_latest: the true time lies in [t, t_latest], 1e-12 of a span wide for a\n"
      "     clean crossing, wider where rounding blurs the contact (nearly parallel features, touches).\n"
      "  span: index of the SAM span of MOVING's motion (polysam: the key interval,\n"
      "     unless \"no_sam\": \"split\" added spans; bezier, biarc: the spans approximating the curve\n"
      "     within its tolerance, on which the contact is computed); span_time: the time within it, 0..1.\n"
      "  features: what touches. \"moving\" is always the feature of MOVING and \"static\" that of the\n"
      "     --against mesh, also when --against-motion moves it. vertex-face: \"moving\" is a vertex\n"
      "     index, \"static\" a triangle index; face-vertex: a triangle of MOVING and a vertex of the other;\n"
      "     edge-edge: both are edges [i, j] (vertex indices, smaller first). Indices count from 0 in the\n"
      "     files' order; polygons count as the triangles of their fan around the first corner.\n"
      "  point: where they touch at t (world); normal: unit world normal there (the face's for\n"
      "     vertex-face and face-vertex, the edges' common normal, up to sign, for edge-edge).\n"
      "  crossing: +1 or -1 when the features cross (the signed distance of the vertex to the face, or of\n"
      "     the two edges, changes sign), 0 for a touch without crossing. certain: false only when a root\n"
      "     solve reached its work limit.\n"
      "Without contact it prints\n"
      "  {\"contact\": false, \"clearance\": d, \"clearance_bounds\": [lo, d], \"clearance_t\": t,\n"
      "   \"closest\": {\"moving\": [x, y, z], \"static\": [x, y, z]}}\n"
      "  The true minimum distance over the motion (over the shared times with --against-motion) lies\n"
      "  within clearance_bounds; \"clearance\", its upper end, is attained: the exact distance at time\n"
      "  clearance_t, between the points \"closest\" (world). The bracket is narrowed to 1% of the\n"
      "  clearance unless 20000 distance evaluations do not suffice (e.g. a distance that stays nearly\n"
      "  constant over a long motion); then it is wider, and still holds the minimum.\n"
      "With --all: {\"contact\": true or false, \"contacts\": [...]}, every contact event (a crossing, a touch,\n"
      "  the start of a sliding contact) as above without \"contact\", in time order; with no contact the\n"
      "  clearance members are added.\n"
      "A one-line summary goes to standard error. Meshes are read in single precision (see io/README.md).\n"
      "Example: the bundled tetrahedron dropped by 6 onto the bundled box; its lowest edge (z = 2 - 6 t)\n"
      "  meets the box top (z = 0.25) at t = 7/24 = 0.2916...:\n"
      "  steady collide data/meshes/tetrahedron.off --against data/meshes/box.off \\\n"
      "      --motion '{\"keyframes\": [{\"pose\": {\"translation\": [0, 0, 3]}}, {\"pose\": {\"translation\": [0, 0, -3]}}]}'\n\n") +
                  kMotionHelp + "\n" + kOutputHelp);

  steady_cli::SweepRequest sweep_request;
  CLI::App* sweep = app.add_subcommand(
      "sweep", "The swept volume of a closed mesh moving along a motion: its boundary (the envelope) as a mesh file");
  sweep->add_option("BODY", sweep_request.body,
                    "The body: a closed, outward oriented triangle mesh file (.off, .ply, .obj, .stl), vertices in "
                    "body coordinates")
      ->type_name("FILE")
      ->required();
  sweep->add_option("-m,--motion", sweep_request.motion, "The motion of BODY (see MOTION)")
      ->type_name("MOTION")
      ->required();
  sweep->add_option("-o,--output", sweep_request.output,
                    "The envelope's mesh file; its extension (.off, .ply, .obj, .stl) selects the format")
      ->type_name("FILE")
      ->required();
  sweep->add_option("--tolerance", sweep_request.tolerance,
                    "Relative tolerance T in (0, 1), default 1e-3: the envelope is within T x the diagonal of "
                    "BODY's bounding box (body coordinates) of the exact swept volume's boundary")
      ->type_name("T");
  sweep->add_option("--report", sweep_request.report,
                    "Also write a JSON report (sizes, volume, area, tolerance, counts, check, timings) to FILE, "
                    "atomically; '-' prints it on standard output")
      ->type_name("FILE");
  sweep->add_flag("--repair", sweep_request.repair,
                  "Repair BODY first: merge duplicate vertices, remove faces with a repeated vertex, duplicate "
                  "faces and unused vertices, orient the faces consistently and outward; holes are not filled");
  sweep->add_flag("--fill-holes", sweep_request.fill_holes, "With --repair (implied): also fill the holes of an open BODY");
  sweep->add_flag("--binary", sweep_request.binary, "Binary output (.ply, .stl)");
  sweep->add_option("--threads", sweep_request.threads,
                    "Threads for the exact re-triangulation and the inside tests; 0 (default): every hardware "
                    "thread. The envelope does not depend on it")
      ->type_name("N")
      ->check(wholeNumber(4096, " (0: every hardware thread)"));
  sweep->add_option("--refinements", sweep_request.refinements,
                    "Sweeps run again, each with a tessellation twice as fine, when the envelope leaves doubt "
                    "(its check fails, or some vertex or face centroid on kept walls or inner shells is not "
                    "certified within the tolerance); the best envelope is written. Along many spans only those "
                    "near the doubtful points may be refined (the report's spans_refined). 0: never; default 2")
      ->type_name("N")
      ->check(wholeNumber(8, ""));
  bool sweep_no_check = false;
  sweep->add_flag("--no-check", sweep_no_check,
                  "Skip the exact self-intersection check of the envelope (about a tenth of the time)");
  sweep->footer(std::string(
      "Computes the boundary of the volume swept by BODY along every span of its motion: the exact\n"
      "trimming of the sweep cycle (caps and swept strips), one closed, outward, 2-manifold triangle mesh in\n"
      "world coordinates (steady::sweep::sweptEnvelope; method in sweep/README.md).\n"
      "Tolerance: the only approximation is the tessellation of the swept strips; every point of the true\n"
      "strips is within epsilon = T x (BODY's bounding-box diagonal, body coordinates) of the output, by a\n"
      "derived bound (not sampled). A motion that scales the body scales the world distances with it: T is\n"
      "relative to the body as given. Smaller T means more triangles (quartering T about doubles them).\n"
      "BODY must be a closed, consistently and outward oriented, 2-manifold mesh without zero-area faces;\n"
      "several shells are allowed (an inward one is a cavity). A mesh that is not is rejected with the\n"
      "first defect (exit status 2); --repair fixes what it safely can and says what it changed in the\n"
      "summary (and the report); it never moves a vertex. Curved motions (bezier, biarc) are first\n"
      "approximated by SAM spans within the motion file's tolerance (see MOTION).\n"
      "Output: the envelope is written atomically (a temporary file in the same directory, then renamed),\n"
      "and so is the report; the output directories are checked before the sweep starts, and on any\n"
      "failure neither file is written. Nothing is printed on standard output (except the report with\n"
      "--report -). A one-line summary goes to standard error: sizes, volume, area, tolerance and the\n"
      "check of the output (closed, manifold, oriented, self-intersections), and a warning when some vertex\n"
      "of the walls kept at mouths that could not be closed, or of an inner shell, is not certified within\n"
      "the tolerance of the true boundary (the report's kept_wall_* and cavity_* fields), or a mouth\n"
      "filling was taken with a probe that is not (deep_fillings_taken); a progress bar is drawn there\n"
      "when it is a terminal and the sweep takes more than a second.\n"
      "Report: {\"volume\", \"area\", \"vertices\", \"faces\", \"tolerance\": {\"absolute\", \"relative\",\n"
      "  \"tessellation\", \"body_diagonal\"}, \"resweeps\", \"spans_refined\", \"spans\", \"spans_repeated\",\n"
      "  \"cycle_triangles\",\n"
      "  \"intersecting_pairs\", \"arrangement_triangles\",\n"
      "  \"patches\", \"ray_retries\", \"patches_by_ray\", \"label_mismatches\", \"thin_cavities_removed\",\n"
      "  \"thin_solids_removed\", \"buried_patches_removed\", \"crack_faces_removed\", \"buried_patches_kept\",\n"
      "  \"crack_faces_kept\", \"kept_wall_vertices\", \"kept_wall_depth_bound\" (null: beyond 8 x tolerance),\n"
      "  \"kept_wall_uncertified\" (vertex indices), \"kept_wall_faces_uncertified\" (face indices),\n"
      "  \"cavity_vertices\", \"cavity_depth_bound\", \"cavity_uncertified\", \"cavity_faces_uncertified\",\n"
      "  \"uncertified_vertices_moved\",\n"
      "  \"pocket_mouths_filled\", \"deep_fillings_taken\", \"fillings_refined\", \"filling_depth_bound\"\n"
      "  (null: beyond 8 x tolerance), \"mouth_flaps_removed\",\n"
      "  \"mouth_rim_faces_removed\", \"buried_dents_filled\", \"rounding_merged\", \"rounding_slivers_flipped\",\n"
      "  \"pinched_vertices_split\",\n"
      "  \"pinches_touching\", \"check\": {\"closed\", \"manifold\", \"oriented\", \"self_intersections\" (null\n"
      "  with --no-check), \"degenerate_faces\", \"shells\", \"volume\", \"area\"}, \"timings_s\": {\"read\", \"repair\",\n"
      "  \"body\","
      " \"motion\", \"cycle\", \"intersect\", \"label\", \"output\", \"check\", \"sweep\", \"total\"}, \"body\",\n"
      "  \"repair\" (null without --repair), \"motion\", \"output\"}.\n"
      "Example: steady sweep data/meshes/bracket.off --motion data/motions/screw_scale.json \\\n"
      "           -o out/envelope.ply --report out/report.json\n\n") +
                kMotionHelp + "\n" + kOutputHelp);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    const std::vector<std::string> extra = app.remaining();
    if (app.get_subcommands().empty() && dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr && !extra.empty() &&
        extra.front().rfind('-', 0) != 0)
      return report("usage", "unknown command '" + extra.front() +
                                 "' (the commands are pow, sam, demo, motion, pattern, collide and sweep; run 'steady --help')",
                    2);
    return report("usage", std::string(e.what()) + " (run 'steady --help' or 'steady <command> --help')", 2);
  }

  try {
    if (pow->parsed()) {
      const double t = steady_cli::readNumber(pow_t, "--t");
      return emit(steady_cli::powCommand(pow_affinity, t, pow_dim, earOptions(pow_half)));
    }
    if (sam->parsed()) {
      std::optional<double> t;
      std::optional<int> steps;
      if (sam_t_opt->count() > 0) t = steady_cli::readNumber(sam_t, "--t");
      if (sam_n_opt->count() > 0) steps = sam_steps;
      if (!t && !steps)
        throw steady_cli::UsageError("usage", "sam: give --t T (one pose) or --copies N (N steps, N+1 poses)");
      return emit(steady_cli::samCommand(sam_from, sam_to, t, steps, sam_dim, earOptions(sam_half)));
    }
    if (demo->parsed()) {
      const steady_cli::DemoOutput out = steady_cli::demoCommand(demo_data, demo_steps);
      const int status = emit(out.json);
      std::fprintf(stderr, "%s\n", out.summary.c_str());
      return status;
    }
    if (sample->parsed()) return emit(steady_cli::motionSampleCommand(sample_motion, sample_count));
    if (pattern->parsed()) {
      const std::string summary =
          steady_cli::patternCommand(pattern_motion, pattern_copies, pattern_mesh, pattern_output, pattern_binary);
      std::fprintf(stderr, "%s\n", summary.c_str());
      return 0;
    }
    if (collide->parsed()) {
      const steady_cli::CollideOutput out = steady_cli::collideCommand(collide_request);
      const int status = emit(out.json);
      std::fprintf(stderr, "%s\n", out.summary.c_str());
      return status;
    }
    if (sweep->parsed()) {
      sweep_request.check = !sweep_no_check;
      sweep_request.progress = ::isatty(STDERR_FILENO) == 1;
      const steady_cli::SweepOutput out = steady_cli::sweepCommand(sweep_request);
      const int status = out.json.empty() ? 0 : emit(out.json);
      std::fprintf(stderr, "%s\n", out.summary.c_str());
      if (status == 0 && out.defective) {
        std::fprintf(stderr, "steady sweep: the envelope failed its check (see above); it is written for "
                             "inspection only (exit status 4)\n");
        return 4;
      }
      return status;
    }
    // A bare `steady`: list the commands.
    std::cout << app.help() << std::flush;
    return 0;
  } catch (const steady_cli::UsageError& e) {
    return report(e.tag(), e.what(), 2);
  } catch (const steady_cli::OutputError& e) {
    return report("io", e.what(), 1);
  } catch (const steady_cli::Interrupted& e) {
    return report("interrupted", e.what(), 128 + e.signal());
  } catch (const steady::Error& e) {
    // A missing or malformed input file is an unreadable argument; the rest is math.
    const bool input = e.code() == steady::ErrorCode::InvalidFile || e.code() == steady::ErrorCode::Io;
    return report(steady::to_string(e.code()), e.what(), input ? 2 : 3);
  } catch (const std::exception& e) {
    return report("internal", e.what(), 1);
  }
}
