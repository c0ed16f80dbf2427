#!/usr/bin/env python3
"""Per-call cost of hya's inverse dynamics from Python against Pinocchio's `pin.rnea` from Python,
and the batch path's cost per state, for every shipped arm. Prints a Markdown table.

Each figure is the median over 15 rounds of the mean time per call within a round of 2000 calls
(batch: the mean over 8 calls on 1024 states, as `hya bench` times its batches), with the two
libraries interleaved round by round, after one untimed round.

    pip install ./hya-py pin && python tools/python_bench.py [HYA_BINARY] [--rounds FILE]

`--rounds FILE` writes every round's figures (each arm, each column, in round order) to FILE as
JSON, so that a median or a ratio in the table can be checked against its rounds.

Each round also times the Rust batch behind the same call in this process, without Python
(`Model._rust_batch_ns`, on copies of the same arrays), and the table gives the ratio of
Python's figure to it, round by round. Speeds here differ from one process to the next by up to
1.6x on a shared machine, so a ratio against another process mixes that in.

With the `hya` binary (the README's release build), each round also runs `hya bench --robot R
--json` and the table gives its Rust batch figures and the ratio of Python's to them, round by
round.
"""
import argparse
import functools
import json
import statistics
import subprocess
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

import hya

ROOT = Path(__file__).resolve().parent.parent
ROUNDS, CALLS, BATCH, BATCH_CALLS = 15, 2000, 1024, 8


def per_call_ns(f, states):
    start = time.perf_counter_ns()
    for k in range(CALLS):
        f(*states[k % len(states)])
    return (time.perf_counter_ns() - start) / CALLS


def per_state_ns(f, *arrays):
    """Mean ns per state over BATCH_CALLS calls of `f` on BATCH states."""
    start = time.perf_counter_ns()
    for _ in range(BATCH_CALLS):
        f(*arrays)
    return (time.perf_counter_ns() - start) / (BATCH_CALLS * BATCH)


def main():
    parser = argparse.ArgumentParser(description="hya's inverse dynamics from Python against Pinocchio's.")
    parser.add_argument("binary", nargs="?", help="the hya binary, for `hya bench` figures round by round")
    parser.add_argument("--rounds", type=Path, help="write every round's figures to this JSON file")
    args = parser.parse_args()
    binary, rounds = args.binary, {}
    rng = np.random.default_rng(1)
    rust = " Rust ID batch, per state | Python / Rust, ID batch | Rust FD batch, per state | Python / Rust, FD batch |" if binary else ""
    print(f"| robot | hya generated, per call | hya run-time model, per call | pin.rnea, per call | hya ID batch of 1024, per state | hya FD batch of 1024, per state | pin.rnea in a Python loop, per state | Python / Rust in this process, ID batch | Python / Rust in this process, FD batch |{rust}")
    print("|---|---|---|---|---|---|---|---|---|" + ("---|" * 4 if binary else ""))
    for name in hya.Model.builtin_names():
        generated = hya.Model.builtin(name)
        runtime = hya.Model.from_urdf(ROOT / "robots" / "urdf" / f"{name}.urdf")
        model = pin.buildModelFromUrdf(str(ROOT / "robots" / "urdf" / f"{name}.urdf"))
        data = model.createData()
        states = [tuple(rng.uniform(-1, 1, generated.dof) for _ in range(3)) for _ in range(64)]
        q, qd, qdd = (rng.uniform(-1, 1, (BATCH, generated.dof)) for _ in range(3))
        figures = {key: [] for key in ("gen", "rt", "pin", "batch", "fdbatch", "pinloop", "here", "herefd", "rust", "rustfd", "ratio", "ratiofd")}
        # One untimed round first: the first calls of a freshly loaded model run slower.
        rnea = functools.partial(pin.rnea, model, data)
        for f in (generated.inverse_dynamics, runtime.inverse_dynamics, rnea):
            per_call_ns(f, states)
        for _ in range(ROUNDS):
            figures["gen"].append(per_call_ns(generated.inverse_dynamics, states))
            figures["rt"].append(per_call_ns(runtime.inverse_dynamics, states))
            figures["pin"].append(per_call_ns(rnea, states))
            figures["batch"].append(per_state_ns(generated.inverse_dynamics, q, qd, qdd))
            figures["here"].append(figures["batch"][-1] / generated._rust_batch_ns("inverse_dynamics", q, qd, qdd, BATCH_CALLS))
            figures["fdbatch"].append(per_state_ns(generated.forward_dynamics, q, qd, qdd))
            figures["herefd"].append(figures["fdbatch"][-1] / generated._rust_batch_ns("forward_dynamics", q, qd, qdd, BATCH_CALLS))
            start = time.perf_counter_ns()
            for k in range(BATCH):
                rnea(q[k], qd[k], qdd[k])
            figures["pinloop"].append((time.perf_counter_ns() - start) / BATCH)
            if binary:
                bench = json.loads(subprocess.run([binary, "bench", "--robot", name, "--json"], check=True, capture_output=True, text=True).stdout)
                figures["rust"].append(bench["batch_id_ns_per_state"])
                figures["rustfd"].append(bench["batch_fd_ns_per_state"])
                figures["ratio"].append(figures["batch"][-1] / figures["rust"][-1])
                figures["ratiofd"].append(figures["fdbatch"][-1] / figures["rustfd"][-1])
        rounds[name] = {key: values for key, values in figures.items() if values}
        med = {key: statistics.median(values) for key, values in rounds[name].items()}
        print(
            f"| {name} | {med['gen']:.0f} ns | {med['rt']:.0f} ns | {med['pin']:.0f} ns | "
            f"{med['batch']:.0f} ns | {med['fdbatch']:.0f} ns | {med['pinloop']:.0f} ns | {med['here']:.2f}x | {med['herefd']:.2f}x |"
            + (f" {med['rust']:.0f} ns | {med['ratio']:.2f}x | {med['rustfd']:.0f} ns | {med['ratiofd']:.2f}x |" if binary else "")
        )
    if args.rounds:
        args.rounds.write_text(json.dumps(rounds, indent=1) + "\n")


if __name__ == "__main__":
    main()
