#!/usr/bin/env python3
"""hya's estimator and computed torque driving MuJoCo's model of HyA at 1 kHz under a disturbance.

The arm is MuJoCo's import of robots/urdf/hya.urdf, set up by tools/mujoco_rollout.py as an ideal
rigid-body chain (checked there against the URDF; torques enter through qfrc_applied). hya runs
the controller from its Python package, on its generated model of the same URDF:

    d̂ = ID(q̂, q̂̇, q̂̈) − τ̂                               hya.DisturbanceEstimator (q and τ filtered)
    τ = M(q) q̈_des + C(q, q̇) + G(q) − K_D ė − K_P e − d̂   hya.ComputedTorque, e = q − q_des

It reads MuJoCo's joint angles and velocities every 1 ms tick, feeds the estimator the torque it
commanded over the last tick (ideal actuators: the measured torque is the command), and holds the
new command over the next tick (MuJoCo integrates with RK4 at 0.1 ms). The reference and the gains
are those of tools/mujoco_estimate_log.py: small sinusoids about HyA's home pose. MuJoCo applies a
disturbance hya does not know, in hya's convention M q̈ + C + G = τ + d:

    d(t) = D sin(2π f t + φ) + Jᵀ(q) F(t)     (joint torques through qfrc_applied, and a payload)

the payload being the paper's 2 kg weight (sections VI-C, VI-D) hanging from the end effector:
F = (0, 0, −2 kg · 9.81 m/s²) at the "ee" frame from a quarter of the run on (xfrc_applied on the
last body, MuJoCo's Jᵀ F through mj_applyFT). The loop runs twice, without and with d̂ in the
command, and prints per joint the RMS tracking error of each run and, for the compensated run, the
RMS of d, of d̂ − d and the correlation of d̂ with d. As a check of both models and of
the bookkeeping, hya's inverse dynamics on MuJoCo's q, q̇, q̈ after every tick must give back the
forces MuJoCo applied (τ + d) to rounding.

It exits non-zero if its own sanity check fails: the run must stay finite, that check must hold
(to 1e-6 N·m), compensation must lower
the tracking error summed over the joints, and on every joint where d is not negligible d̂ must
correlate with it (above 0.5) and be closer to it than zero is (RMS of d̂ − d below that of d).

    python3 -m venv .venv && .venv/bin/pip install ./hya-py -r tools/requirements-mujoco.txt
    .venv/bin/python examples/python/mujoco_closed_loop.py [--seconds 4] [--payload 2.0]
"""
import argparse
import math
import sys
from pathlib import Path

import numpy as np

import hya

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import mujoco  # noqa: E402
from mujoco_estimate_log import KD, KP, Q0, REF_AMPLITUDE, REF_FREQUENCY, reference  # noqa: E402
from mujoco_rollout import load  # noqa: E402

TICK = 1e-3  # control period, s
SUBSTEPS = 10  # MuJoCo steps per tick (RK4 at 0.1 ms)
GRAVITY = 9.81  # m/s², along the base's −z as in hya and tools/mujoco_rollout.py
# Joint-torque disturbance: amplitude D (N·m), frequency f (Hz, the paper's section V loads
# are at 1 Hz), phase φ (rad), chosen for this example.
D = np.array([3.0, 3.0, 1.0, 0.8, 0.3, 0.2])
F = np.array([1.0, 0.8, 1.0, 0.7, 1.0, 0.9])
PHI = np.array([0.0, 0.9, 1.8, 2.7, 3.6, 4.5])
MAX_MISMATCH = 1e-6  # N·m: hya's and MuJoCo's dynamics of one URDF agree to rounding
NEGLIGIBLE = 0.05  # N·m: an RMS of d below this is not checked (nothing to estimate)


def reference_rates(t):
    """q̇_des and q̈_des of mujoco_estimate_log.reference (q_des = Q0 + A sin(2π f t)), exactly."""
    w = 2 * math.pi * REF_FREQUENCY
    return REF_AMPLITUDE * w * np.cos(w * t), -REF_AMPLITUDE * w**2 * np.sin(w * t)


def joint_disturbance(t):
    return D * np.sin(2 * math.pi * F * t + PHI) - D * np.sin(PHI)  # zero at t = 0, where the arm rests


class Arm:
    """MuJoCo's HyA with hya's model of it: measurements, commands, and the disturbance."""

    def __init__(self, m, model, payload_kg, payload_from):
        self.m = m
        self.d = mujoco.MjData(m)
        self.d.qpos[:] = Q0
        self.d.qvel[:] = 0.0
        mujoco.mj_forward(self.m, self.d)
        self.model = model
        self.body = self.m.nbody - 1  # the last body: Wrist_FE, with "ee" fused into it
        self.weight = np.array([0.0, 0.0, -payload_kg * GRAVITY])
        self.payload_from = payload_from

    def payload(self, t):
        """(force, point): the weight at the "ee" frame, from payload_from on."""
        point = self.model.frame_pose(self.d.qpos.copy(), "ee")[:3, 3]
        return (self.weight if t >= self.payload_from else np.zeros(3)), point

    def disturbance(self, t):
        """d(t) in joint space at the current state: joint torques plus Jᵀ F of the payload."""
        force, point = self.payload(t)
        torque = np.zeros(self.m.nv)
        mujoco.mj_applyFT(self.m, self.d, force, np.zeros(3), point, self.body, torque)
        return joint_disturbance(t) + torque

    def step(self, t, tau):
        """Holds tau over one tick while the disturbance acts (re-evaluated every substep)."""
        h = TICK / SUBSTEPS
        for s in range(SUBSTEPS):
            mujoco.mj_kinematics(self.m, self.d)  # xipos of the current state
            force, point = self.payload(t + s * h)
            self.d.xfrc_applied[:] = 0.0
            self.d.xfrc_applied[self.body, :3] = force
            # xfrc_applied acts at the body's centre of mass: the moment of the force about it
            # puts the force's line of action through the "ee" point.
            self.d.xfrc_applied[self.body, 3:] = np.cross(point - self.d.xipos[self.body], force)
            self.d.qfrc_applied[:] = tau + joint_disturbance(t + s * h)
            mujoco.mj_step(self.m, self.d)
        mujoco.mj_forward(self.m, self.d)  # positions, Jacobians and q̈ of the new state

    def model_mismatch(self):
        """max |ID(q, q̇, q̈) − Σ forces applied| over the joints, with hya's inverse dynamics on
        MuJoCo's state and acceleration: zero up to rounding if hya's model is MuJoCo's and the
        applied forces are what this script thinks they are."""
        force, moment = self.d.xfrc_applied[self.body, :3], self.d.xfrc_applied[self.body, 3:]
        applied = self.d.qfrc_applied.copy()
        mujoco.mj_applyFT(self.m, self.d, force, moment, self.d.xipos[self.body], self.body, applied)
        inverse = self.model.inverse_dynamics(self.d.qpos.copy(), self.d.qvel.copy(), self.d.qacc.copy())
        return np.abs(inverse - applied).max()


def run(m, model, compensate, seconds, payload_kg):
    """One closed loop from rest at Q0; returns the series (e, d̂, d) as arrays, one row per
    tick, and the largest model mismatch (Arm.model_mismatch) seen."""
    arm = Arm(m, model, payload_kg, payload_from=seconds / 4)
    controller = hya.ComputedTorque(model, kp=KP, kd=KD)
    tau = model.gravity(Q0)
    estimator = hya.DisturbanceEstimator(model, dt=TICK, q0=Q0, tau0=tau)
    rows, mismatch = [], 0.0
    for k in range(round(seconds / TICK)):
        t = k * TICK
        q, qd = arm.d.qpos.copy(), arm.d.qvel.copy()  # MuJoCo's measurements
        d_hat = estimator.update(q, tau)  # the torque held over the last tick
        qd_des, qdd_des = reference_rates(t)
        q_des = reference(t)
        tau = np.array(controller.command(q, qd, q_des, qd_des, qdd_des, d_hat if compensate else None))
        rows.append((q - q_des, d_hat, arm.disturbance(t)))
        arm.step(t, tau)
        mismatch = max(mismatch, arm.model_mismatch())
        if not np.all(np.isfinite(arm.d.qpos)):
            raise SystemExit(f"the run {'with' if compensate else 'without'} compensation blew up at t = {t:.3f} s")
    return [np.array(column) for column in zip(*rows)] + [mismatch]


def rms(x):
    return np.sqrt((x**2).mean(axis=0))


def correlation(a, b):
    a, b = a - a.mean(axis=0), b - b.mean(axis=0)
    return (a * b).sum(axis=0) / np.sqrt((a**2).sum(axis=0) * (b**2).sum(axis=0) + 1e-300)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=4.0, help="length of each run, s")
    parser.add_argument("--payload", type=float, default=2.0, help="the weight hung from the end effector, kg")
    args = parser.parse_args()
    if not (0.02 <= args.seconds <= 600):
        parser.error(f"--seconds {args.seconds}: must be in [0.02, 600]")
    if not (0.0 <= args.payload <= 100):
        parser.error(f"--payload {args.payload}: must be in [0, 100] kg")

    model = hya.Model.builtin("hya")
    m, _urdf, notes, _balanced = load("hya")  # checked against the URDF; prints what the import changed
    m.opt.timestep = TICK / SUBSTEPS
    for note in notes:
        print(f"  import: {note}")
    print(f"HyA in MuJoCo {mujoco.__version__}, hya's generated model; {args.seconds} s at {1 / TICK:.0f} Hz, "
          f"{args.payload} kg at 'ee' from t = {args.seconds / 4} s")
    e_off, _, _, mismatch_off = run(m, model, False, args.seconds, args.payload)
    e_on, d_hat, d, mismatch_on = run(m, model, True, args.seconds, args.payload)
    mismatch = max(mismatch_off, mismatch_on)

    fmt = lambda values: " ".join(f"{v:8.4f}" for v in values)  # noqa: E731
    print("joint (d and d̂: the compensated run)    " + " ".join(f"{n:>8}" for n in model.joint_names))
    print("tracking RMS without compensation, mrad " + fmt(1e3 * rms(e_off)))
    print("tracking RMS with compensation, mrad    " + fmt(1e3 * rms(e_on)))
    print("applied disturbance d RMS, N·m          " + fmt(rms(d)))
    print("estimate error d̂ − d RMS, N·m           " + fmt(rms(d_hat - d)))
    print("correlation of d̂ with d                 " + fmt(correlation(d_hat, d)))
    print(f"hya's ID(q, q̇, q̈) on MuJoCo's states against the forces applied: within {mismatch:.2e} N·m")

    checked = rms(d) > NEGLIGIBLE
    failures = []
    if not mismatch < MAX_MISMATCH:
        failures.append(f"hya's model and MuJoCo's differ by {mismatch:.3g} N·m (above {MAX_MISMATCH})")
    if not rms(e_on).sum() < rms(e_off).sum():
        failures.append("compensation does not lower the tracking error")
    for i in np.flatnonzero(checked):
        name = model.joint_names[i]
        if not correlation(d_hat, d)[i] > 0.5:
            failures.append(f"{name}: d̂ does not correlate with d")
        if not rms(d_hat - d)[i] < rms(d)[i]:
            failures.append(f"{name}: d̂ is no closer to d than zero is")
    if failures:
        print("sanity check FAILED: " + "; ".join(failures))
        return 1
    print(f"sanity check passed ({checked.sum()} joints with d above {NEGLIGIBLE} N·m RMS)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
