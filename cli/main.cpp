// steady: the command-line tool. Real powers of affinities and steady affine morphs as JSON.

#include "affinity_io.hpp"
#include "commands.hpp"

#include <steady/core/ear.hpp>
#include <steady/core/error.hpp>

#include <CLI/CLI.hpp>

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

const char* const kOutputHelp =
    "OUTPUT: JSON on standard output; numbers in the shortest form that reads back to the same\n"
    "  double (at most 17 significant digits). Matrices are arrays of rows of [L | t].\n"
    "EXIT STATUS: 0 success; 2 usage error or unreadable argument; 3 math error (no real logarithm,\n"
    "  reflection, singular pose, overflow); 1 anything else. Errors are reported on standard error\n"
    "  as \"steady: error [<reason>]: <message>\" and nothing is printed on standard output.\n";

int report(const std::string& tag, const std::string& message, int status) {
  std::fprintf(stderr, "steady: error [%s]: %s\n", tag.c_str(), message.c_str());
  return status;
}

steady::EarOptions earOptions(const std::string& half_turn) {
  steady::EarOptions o;
  o.half_turn = half_turn == "cw" ? steady::HalfTurn::Clockwise : steady::HalfTurn::CounterClockwise;
  return o;
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
             kOutputHelp);

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

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    const std::vector<std::string> extra = app.remaining();
    if (app.get_subcommands().empty() && dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr && !extra.empty() &&
        extra.front().rfind('-', 0) != 0)
      return report("usage", "unknown command '" + extra.front() +
                                 "' (the commands are pow, sam and demo; run 'steady --help')", 2);
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
    // A bare `steady`: list the commands.
    std::cout << app.help() << std::flush;
    return 0;
  } catch (const steady_cli::UsageError& e) {
    return report(e.tag(), e.what(), 2);
  } catch (const steady::Error& e) {
    return report(steady::to_string(e.code()), e.what(), 3);
  } catch (const std::exception& e) {
    return report("internal", e.what(), 1);
  }
}
