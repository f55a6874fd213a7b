#!/usr/bin/env bash
# Build steady_bench (Release), run it with repetitions and print a Markdown table of the median
# time per call of each benchmark, with the ratio of each steady call to its Eigen peer.
#
# Usage: scripts/bench-table.sh [extra steady_bench flags...]
#   e.g. scripts/bench-table.sh --benchmark_filter='Ear|Log4'
# Environment:
#   BUILD_DIR          build tree (default: <repo>/build); configured with
#                      -DCMAKE_BUILD_TYPE=Release -DSTEADY_BUILD_BENCH=ON
#   CMAKE_ARGS         extra arguments for the cmake configure step
#   BENCH_REPETITIONS  repetitions per benchmark (default 5); the table shows their median
#   BENCH_MIN_TIME     minimum seconds per repetition (default: Google Benchmark's, 0.5)
#   BENCH_TIME         cpu_time (default) or real_time
#   BENCH_JSON         where to keep the JSON output (default: $BUILD_DIR/steady_bench.json)
#   BENCH_CPU          if set, pin the run to this CPU with taskset
#   NO_BUILD=1         skip configure/build and run the existing binary
# The console output of the run goes to stderr; the table is the only thing on stdout.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD_DIR=${BUILD_DIR:-$ROOT/build}
REPS=${BENCH_REPETITIONS:-5}
TIME_FIELD=${BENCH_TIME:-cpu_time}
JSON=${BENCH_JSON:-$BUILD_DIR/steady_bench.json}

case "$TIME_FIELD" in
  cpu_time|real_time) ;;
  *) echo "BENCH_TIME must be cpu_time or real_time (got '$TIME_FIELD')" >&2; exit 2 ;;
esac

if [[ "${NO_BUILD:-0}" != 1 ]]; then
  # shellcheck disable=SC2086  # CMAKE_ARGS is a list of words on purpose
  cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DSTEADY_BUILD_BENCH=ON \
    ${CMAKE_ARGS:-} >&2
  cmake --build "$BUILD_DIR" --target steady_bench -j "$(nproc)" >&2
fi

BIN="$BUILD_DIR/bench/steady_bench"
[[ -x "$BIN" ]] || { echo "no benchmark binary at $BIN" >&2; exit 1; }

run=("$BIN"
     "--benchmark_repetitions=$REPS"
     "--benchmark_report_aggregates_only=true"
     "--benchmark_out=$JSON"
     "--benchmark_out_format=json")
[[ -n "${BENCH_MIN_TIME:-}" ]] && run+=("--benchmark_min_time=$BENCH_MIN_TIME")
run+=("$@")
if [[ -n "${BENCH_CPU:-}" ]]; then
  run=(taskset -c "$BENCH_CPU" "${run[@]}")
fi

echo "+ ${run[*]}" >&2
"${run[@]}" >&2

python3 - "$JSON" "$TIME_FIELD" "$REPS" <<'PY'
import json
import statistics
import sys

path, field, reps = sys.argv[1], sys.argv[2], sys.argv[3]
with open(path) as f:
    doc = json.load(f)

to_ns = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}

# Medians (and coefficient of variation) per benchmark. With repetitions the JSON holds the
# aggregates; without, the single iteration run counts as its own median.
median, cv, errors, samples = {}, {}, {}, {}
for b in doc.get("benchmarks", []):
    name = b.get("run_name", b["name"])
    if b.get("error_occurred"):
        errors[name] = b.get("error_message", "error")
        continue
    ns = b[field] * to_ns[b.get("time_unit", "ns")]
    if b.get("run_type") == "aggregate":
        agg = b.get("aggregate_name")
        if agg == "median":
            median[name] = ns
        elif agg == "cv":
            cv[name] = b[field] * 100.0  # cv is a fraction, not a time
    else:
        samples.setdefault(name, []).append(ns)
for name, xs in samples.items():
    median.setdefault(name, statistics.median(xs))

# steady call -> its Eigen peers; targets and the peers.md figures for reference.
peers = {
    "BM_EarLog2": ["BM_EigenLog2", "BM_EigenLog2Hom"],
    "BM_EarLog3": ["BM_EigenLog4", "BM_EigenLog3"],
    "BM_EarPow3": ["BM_EigenPow4"],
    "BM_EarSpanEval3": ["BM_EigenExp4"],
}
targets = {"BM_EarLog2": 60.0, "BM_EarLog3": 150.0, "BM_EarSpanEval3": 30.0}
reference = {
    "BM_EigenLog2": "peers.md ~537",
    "BM_EigenLog3": "peers.md ~2430",
    "BM_EigenLog4": "peers.md ~3150",
    "BM_EigenExp4": "peers.md ~250 (exp(tX))",
    "BM_EigenPow4": "peers.md ~8700",
}
order = ["BM_EarLog2", "BM_EarLog3", "BM_EarPow3", "BM_EarSpanEval3", "BM_EarSpanBuild3",
         "BM_EigenLog2", "BM_EigenLog2Hom", "BM_EigenLog3", "BM_EigenLog4", "BM_EigenExp4",
         "BM_EigenPow4"]
names = [n for n in order if n in median or n in errors]
names += sorted(n for n in set(median) | set(errors) if n not in order)


def fmt_ns(x):
    return f"{x:,.0f}" if x >= 100 else f"{x:.1f}"


print(f"| benchmark | median ns | cv % | target / reference | ratio to Eigen peer "
      f"(peer ns / steady ns) |")
print("|---|---:|---:|---|---|")
for n in names:
    if n in errors:
        print(f"| {n} | error | | | {errors[n]} |")
        continue
    t = median[n]
    c = f"{cv[n]:.1f}" if n in cv else ""
    if n in targets:
        ok = "met" if t <= targets[n] else "**missed**"
        ref = f"<= {targets[n]:.0f} ns: {ok}"
    else:
        ref = reference.get(n, "")
    ratios = []
    for p in peers.get(n, []):
        if p in median:
            ratios.append(f"{median[p] / t:.1f}x vs {p[3:]} ({fmt_ns(median[p])} ns)")
    print(f"| {n} | {fmt_ns(t)} | {c} | {ref} | {'; '.join(ratios)} |")

ctx = doc.get("context", {})
print()
print(f"Median of {reps} repetitions, `{field}` per call (one call per iteration), "
      f"{ctx.get('date', '?')}, {ctx.get('num_cpus', '?')} CPUs at "
      f"{ctx.get('mhz_per_cpu', '?')} MHz, load average "
      f"{', '.join(f'{x:.2f}' for x in ctx.get('load_avg', [])) or '?'}.")
checks = [k for k in ctx if k.startswith("check_")]
if checks:
    print("Correctness on the benchmark set (max relative entry difference): " +
          ", ".join(f"{k[6:]} {ctx[k]}" for k in checks) + ".")
PY
