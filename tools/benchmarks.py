#!/usr/bin/env python3
"""Measures hya's generated and generic dynamics against Pinocchio in one run and writes
BENCHMARKS.md. Run through tools/pinocchio_bench.sh, which builds the Pinocchio program.

Two hya builds take part: `plain`, the binary the README's `cargo run --release` builds, and
`native`, the same with `RUSTFLAGS='-C target-cpu=native'` (like the Pinocchio build). The
machine's speed drifts by up to 1.8x for seconds at a time, so the three programs are
interleaved robot by robot, round after round (their order rotating), and every ratio is
computed within a round, from figures measured seconds apart; tables give the median over the
rounds and the spread (lowest to highest). Each program's figure in a round is itself a median
over 31 rounds of 2000 calls."""
import argparse
from xml.etree import ElementTree
import datetime
import json
import os
import platform
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# The shipped robots, from the one list of them.
ROBOTS = [
    line.split()[0]
    for line in (ROOT / "robots" / "robots.list").read_text().splitlines()
    if line.strip() and not line.lstrip().startswith("#")
]
# Where each build lives, and the flags it is built with.
BUILDS = {
    "plain": (ROOT / "target", {}),
    "native": (ROOT / "target" / "bench-native", {"RUSTFLAGS": "-C target-cpu=native"}),
}
NOTES = Path(__file__).resolve().parent / "benchmarks_notes.md"
# Measurements made apart from this run (profiles, compile times), each dated in its text.
STUDIES = Path(__file__).resolve().parent / "benchmarks_studies.md"
# The last run's raw figures, for re-rendering (`--from-json`).
RAW = Path(__file__).resolve().parent / ".build" / "benchmarks_raw.json"
# The last Python table (`--python`), kept for rewrites without it.
PYTHON_RAW = RAW.parent / "python_bench.md"
# Every round of that table's figures.
PYTHON_ROUNDS = RAW.parent / "python_bench_rounds.json"


def run(*args):
    return subprocess.run(args, check=True, capture_output=True, text=True, cwd=ROOT).stdout


def hya(build):
    return str(BUILDS[build][0] / "release" / "hya")


def cpu():
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return platform.processor() or "unknown"


def stats(robot):
    """Operation counts of the generated functions, from `hya generate --stats`."""
    text = run(hya("plain"), "generate", f"robots/urdf/{robot}.urdf", "--name", "X", "--stats")
    counts = {}
    for line in text.splitlines()[1:]:
        if line.startswith("total"):
            continue
        name, adds, muls, mul_adds, divs, trig = line.split()
        counts[name] = (int(adds), int(muls), int(mul_adds), int(divs), int(trig))
    return counts


def last_link(robot):
    """The URDF's last link, the frame whose kinematics hya generates (`TreeModel::tip_frame`)."""
    links = ElementTree.parse(ROOT / f"robots/urdf/{robot}.urdf").getroot().iter("link")
    return [link.get("name") for link in links][-1]


def commit():
    """The commit measured, marked if the work tree differs from it."""
    head = run("git", "rev-parse", "--short", "HEAD").strip()
    return head + (" with uncommitted changes" if run("git", "status", "--porcelain", "--untracked-files=no").strip() else "")


def median_and_spread(values, digits=0, suffix=""):
    """`median [lowest–highest]` of the rounds' values."""
    values = [v for v in values if v is not None]
    if not values:
        return "–"
    fmt = f"{{:.{digits}f}}"
    med = fmt.format(statistics.median(values))
    return f"{med}{suffix} [{fmt.format(min(values))}–{fmt.format(max(values))}]"


def measure(pinocchio, rounds):
    """`runs[round][robot] = {"plain": json, "native": json, "pinocchio": json}`."""
    programs = {
        "plain": lambda robot: [hya("plain"), "bench", "--robot", robot, "--json"],
        "native": lambda robot: [hya("native"), "bench", "--robot", robot, "--json"],
        "pinocchio": lambda robot: [pinocchio, robot, str(ROOT / f"robots/urdf/{robot}.urdf"), last_link(robot)],
    }
    order = list(programs)
    runs = []
    for round_index in range(rounds):
        figures = {}
        for robot in ROBOTS:
            figures[robot] = {}
            for name in order:
                figures[robot][name] = json.loads(run(*programs[name](robot)))
            order = order[1:] + order[:1]
        for robot in ROBOTS:
            # Pinocchio timed the URDF's last link; hya's generated kinematics are of its tip.
            tips = {figures[robot][b].get("frame") for b in ("plain", "native")} - {None}
            if tips and tips != {last_link(robot)}:
                raise SystemExit(f"{robot}: hya's tip {tips} is not the URDF's last link {last_link(robot)}")
        runs.append(figures)
        print(f"round {round_index + 1}/{rounds} done", flush=True)
    return runs


def reproduce_seconds(quick):
    """Wall-clock seconds of `hya reproduce` (plain build) into a scratch directory."""
    with tempfile.TemporaryDirectory() as out:
        args = [hya("plain"), "reproduce", "--out", out] + (["--quick"] if quick else [])
        start = time.monotonic()
        subprocess.run(args, check=True, capture_output=True, cwd=ROOT)
        return time.monotonic() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pinocchio", required=True, help="the pinocchio_bench binary")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--no-reproduce", action="store_true", help="skip timing `hya reproduce`")
    parser.add_argument("--out", default=str(ROOT / "BENCHMARKS.md"))
    parser.add_argument("--from-json", help="write BENCHMARKS.md from a saved run's raw figures instead of measuring")
    parser.add_argument("--python", help="a Python with hya and pin installed: adds tools/python_bench.py's table")
    args = parser.parse_args()
    # A rewrite from saved figures needs only the plain build, for the operation counts.
    for build, (target, flags) in BUILDS.items():
        if args.from_json and build != "plain":
            continue
        env = {k: v for k, v in os.environ.items() if k != "RUSTFLAGS"}
        env.update(CARGO_TARGET_DIR=str(target), **flags)
        print(f"building hya ({build})", flush=True)
        subprocess.run(["cargo", "build", "--release", "-q", "-p", "hya-cli"], check=True, cwd=ROOT, env=env)
    if args.from_json:
        saved = json.loads(Path(args.from_json).read_text())
        runs, reproduce, meta = saved["runs"], saved["reproduce"], saved["meta"]
    else:
        # What the figures were measured on, kept with them for a later rewrite.
        meta = {
            "date": datetime.date.today().isoformat(),
            "cpu": cpu(),
            "cores": os.cpu_count(),
            "rustc": run("rustc", "--version").strip(),
            "pinocchio": os.environ.get("PINOCCHIO_VERSION", "(version unknown)"),
            "pinocchio_flags": os.environ.get("PINOCCHIO_FLAGS", "(flags unknown)"),
            "rounds": args.rounds,
            "commit": commit(),
        }
        runs = measure(args.pinocchio, args.rounds)
        reproduce = None if args.no_reproduce else (reproduce_seconds(False), reproduce_seconds(True))
        RAW.parent.mkdir(exist_ok=True)
        RAW.write_text(json.dumps({"runs": runs, "reproduce": reproduce, "meta": meta}))
        print(f"raw figures in {RAW}", flush=True)

    def each(robot, program, key):
        return [r[robot][program].get(key) for r in runs]

    def ratios(robot, numerator, denominator):
        """Per-round ratios `numerator / denominator`, each a (program, key) pair."""
        out = []
        for r in runs:
            top, bottom = r[robot][numerator[0]].get(numerator[1]), r[robot][denominator[0]].get(denominator[1])
            out.append(top / bottom if top and bottom else None)
        return out

    def med(values):
        return statistics.median([v for v in values if v is not None])

    build_features = {b: runs[0]["hya"][b]["build"] for b in ("plain", "native")}
    # How generated code met FMA in each build (absent from runs before the key existed).
    fma = {b: runs[0]["hya"][b].get("generated_fma", "not recorded") for b in ("plain", "native")}
    lines = [
        "# Benchmarks",
        "",
        "Generated dynamics against hya's generic tree model and Pinocchio, measured side by side in one run",
        "by `tools/pinocchio_bench.sh [--python PY]` (`python3 tools/benchmarks.py --pinocchio - --from-json tools/.build/benchmarks_raw.json [--python PY]` rewrites it from the saved figures). Figures are ns per call: the median over the rounds, with the lowest",
        "and highest round in brackets. Ratios are computed within each round and then summarised the same way.",
        "",
        f"- Date: {meta['date']}; CPU: {meta['cpu']}; {meta['cores']} cores, shared and noisy; {meta['rustc']}"
        + (f"; commit {meta['commit']}." if meta.get("commit") else "."),
        f"- hya **plain**: `cargo build --release`, what the README's commands build (compiled for `{build_features['plain']}`; generated code's fused multiply-add variant: {fma['plain']}).",
        f"- hya **native**: `RUSTFLAGS='-C target-cpu=native' cargo build --release` (compiled for `{build_features['native']}`; fused variant: {fma['native']}); shown beside, labelled.",
        f"- Pinocchio {meta['pinocchio']} from the `pin` wheel: `g++ {meta['pinocchio_flags']}`; its algorithms are header templates, compiled with these flags.",
        f"- Method: {meta['rounds']} rounds; in each, for every robot, the plain build, the native build and Pinocchio run one after the other (the order rotating); each reports the median of 31 rounds of 2000 calls over 64 varied states. The Python table, if present, is measured after the rounds.",
        "",
    ]
    for build in ("plain", "native"):
        lines += [
            f"## hya {build} build against Pinocchio (native)",
            "",
            "| robot | ID generated | ID generic | Pinocchio rnea | rnea / generated | M generated | Pinocchio crba | crba / M | FD generated (ABA) | FD generic | Pinocchio aba | aba / FD |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|",
        ]
        for robot in ROBOTS:
            lines.append(
                f"| {robot} | {median_and_spread(each(robot, build, 'generated_id_ns'))} "
                f"| {median_and_spread(each(robot, build, 'generic_id_ns'))} "
                f"| {median_and_spread(each(robot, 'pinocchio', 'rnea_ns'))} "
                f"| {median_and_spread(ratios(robot, ('pinocchio', 'rnea_ns'), (build, 'generated_id_ns')), 1, 'x')} "
                f"| {median_and_spread(each(robot, build, 'generated_mass_ns'))} "
                f"| {median_and_spread(each(robot, 'pinocchio', 'crba_ns'))} "
                f"| {median_and_spread(ratios(robot, ('pinocchio', 'crba_ns'), (build, 'generated_mass_ns')), 1, 'x')} "
                f"| {median_and_spread(each(robot, build, 'generated_fd_ns'))} "
                f"| {median_and_spread(each(robot, build, 'generic_fd_ns'))} "
                f"| {median_and_spread(each(robot, 'pinocchio', 'aba_ns'))} "
                f"| {median_and_spread(ratios(robot, ('pinocchio', 'aba_ns'), (build, 'generated_fd_ns')), 1, 'x')} |"
            )
        lines.append("")
    lines += [
        "## Batches: many states per call",
        "",
        "hya's batch entry points (`Dynamics::inverse_dynamics_batch`, `forward_dynamics_batch`) on 1024 states per",
        "call, ns per state, against the single call in the same build and against Pinocchio on the same 1024 states:",
        "`rnea` in a C++ loop, and `rneaInParallel` (OpenMP over a pool of model copies) on one thread and on every",
        "core. A speed-up is single-call ns over batch ns per state, computed within each round. hya's batches run",
        "four states per AVX2 register, in the plain build chosen at run time; they use one core.",
        "",
    ]
    for build in ("plain", "native"):
        lines += [
            f"### hya {build} build",
            "",
            "| robot | ID single | ID batch | batch speed-up | Pinocchio rnea loop | rnea loop / ID batch | rneaInParallel, 1 thread | rneaInParallel, all cores | FD single | FD batch | batch speed-up |",
            "|---|---|---|---|---|---|---|---|---|---|---|",
        ]
        for robot in ROBOTS:
            lines.append(
                f"| {robot} | {median_and_spread(each(robot, build, 'generated_id_ns'))} "
                f"| {median_and_spread(each(robot, build, 'batch_id_ns_per_state'))} "
                f"| {median_and_spread(ratios(robot, (build, 'generated_id_ns'), (build, 'batch_id_ns_per_state')), 1, 'x')} "
                f"| {median_and_spread(each(robot, 'pinocchio', 'rnea_loop_ns_per_state'))} "
                f"| {median_and_spread(ratios(robot, ('pinocchio', 'rnea_loop_ns_per_state'), (build, 'batch_id_ns_per_state')), 1, 'x')} "
                f"| {median_and_spread(each(robot, 'pinocchio', 'rnea_parallel_1_ns_per_state'))} "
                f"| {median_and_spread(each(robot, 'pinocchio', 'rnea_parallel_all_ns_per_state'))} "
                f"| {median_and_spread(each(robot, build, 'generated_fd_ns'))} "
                f"| {median_and_spread(each(robot, build, 'batch_fd_ns_per_state'))} "
                f"| {median_and_spread(ratios(robot, (build, 'generated_fd_ns'), (build, 'batch_fd_ns_per_state')), 1, 'x')} |"
            )
        lines.append("")
    lines += [
        "## Frame kinematics and derivatives",
        "",
        "The last link's world-aligned Jacobian (hya's generated `FrameKinematics::frame_jacobian` against",
        "Pinocchio's `computeFrameJacobian`, `LOCAL_WORLD_ALIGNED`, each from `q`), the derivatives of inverse",
        "dynamics (hya's generated analytic pass against `computeRNEADerivatives`) and of forward dynamics",
        "(hya's `−M⁻¹ ∂ID` from the generated pieces, with `M⁻¹`, against `computeABADerivatives`), ns per call,",
        "and the ratio Pinocchio / hya within each round. `computeRNEADerivatives` also gives `∂τ/∂q̈ = M`, which hya's",
        "∇ID leaves out; `computeABADerivatives` gives `M⁻¹` as hya's ∇FD does. Rounds measured before these keys existed show –.",
        "",
    ]
    for build in ("plain", "native"):
        lines += [
            f"### hya {build} build",
            "",
            "| robot | J generated | computeFrameJacobian | ratio | ∇ID generated | computeRNEADerivatives | ratio | ∇FD generated | computeABADerivatives | ratio |",
            "|---|---|---|---|---|---|---|---|---|---|",
        ]
        for robot in ROBOTS:
            pairs = [
                ("generated_jacobian_ns", "compute_frame_jacobian_ns"),
                ("generated_id_derivatives_ns", "compute_rnea_derivatives_ns"),
                ("generated_fd_derivatives_ns", "compute_aba_derivatives_ns"),
            ]
            cells = [
                f"{median_and_spread(each(robot, build, ours))} | {median_and_spread(each(robot, 'pinocchio', theirs))} "
                f"| {median_and_spread(ratios(robot, ('pinocchio', theirs), (build, ours)), 1, 'x')}"
                for ours, theirs in pairs
            ]
            lines.append(f"| {robot} | " + " | ".join(cells) + " |")
        lines.append("")
    threads = {r["hya"]["pinocchio"].get("rnea_parallel_threads") for r in runs} - {None}
    if threads:
        lines += [f"`rneaInParallel`, all cores: {', '.join(str(t) for t in sorted(threads))} threads.", ""]
    lines += [
        "## HyA: control tick and simulator",
        "",
        "| figure | plain | native |",
        "|---|---|---|",
        f"| control tick, `DisturbanceAttenuation::tick` (two filter steps, the estimator's and the controller's ID in one two-state batch, checks), ns | {median_and_spread(each('hya', 'plain', 'tick_ns'))} | {median_and_spread(each('hya', 'native', 'tick_ns'))} |",
        f"| the same tick as `update` then `command` (two single IDs), ns | {median_and_spread(each('hya', 'plain', 'tick_in_sequence_ns'))} | {median_and_spread(each('hya', 'native', 'tick_in_sequence_ns'))} |",
        f"| `goto_internal`, method lu, lag actuators: seed-seconds per wall s on one core, seeds in lockstep | {median_and_spread(each('hya', 'plain', 'sim_realtime_factor'))} | {median_and_spread(each('hya', 'native', 'sim_realtime_factor'))} |",
        f"| the same seeds one by one | {median_and_spread(each('hya', 'plain', 'sim_realtime_factor_one_by_one'))} | {median_and_spread(each('hya', 'native', 'sim_realtime_factor_one_by_one'))} |",
        f"| the hydraulic plant, in lockstep | {median_and_spread(each('hya', 'plain', 'sim_realtime_factor_hydraulic'))} | {median_and_spread(each('hya', 'native', 'sim_realtime_factor_hydraulic'))} |",
        f"| the hydraulic plant, one by one | {median_and_spread(each('hya', 'plain', 'sim_realtime_factor_hydraulic_one_by_one'))} | {median_and_spread(each('hya', 'native', 'sim_realtime_factor_hydraulic_one_by_one'))} |",
        f"| ideal actuators, in lockstep | {median_and_spread(each('hya', 'plain', 'sim_realtime_factor_ideal'))} | {median_and_spread(each('hya', 'native', 'sim_realtime_factor_ideal'))} |",
        f"| ideal actuators, one by one | {median_and_spread(each('hya', 'plain', 'sim_realtime_factor_ideal_one_by_one'))} | {median_and_spread(each('hya', 'native', 'sim_realtime_factor_ideal_one_by_one'))} |",
        f"| `(∂τ/∂q, ∂τ/∂q̇)`, generated (analytic), ns | {median_and_spread(each('hya', 'plain', 'generated_id_derivatives_ns'))} | {median_and_spread(each('hya', 'native', 'generated_id_derivatives_ns'))} |",
        f"| `(∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)`, from the generated pieces, ns | {median_and_spread(each('hya', 'plain', 'generated_fd_derivatives_ns'))} | {median_and_spread(each('hya', 'native', 'generated_fd_derivatives_ns'))} |",
        f"| last link's Jacobian, run-time tree, ns | {median_and_spread(each('hya', 'plain', 'generic_jacobian_ns'))} | {median_and_spread(each('hya', 'native', 'generic_jacobian_ns'))} |",
    ]
    if reproduce:
        lines.append(f"| `hya reproduce` (full; `--quick`), wall s, plain build, once after the rounds | {reproduce[0]:.0f} ({reproduce[1]:.0f} quick) | – |")
    lines += ["", "## Operation counts of the generated code", ""]
    lines += [
        "After constant folding, common-subexpression and dead-code elimination (`hya generate ROBOT.urdf --name X --stats`):",
        "adds, multiplies, fused multiply-adds (each one add and one multiply of the plain variant), divisions, `sin_cos` lanes.",
        "",
        "| robot | inverse dynamics | mass matrix | forward dynamics (ABA) |",
        "|---|---|---|---|",
    ]
    fmt_ops = lambda c: " / ".join(str(n) for n in c)
    for robot in ROBOTS:
        c = stats(robot)
        lines.append(f"| {robot} | {fmt_ops(c['inverse_dynamics'])} | {fmt_ops(c['mass_matrix'])} | {fmt_ops(c['forward_dynamics'])} |")
    lines.append("")
    if args.python:
        print("timing from Python", flush=True)
        table = run(args.python, str(Path(__file__).resolve().parent / "python_bench.py"), hya("plain"), "--rounds", str(PYTHON_ROUNDS))
        PYTHON_RAW.write_text(table)
    else:
        table = PYTHON_RAW.read_text() if PYTHON_RAW.exists() else None
    if table:
        lines += [
            "## From Python",
            "",
            "Per call from Python (the wheel `pip install ./hya-py` builds, plain flags), against `pin.rnea` from",
            "the `pin` wheel; and the batch path's cost per state for 1024 states per call (NumPy arrays,",
            "read in place with the GIL held, as a batch this short is; the mean of 8 calls, as `hya bench` times",
            "the Rust batches in the tables above) against `pin.rnea` called in a Python loop. Medians of 15",
            "interleaved rounds (`tools/python_bench.py`, run after the rounds above). Each round also times the",
            "Rust batch behind the call in the same process, without Python, and runs `hya bench` (plain build)",
            "for the Rust batch figures beside them; ratios are taken within each round."
            + (f" Every round's figures are in `{PYTHON_ROUNDS.relative_to(ROOT)}` (not committed)." if PYTHON_ROUNDS.exists() else ""),
            "",
            table.rstrip(),
            "",
        ]
    for notes in (STUDIES, NOTES):
        if notes.exists():
            lines += [notes.read_text().rstrip(), ""]

    # The targets of the speed issue, on HyA, in the plain build (the one users get).
    h = lambda key: each("hya", "plain", key)
    rnea_ratio = ratios("hya", ("pinocchio", "rnea_ns"), ("plain", "generated_id_ns"))
    aba_ratio = ratios("hya", ("pinocchio", "aba_ns"), ("plain", "generated_fd_ns"))
    batch_id_speedup = ratios("hya", ("plain", "generated_id_ns"), ("plain", "batch_id_ns_per_state"))
    batch_rnea_ratio = ratios("hya", ("pinocchio", "rnea_loop_ns_per_state"), ("plain", "batch_id_ns_per_state"))
    batch_fd_speedup = ratios("hya", ("plain", "generated_fd_ns"), ("plain", "batch_fd_ns_per_state"))

    def target(name, rounds, ok, unit, digits):
        """A row: the median of the rounds against `ok`, and how many rounds meet it."""
        rounds = [v for v in rounds if v is not None]
        median, meeting = statistics.median(rounds), sum(ok(v) for v in rounds)
        if not ok(median):
            verdict = "**missed**"
        elif meeting == len(rounds):
            verdict = "met"
        else:
            verdict = f"met at the median ({meeting} of {len(rounds)} rounds)"
        return f"| {name} | {median_and_spread(rounds, digits, unit)} | {verdict} |"

    rows = [
        target("generated ID ≤ 100 ns", h("generated_id_ns"), lambda v: v <= 100, " ns", 0),
        target("generated ID ≥ 10x Pinocchio's rnea", rnea_ratio, lambda v: v >= 10, "x", 1),
        target("mass matrix ≤ 100 ns", h("generated_mass_ns"), lambda v: v <= 100, " ns", 0),
        target("forward dynamics ≤ 300 ns", h("generated_fd_ns"), lambda v: v <= 300, " ns", 0),
        target("forward dynamics ≥ 5x Pinocchio's aba", aba_ratio, lambda v: v >= 5, "x", 1),
        target("control tick ≤ 300 ns", h("tick_ns"), lambda v: v <= 300, " ns", 0),
        target("batch ID ≥ 3x the single call's throughput", batch_id_speedup, lambda v: v >= 3, "x", 1),
        target("batch ID ≥ 20x Pinocchio's rnea (in a loop, per state)", batch_rnea_ratio, lambda v: v >= 20, "x", 1),
        target("batch FD ≥ 2.5x the single call's throughput", batch_fd_speedup, lambda v: v >= 2.5, "x", 1),
        target("simulation ≥ 500x real time (lag)", h("sim_realtime_factor"), lambda v: v >= 500, "x", 0),
        target("simulation ≥ 300x real time (hydraulic)", h("sim_realtime_factor_hydraulic"), lambda v: v >= 300, "x", 0),
    ]
    # The kinematics issue's targets, on HyA and iiwa14 (rounds from before these keys: none).
    for robot in ("hya", "iiwa14"):
        for name, ours, theirs in [
            ("frame Jacobian ≥ 5x computeFrameJacobian", "generated_jacobian_ns", "compute_frame_jacobian_ns"),
            ("∇ID ≥ 5x computeRNEADerivatives", "generated_id_derivatives_ns", "compute_rnea_derivatives_ns"),
            ("∇FD ≥ 5x computeABADerivatives", "generated_fd_derivatives_ns", "compute_aba_derivatives_ns"),
        ]:
            measured = [v for v in ratios(robot, ("pinocchio", theirs), ("plain", ours)) if v is not None]
            if robot in ROBOTS and measured:
                rows.append(target(f"{robot}: {name}", measured, lambda v: v >= 5, "x", 1))
    if reproduce:
        rows.append(f"| `hya reproduce` < 1 min | {reproduce[0]:.0f} s (once) | {'met' if reproduce[0] < 60 else '**missed**'} |")
    lines += [
        "## Targets (HyA unless named, plain build: the median of this run's rounds, lowest and highest round in brackets)",
        "",
        "| target | measured | verdict |",
        "|---|---|---|",
        *rows,
        "",
    ]
    Path(args.out).write_text("\n".join(lines))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
