#!/usr/bin/env python3
"""Per-call cost of hya's inverse dynamics from Python against Pinocchio's `pin.rnea` from Python,
and the batch path's cost per state, for every shipped arm. Prints a Markdown table.

Each figure is the median over 15 rounds of the mean time per call within a round of 2000 calls
(batch: 15 rounds of one call on 1024 states), with the two libraries interleaved round by round,
after one untimed round.

    pip install ./hya-py pin && python tools/python_bench.py
"""
import functools
import statistics
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

import hya

ROOT = Path(__file__).resolve().parent.parent
ROUNDS, CALLS, BATCH = 15, 2000, 1024


def per_call_ns(f, states):
    start = time.perf_counter_ns()
    for k in range(CALLS):
        f(*states[k % len(states)])
    return (time.perf_counter_ns() - start) / CALLS


def main():
    rng = np.random.default_rng(1)
    print("| robot | hya generated, per call | hya run-time model, per call | pin.rnea, per call | hya batch of 1024, per state | pin.rnea in a Python loop, per state |")
    print("|---|---|---|---|---|---|")
    for name in hya.Model.builtin_names():
        generated = hya.Model.builtin(name)
        runtime = hya.Model.from_urdf(ROOT / "robots" / "urdf" / f"{name}.urdf")
        model = pin.buildModelFromUrdf(str(ROOT / "robots" / "urdf" / f"{name}.urdf"))
        data = model.createData()
        states = [tuple(rng.uniform(-1, 1, generated.dof) for _ in range(3)) for _ in range(64)]
        q, qd, qdd = (rng.uniform(-1, 1, (BATCH, generated.dof)) for _ in range(3))
        figures = {key: [] for key in ("gen", "rt", "pin", "batch", "pinloop")}
        # One untimed round first: the first calls of a freshly loaded model run slower.
        rnea = functools.partial(pin.rnea, model, data)
        for f in (generated.inverse_dynamics, runtime.inverse_dynamics, rnea):
            per_call_ns(f, states)
        for _ in range(ROUNDS):
            figures["gen"].append(per_call_ns(generated.inverse_dynamics, states))
            figures["rt"].append(per_call_ns(runtime.inverse_dynamics, states))
            figures["pin"].append(per_call_ns(rnea, states))
            start = time.perf_counter_ns()
            generated.inverse_dynamics(q, qd, qdd)
            figures["batch"].append((time.perf_counter_ns() - start) / BATCH)
            start = time.perf_counter_ns()
            for k in range(BATCH):
                rnea(q[k], qd[k], qdd[k])
            figures["pinloop"].append((time.perf_counter_ns() - start) / BATCH)
        med = {key: statistics.median(values) for key, values in figures.items()}
        print(
            f"| {name} | {med['gen']:.0f} ns | {med['rt']:.0f} ns | {med['pin']:.0f} ns | "
            f"{med['batch']:.0f} ns | {med['pinloop']:.0f} ns |"
        )


if __name__ == "__main__":
    main()
