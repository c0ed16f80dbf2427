#!/usr/bin/env python3
"""Measures hya's generated and generic dynamics against Pinocchio in one run and writes
BENCHMARKS.md. Run through tools/pinocchio_bench.sh, which builds the Pinocchio program.

The machine's speed drifts by up to 1.8x for seconds at a time, so the programs are interleaved
robot by robot, round after round, and each figure is the median over the rounds of the medians
each program reports (each of those a median over 31 rounds of 2000 calls)."""
import argparse
import datetime
import json
import os
import platform
import statistics
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# The shipped robots, from the one list of them.
ROBOTS = [
    line.split()[0]
    for line in (ROOT / "robots" / "robots.list").read_text().splitlines()
    if line.strip() and not line.lstrip().startswith("#")
]
TARGET = ROOT / "target" / "bench-native"


def run(*args):
    return subprocess.run(args, check=True, capture_output=True, text=True, cwd=ROOT).stdout


def cpu():
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return platform.processor() or "unknown"


def stats(robot):
    """Operation counts of the generated functions, from `hya generate --stats`."""
    text = run(str(TARGET / "release/hya"), "generate", f"robots/urdf/{robot}.urdf", "--name", "X", "--stats")
    counts = {}
    for line in text.splitlines()[1:]:
        name, adds, muls, _divs, trig = line.split()
        counts[name] = (int(adds), int(muls), int(trig))
    return counts


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pinocchio", required=True, help="the pinocchio_bench binary")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--out", default=str(ROOT / "BENCHMARKS.md"))
    args = parser.parse_args()
    # target-cpu=native, like the Pinocchio build; a target directory of its own, so ordinary
    # builds keep theirs.
    env = dict(os.environ, RUSTFLAGS="-C target-cpu=native", CARGO_TARGET_DIR=str(TARGET))
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "hya-cli"], check=True, cwd=ROOT, env=env)
    hya_runs = {r: [] for r in ROBOTS}
    pin_runs = {r: [] for r in ROBOTS}
    for round_index in range(args.rounds):
        for robot in ROBOTS:
            hya_runs[robot].append(json.loads(run(str(TARGET / "release/hya"), "bench", "--robot", robot, "--json")))
            pin_runs[robot].append(json.loads(run(args.pinocchio, robot, str(ROOT / f"robots/urdf/{robot}.urdf"))))
        print(f"round {round_index + 1}/{args.rounds} done", flush=True)

    def med(runs, key):
        values = [r[key] for r in runs if r.get(key) is not None]
        return statistics.median(values) if values else None

    lines = [
        "# Benchmarks",
        "",
        "Generated dynamics against hya's generic tree model and Pinocchio, measured side by side in one run",
        "by `tools/pinocchio_bench.sh` (medians in ns per call; ratios are Pinocchio or generic over generated).",
        "",
        f"- Date: {datetime.date.today().isoformat()}; CPU: {cpu()}; {os.cpu_count()} cores, shared and noisy.",
        f"- hya: `RUSTFLAGS='-C target-cpu=native' cargo build --release` ({run('rustc', '--version').strip()}).",
        f"- Pinocchio {os.environ.get('PINOCCHIO_VERSION', '(version unknown)')} from the `pin` wheel: `g++ {os.environ.get('PINOCCHIO_FLAGS', '')}`; its algorithms are header templates, compiled with these flags.",
        f"- Method: {args.rounds} interleaved rounds per robot; each program reports the median of 31 rounds of 2000 calls over 64 varied states.",
        "",
        "| robot | ID generated | ID generic | Pinocchio rnea | rnea / generated | generic / generated | M generated | M generic | Pinocchio crba | FD generated | FD generic | Pinocchio aba | ID ops (adds, muls, sin_cos) | M ops |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for robot in ROBOTS:
        h, p = hya_runs[robot], pin_runs[robot]
        gid, generic_id, rnea = med(h, "generated_id_ns"), med(h, "generic_id_ns"), med(p, "rnea_ns")
        counts = stats(robot)
        id_ops = counts["inverse_dynamics"]
        m_ops = counts["mass_matrix"]
        lines.append(
            f"| {robot} | {gid:.0f} | {generic_id:.0f} | {rnea:.0f} | {rnea / gid:.1f}x | {generic_id / gid:.1f}x | "
            f"{med(h, 'generated_mass_ns'):.0f} | {med(h, 'generic_mass_ns'):.0f} | {med(p, 'crba_ns'):.0f} | "
            f"{med(h, 'generated_fd_ns'):.0f} | {med(h, 'generic_fd_ns'):.0f} | {med(p, 'aba_ns'):.0f} | "
            f"{id_ops[0]}, {id_ops[1]}, {id_ops[2]} | {m_ops[0]}, {m_ops[1]}, {m_ops[2]} |"
        )
    tick = med(hya_runs["hya"], "tick_ns")
    realtime = med(hya_runs["hya"], "sim_realtime_factor_hydraulic")
    lines += [
        "",
        f"HyA control tick (two filter steps, estimator inverse dynamics, controller inverse dynamics): **{tick:.0f} ns**.",
    ]
    if realtime:
        lines.append(f"Simulation of `goto_internal` (method lu, 5 kHz RK4 plant): **{realtime:.0f}x** real time.")
    hya_id = med(hya_runs["hya"], "generated_id_ns")
    rnea_ratio = med(pin_runs["hya"], "rnea_ns") / hya_id
    generic_ratio = med(hya_runs["hya"], "generic_id_ns") / hya_id
    verdict = lambda ok: "met" if ok else "**missed**"
    lines += [
        "",
        "## Targets (HyA, this run)",
        "",
        "| target | measured | verdict |",
        "|---|---|---|",
        f"| generated ID ≥ 4x faster than Pinocchio's rnea | {rnea_ratio:.1f}x | {verdict(rnea_ratio >= 4)} |",
        f"| generated ID ≥ 3x faster than the generic path | {generic_ratio:.1f}x | {verdict(generic_ratio >= 3)} |",
        f"| control tick < 500 ns | {tick:.0f} ns | {verdict(tick < 500)} |",
        f"| goto_internal ≥ 200x real time | {realtime:.0f}x | {verdict(realtime >= 200)} |" if realtime else "",
    ]
    lines += [
        "",
        "FD generated: the generated mass matrix and bias forces with a Cholesky solve; Pinocchio's aba is",
        "the articulated-body algorithm. Operation counts are of the generated code after constant folding",
        "and dead-code elimination (`hya generate ROBOT.urdf --name X --stats`).",
        "",
    ]
    Path(args.out).write_text("\n".join(lines))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
