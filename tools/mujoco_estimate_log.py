#!/usr/bin/env python3
"""A recorded log of HyA simulated by MuJoCo under a known disturbance, for checking
`hya estimate` against an engine other than hya's own.

The arm is MuJoCo's import of robots/urdf/hya.urdf, set up as the ideal rigid-body chain of
tools/mujoco_rollout.py (same checks against the URDF). A controller running in this script at
1 kHz tracks small sinusoids about HyA's home pose with a PD law plus MuJoCo's own bias forces,
and a known disturbance torque d(t) acts on every joint besides the command:

    M(q) q̈ + C(q, q̇) + G(q) = τ + d,   so   d = ID(q, q̇, q̈) − τ   (hya's definition)

    d_i(t) = D_i sin(2π f_i t) + S_i · [t ≥ 1 s]            (zero at t = 0, where the arm rests)

τ is held over each 1 ms tick (zero-order hold); d is applied continuously. The state is
integrated with RK4 at 1e-4 s. Writes hya-cli/tests/data/mujoco_hya_estimate.csv: '#' comment
lines, then one row per tick k (t_k = k ms, k = 0..1999):

    q_1..q_6 (rad, the state at t_k), τ_1..τ_6 (N·m, the command held from t_k), d_1..d_6 (N·m, d(t_k))

The first twelve columns are what `hya estimate` reads; the last six are the truth.

Usage (with the virtualenv of tools/mujoco_rollout.py):
    tools/.venv/bin/python tools/mujoco_estimate_log.py
"""
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mujoco  # noqa: E402

from mujoco_rollout import fmt, gravity_torque, load  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "hya-cli" / "tests" / "data" / "mujoco_hya_estimate.csv"
DT = 1e-4  # integration step, s
TICK = 1e-3  # control period, s
DURATION = 2.0  # s
Q0 = np.array([0.0, 0.0, -0.7854, 0.7854, 0.7854, 0.0])
# Reference sinusoids about Q0: amplitude (rad) and frequency (Hz) per joint.
REF_AMPLITUDE = np.array([0.05, 0.05, 0.08, 0.08, 0.1, 0.1])
REF_FREQUENCY = np.array([0.5, 0.6, 0.7, 0.8, 0.9, 1.0])
# The disturbance: sine amplitude D (N·m), frequency f (Hz), step S (N·m) at 1 s.
D = np.array([4.0, 3.0, 1.0, 0.8, 0.3, 0.2])
F = np.array([1.3, 1.7, 2.1, 2.5, 2.9, 3.3])
S = np.array([-2.0, 2.5, 0.6, -0.5, 0.2, -0.1])
# PD gains per joint: stiffness (N·m/rad) and damping (N·m·s/rad).
KP = np.array([400.0, 400.0, 60.0, 60.0, 10.0, 10.0])
KD = np.array([40.0, 40.0, 6.0, 6.0, 1.0, 1.0])


def disturbance(t):
    return D * np.sin(2 * math.pi * F * t) + S * (t >= 1.0)


def reference(t):
    return Q0 + REF_AMPLITUDE * np.sin(2 * math.pi * REF_FREQUENCY * t)


def main():
    m, _urdf, notes, _balanced = load("hya")
    m.opt.timestep = DT
    d = mujoco.MjData(m)
    d.qpos[:] = Q0
    d.qvel[:] = 0.0
    mujoco.mj_forward(m, d)
    hold = gravity_torque(m, Q0)
    per_tick = round(TICK / DT)
    rows = []
    for k in range(round(DURATION / TICK)):
        t = k * TICK
        mujoco.mj_forward(m, d)
        q, qd = d.qpos.copy(), d.qvel.copy()
        tau = hold if k == 0 else d.qfrc_bias + KP * (reference(t) - q) - KD * qd
        tau = np.array(tau, dtype=float)
        rows.append(list(q) + list(tau) + list(disturbance(t)))
        for s in range(per_tick):
            # d is evaluated at the start of each integration step (1e-4 s): MuJoCo holds
            # qfrc_applied over its RK4 step.
            d.qfrc_applied[:] = tau + disturbance(t + s * DT)
            mujoco.mj_step(m, d)
        if not np.all(np.isfinite(d.qpos)):
            raise SystemExit("the log blew up")
    swing = np.ptp(np.array([r[:6] for r in rows]), axis=0)
    comments = [
        "# HyA in MuJoCo " + mujoco.__version__ + " (tools/mujoco_estimate_log.py): rows q(6) tau(6) d(6) per 1 ms tick",
        "# d = ID(q, qd, qdd) - tau: d_i(t) = D_i sin(2 pi f_i t) + S_i [t >= 1 s]",
        "# D = " + " ".join(map(fmt, D)) + "; f = " + " ".join(map(fmt, F)) + "; S = " + " ".join(map(fmt, S)),
        "# joint swing over the log (rad): " + " ".join(f"{x:.3f}" for x in swing),
    ] + [f"# note: {n}" for n in notes]
    OUT.parent.mkdir(parents=True, exist_ok=True)
    with OUT.open("w") as f:
        for line in comments:
            f.write(line + "\n")
        for row in rows:
            f.write(" ".join(f"{x:.12g}" for x in row) + "\n")
    print(f"wrote {OUT} ({OUT.stat().st_size} bytes); swing {swing}")


if __name__ == "__main__":
    main()
