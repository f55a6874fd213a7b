#!/usr/bin/env bash
# Build steady_bench (Release), run the sweep benchmarks (bench/bench_sweep.cpp) each in its own
# process (so that the peak memory each reports is its own), and print Markdown tables: steady
# against the OpenVDB sampled-union baseline at matched error, every run in detail, and the
# time-versus-faces curve with a fitted exponent.
#
# Usage: scripts/bench-sweep.sh [extra steady_bench flags...]
# Environment:
#   BUILD_DIR          build tree (default: <repo>/build); configured with
#                      -DCMAKE_BUILD_TYPE=Release -DSTEADY_BUILD_BENCH=ON
#   CMAKE_ARGS         extra arguments for the cmake configure step
#   BUILD_JOBS         parallel build jobs (default: nproc)
#   BENCH_FILTER       extended regex (grep -E) selecting among the sweep benchmarks
#                      (BM_SteadySweep/..., BM_VdbSweep/...); default: all of them.
#                      e.g. 'elephant/screw' for one body and motion
#   STEADY_REPS        repetitions of each steady run (default 3; the table shows the median)
#   BENCH_TIMEOUT      seconds after which one run is stopped and reported as such (default 1800)
#   OUT_DIR            where the JSON of each run is kept (default: $BUILD_DIR/bench-sweep)
#   NO_BUILD=1         skip configure/build and run the existing binary
# The console output of the runs goes to stderr; the tables are the only thing on stdout.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD_DIR=${BUILD_DIR:-$ROOT/build}
FILTER=${BENCH_FILTER:-.}
REPS=${STEADY_REPS:-3}
TIMEOUT=${BENCH_TIMEOUT:-1800}
OUT_DIR=${OUT_DIR:-$BUILD_DIR/bench-sweep}

if [[ "${NO_BUILD:-0}" != 1 ]]; then
  # shellcheck disable=SC2086  # CMAKE_ARGS is a list of words on purpose
  cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DSTEADY_BUILD_BENCH=ON \
    ${CMAKE_ARGS:-} >&2
  cmake --build "$BUILD_DIR" --target steady_bench -j "${BUILD_JOBS:-$(nproc)}" >&2
fi

BIN="$BUILD_DIR/bench/steady_bench"
[[ -x "$BIN" ]] || { echo "no benchmark binary at $BIN" >&2; exit 1; }

mkdir -p "$OUT_DIR"
rm -f "$OUT_DIR"/run-*.json "$OUT_DIR"/run-*.status
mapfile -t names < <("$BIN" --benchmark_list_tests=true --benchmark_filter='^BM_(SteadySweep|VdbSweep)/' |
                     grep -E -- "$FILTER" || true)
[[ ${#names[@]} -gt 0 ]] || { echo "no benchmark matches '$FILTER'" >&2; exit 1; }

i=0
for name in "${names[@]}"; do
  i=$((i + 1))
  json="$OUT_DIR/run-$(printf %03d "$i").json"
  regex="^$(printf '%s' "$name" | sed 's/[.[\*^$()+?{|]/\\&/g')\$"
  run=("$BIN" "--benchmark_filter=$regex" "--benchmark_out=$json" "--benchmark_out_format=json")
  if [[ "$name" == BM_SteadySweep/* && "$REPS" -gt 1 ]]; then
    run+=("--benchmark_repetitions=$REPS" "--benchmark_report_aggregates_only=true")
  fi
  run+=("$@")
  echo "+ [$i/${#names[@]}] ${run[*]}" >&2
  status=0
  timeout "$TIMEOUT" "${run[@]}" >&2 || status=$?
  if [[ $status -ne 0 ]]; then
    # 124: stopped by timeout; anything else: the run failed (crash, out of memory)
    printf '%s\t%s\n' "$name" "$status" > "${json%.json}.status"
  fi
done

python3 - "$OUT_DIR" "$TIMEOUT" <<'PY'
import glob
import json
import math
import os
import re
import sys

out_dir, timeout = sys.argv[1], float(sys.argv[2])
to_s = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}


def base(name):
    # Drop Google Benchmark's suffixes (/iterations:1, /real_time, /repeats:n).
    return re.sub(r"/(iterations:\d+|repeats:\d+|real_time|process_time|min_time:[^/]+)", "", name)


def parse(name):
    # BM_SteadySweep/<mesh>/<motion>/eps<e> or BM_VdbSweep/<mesh>/<motion>/h<k>_N<n>
    kind, mesh, motion, setting = name.split("/")
    return kind, mesh, motion, setting


def is_sweep(name):
    return re.fullmatch(r"BM_(SteadySweep|VdbSweep)/[^/]+/[^/]+/[^/]+", name) is not None



runs, failed, ctx = {}, {}, {}
for path in sorted(glob.glob(os.path.join(out_dir, "run-*.json"))):
    try:
        with open(path) as f:
            doc = json.load(f)
    except (OSError, ValueError):
        continue
    ctx = doc.get("context", ctx)
    for b in doc.get("benchmarks", []):
        name = base(b.get("run_name", b["name"]))
        if not is_sweep(name):
            continue
        if b.get("error_occurred"):
            failed[name] = b.get("error_message", "error")
            continue
        if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
            continue
        r = dict(b)
        r["seconds"] = b["real_time"] * to_s[b.get("time_unit", "ns")]
        runs[name] = r
for path in sorted(glob.glob(os.path.join(out_dir, "run-*.status"))):
    with open(path) as f:
        name, status = f.read().strip().split("\t")
        name = base(name)
    if is_sweep(name) and name not in runs and name not in failed:
        failed[name] = f"stopped after {timeout:.0f} s" if status == "124" else f"exit status {status}"


def fnum(x, digits=3):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "—"
    if x == 0:
        return "0"
    if abs(x) >= 1e4 or abs(x) < 1e-3:
        return f"{x:.{digits - 1}e}"
    return f"{x:.{digits}g}"


def fint(x):
    return "—" if x is None else f"{x:,.0f}"


def fsec(x):
    return "—" if x is None else (f"{x:.3f}" if x < 10 else f"{x:.1f}")


def fit(points):
    # Least-squares slope of log(time) against log(faces).
    xs = [math.log(f) for f, _ in points]
    ys = [math.log(t) for _, t in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else float("nan")


ref_eps, main_eps = "eps0.0001", "eps0.001"
reference = {}
for name, r in runs.items():
    kind, mesh, motion, setting = parse(name)
    if kind == "BM_SteadySweep" and setting == ref_eps:
        reference[(mesh, motion)] = r["volume"]


def vol_diff(mesh, motion, r):
    ref = reference.get((mesh, motion))
    return None if ref is None or "volume" not in r else (r["volume"] - ref) / ref


cases = []
for name in list(runs) + list(failed):
    kind, mesh, motion, setting = parse(name)
    if (mesh, motion) not in cases:
        cases.append((mesh, motion))

targets = {("elephant", "screw"): 0.5, ("bunny00", "screw"): 3.0}
peak_limit_mb = 2048.0
eps = 1e-3

print("### steady against the OpenVDB sampled union at matched error")
print()
print("ε = 1e-3 × bounding-box diagonal (bodies scaled to diagonal 1). *err* = containment error "
      "(largest distance outside the output of the body's vertices posed at 64 seeded times); "
      "*vol Δ* = volume relative to steady at ε/10. The matched OpenVDB run is the fastest one "
      "whose containment error is at most ε.")
print()
print("| body | motion | faces in | steady s | faces out | vol Δ | err | peak MB | "
      "OpenVDB matched | OpenVDB s | faces out | vol Δ | err | peak MB | speed-up (wall / CPU) | targets |")
print("|---|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---|---|")
for mesh, motion in cases:
    if re.fullmatch(r"sphere\d+", mesh):
        continue  # the time-versus-faces family: last table
    sname = f"BM_SteadySweep/{mesh}/{motion}/{main_eps}"
    s = runs.get(sname)
    vdb = [(n, r) for n, r in runs.items() if n.startswith(f"BM_VdbSweep/{mesh}/{motion}/")]
    vdb_failed = [n for n in failed if n.startswith(f"BM_VdbSweep/{mesh}/{motion}/")]
    if s is None and not vdb:
        continue
    faces_in = (s or (vdb[0][1] if vdb else {})).get("faces_in")
    row = [mesh, motion, fint(faces_in)]
    notes = []
    if s is not None:
        row += [fsec(s["seconds"]), fint(s.get("faces_out")), fnum(vol_diff(mesh, motion, s)),
                fnum(s.get("err_out")), fint(s.get("peak_mb"))]
        lim = targets.get((mesh, motion))
        if lim is not None:
            notes.append(f"≤ {lim} s: {'met' if s['seconds'] <= lim else '**missed**'}")
        if s.get("peak_mb") is not None:
            notes.append(f"≤ 2 GB: {'met' if s['peak_mb'] <= peak_limit_mb else '**missed**'}")
    else:
        row += [failed.get(sname, "not run"), "", "", "", ""]
    ok = sorted((r["seconds"], n, r) for n, r in vdb if r.get("err_out", math.inf) <= eps)
    if ok:
        t, n, r = ok[0]
        row += [n.split("/")[-1], fsec(t), fint(r.get("faces_out")), fnum(vol_diff(mesh, motion, r)),
                fnum(r.get("err_out")), fint(r.get("peak_mb"))]
        if s is not None:
            wall = t / s["seconds"]
            cpu = r["cpu_s"] / s["cpu_s"] if s.get("cpu_s") else None
            row.append(f"{wall:.1f}x / {fnum(cpu)}x")
            notes.append(f"≥ 10x: {'met' if wall >= 10 else '**missed**'}")
        else:
            row.append("")
    else:
        # No OpenVDB run reached ε. Its cost there is bounded below by the slowest run (a finer
        # voxel costs more; a stopped run counts with the time limit), and estimated by the
        # power laws of error and time against the voxel size through the two finest N = auto
        # runs (the local slopes; the time's steepens towards h^-3 as the voxel shrinks, so the
        # estimate errs low).
        best = min(vdb, key=lambda nr: nr[1].get("err_out", math.inf)) if vdb else None
        if best is not None:
            n, r = best
            row += [f"none ≤ ε; most accurate: {n.split('/')[-1]}", fsec(r["seconds"]),
                    fint(r.get("faces_out")), fnum(vol_diff(mesh, motion, r)), fnum(r.get("err_out")),
                    fint(r.get("peak_mb"))]
            slowest = max([r2["seconds"] for _, r2 in vdb] +
                          [timeout for n2 in vdb_failed if failed[n2].startswith("stopped")])
            ladder = sorted((r2["voxel"], r2["err_out"], r2["seconds"]) for n2, r2 in vdb
                            if n2.endswith("_Nauto") and r2.get("err_out", 0) > 0)[:2]
            est = ""
            if len(ladder) >= 2:
                p_err = fit([(h, e) for h, e, _ in ladder])
                p_time = fit([(h, t) for h, _, t in ladder])
                # log e = log e0 + p_err log(h / h0): the voxel size where e = ε, and its time
                h0, e0, t0 = min(ladder)
                if p_err > 0:
                    h_eps = h0 * (eps / e0) ** (1 / p_err)
                    t_eps = t0 * (h_eps / h0) ** p_time
                    est = (f"; ≈ {t_eps / s['seconds']:.0f}x extrapolated (voxel ≈ {h_eps / eps:.2g} ε, "
                           f"≈ {t_eps:.3g} s; fits err ∝ h^{p_err:.2f}, time ∝ h^{p_time:.2f})") if s else ""
            if s is not None:
                row.append(f"> {slowest / s['seconds']:.1f}x (measured lower bound){est}")
                notes.append("≥ 10x: " + ("met (lower bound)" if slowest / s["seconds"] >= 10 else "open"))
            else:
                row.append(est)
        else:
            row += ["—", "", "", "", "", "", ""]
    if vdb_failed:
        notes.append("OpenVDB " + ", ".join(f"{n.split('/')[-1]}: {failed[n]}" for n in vdb_failed))
    row.append("; ".join(notes))
    print("| " + " | ".join(str(x) for x in row) + " |")

print()
print("### Every run")
print()
print("| benchmark | wall s | CPU s | faces out | volume | vol Δ | err | outside > ε | peak MB | stages (s) |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---|")
for name in sorted(set(runs) | set(failed), key=lambda n: (parse(n)[1], parse(n)[2], parse(n)[0], n)):
    kind, mesh, motion, setting = parse(name)
    if name in failed:
        print(f"| {name} | {failed[name]} | | | | | | | | |")
        continue
    r = runs[name]
    if kind == "BM_SteadySweep":
        stages = ", ".join(f"{k[2:]} {r[k]:.3f}" for k in
                           ("s_cycle", "s_intersect", "s_label", "s_output", "s_check") if k in r)
        flags = []
        if r.get("closed") == 0 or r.get("manifold") == 0:
            flags.append("**not closed/manifold**")
        if r.get("self_x", 0) > 0:
            flags.append(f"**{r['self_x']:.0f} self-intersections**")
        if flags:
            stages += "; " + ", ".join(flags)
    else:
        stages = (f"level sets {r.get('s_levelsets', 0):.3f}, union {r.get('s_union', 0):.3f}, "
                  f"mesh {r.get('s_mesh', 0):.3f}; voxel {fnum(r.get('voxel'))}, "
                  f"N {r.get('samples', 0):.0f}, {fnum(r.get('voxels'))} voxels")
    print(f"| {name} | {fsec(r['seconds'])} | {fsec(r.get('cpu_s'))} | {fint(r.get('faces_out'))} | "
          f"{fnum(r.get('volume'), 6)} | {fnum(vol_diff(mesh, motion, r))} | {fnum(r.get('err_out'))} | "
          f"{fint(r.get('n_out_eps'))} | {fint(r.get('peak_mb'))} | {stages} |")


print()
print("### Time against faces (steady, ε = 1e-3 × diagonal)")
print()
print("The exponent is the least-squares slope of log time against log faces; the n log n column "
      "is the slope that n log n itself has over the same face counts (its reference for "
      "\"no worse than O(n log n)\").")
print()
print("| family | faces : seconds | fitted exponent | n log n exponent | verdict |")
print("|---|---|---:|---:|---|")
families = {
    "subdivided sphere, screw": lambda m, mo: (m == "sphere" or (m.startswith("sphere") and m[6:].isdigit()))
    and mo == "screw",
    "CGAL meshes, screw": lambda m, mo: not m.startswith("sphere") and mo == "screw",
    "CGAL meshes, affine": lambda m, mo: not m.startswith("sphere") and mo == "affine",
}
for label, member in families.items():
    pts = []
    for name, r in runs.items():
        kind, mesh, motion, setting = parse(name)
        if kind == "BM_SteadySweep" and setting == main_eps and member(mesh, motion):
            pts.append((r["faces_in"], r["seconds"]))
    pts.sort()
    if len(pts) < 2:
        continue
    k = fit(pts)
    knlogn = fit([(f, f * math.log(f)) for f, _ in pts])
    verdict = "met" if k <= knlogn else "**missed**"
    if len(pts) < 3:
        verdict += " (two sizes only: indicative)"
    curve = ", ".join(f"{f:,.0f} : {t:.3f}" for f, t in pts)
    print(f"| {label} | {curve} | {k:.2f} | {knlogn:.2f} | {verdict} |")

print()
load = ", ".join(f"{x:.2f}" for x in ctx.get("load_avg", [])) or "?"
print(f"Wall-clock time (median of the steady repetitions, one run for OpenVDB), "
      f"{ctx.get('date', '?')}, {ctx.get('num_cpus', '?')} CPUs at {ctx.get('mhz_per_cpu', '?')} MHz, "
      f"load average {load}; OpenVDB uses every core (TBB), CPU s counts all threads. "
      f"Peak MB: the process's peak resident memory after its timed sweeps, one process per run.")
PY
