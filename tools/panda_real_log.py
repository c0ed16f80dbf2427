#!/usr/bin/env python3
"""`hya identify` on a real arm's identification log, held against that arm's published model.

The log is the exciting trajectory Gaz, Cognetti, Oliva, Robuffo Giordano and De Luca recorded
on a Franka Emika Panda ("Dynamic identification of the Franka Emika Panda robot with retrieval
of feasible parameters using penalty-based optimization", IEEE RA-L 4(4), 2019), published
with their code (github.com/marcocognetti/FrankaEmikaPandaDynModel, matlab/data/Exciting_Traj/
Trajectory_1/rbt_log: 21 s, 20,544 samples about 1 ms apart, measured joint torques). hya's
shipped `panda` carries their identified rigid bodies; their friction law (a sigmoid per
joint, matlab/dyn_model_panda/get_FrictionTorque.m) is applied here at the filtered velocity.

    tools/panda_real_log.py CHECKOUT [path/to/hya]

CHECKOUT is a clone of that repository (its data is not ours to commit). Prints Markdown.
The held-out window is the last quarter of the log, as `hya identify` holds it out; the
residuals there are `d̂` of `hya estimate` (what a model leaves of the filtered torque).
"""

import math
import os
import subprocess
import sys
import tempfile

CHECKOUT = sys.argv[1]
HYA = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), "..", "target", "release", "hya")
N = 7
HELD_OUT = 0.25
# Gaz et al.'s friction: tau_f = A/(1+exp(-alpha (qd + phi))) - A/(1+exp(-alpha phi)) per joint.
GAZ_A = [0.54615, 0.87224, 0.64068, 1.2794, 0.83904, 0.30301, 0.56489]
GAZ_PHI = [0.039533, 0.025882, -0.04607, 0.036194, 0.026226, -0.021047, 0.0035526]
GAZ_ALPHA = [5.1181, 9.0657, 10.136, 5.5903, 8.3469, 17.133, 10.336]


def gaz_friction(i, qd):
    logistic = lambda x: 1.0 / (1.0 + math.exp(-x))
    return GAZ_A[i] * (logistic(GAZ_ALPHA[i] * (qd + GAZ_PHI[i])) - logistic(GAZ_ALPHA[i] * GAZ_PHI[i]))


def hya(args, stdin=""):
    done = subprocess.run([HYA, *args], input=stdin, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"hya {' '.join(args)}: {done.stderr}")
    return done.stdout, done.stderr


def numbers(path):
    with open(os.path.join(CHECKOUT, "matlab/data/Exciting_Traj/Trajectory_1/rbt_log", path)) as f:
        return [float(line) for line in f if line.strip()]


def rows(text):
    """The numeric rows of hya's output (its header line left out; cells comma- or blank-separated)."""
    return [[float(v) for v in line.replace(",", " ").split()]
            for line in text.splitlines() if line and line[0] in "-0123456789"]


def rms(residuals):
    return [math.sqrt(sum(r[i] ** 2 for r in residuals) / len(residuals)) for i in range(N)]


def main():
    time, q, tau = numbers("exciting_traj_time.txt"), numbers("exciting_traj_positions.txt"), numbers(
        "exciting_traj_torques.txt")
    log = "t " + " ".join(f"q{i + 1}" for i in range(N)) + " " + " ".join(f"tau{i + 1}" for i in range(N)) + "\n"
    log += "".join(" ".join(repr(v) for v in [t, *q[k * N:(k + 1) * N], *tau[k * N:(k + 1) * N]]) + "\n"
                   for k, t in enumerate(time))
    out = tempfile.mkdtemp(prefix="hya-panda-real-")
    _, summary = hya(["identify", "--robot", "panda", "--dt", "0.001", "--timestamps", "--max-step", "0.01",
                      "--out", os.path.join(out, "identified")], log)
    start = time[0] + (1.0 - HELD_OUT) * (time[-1] - time[0])
    held = [k for k, t in enumerate(time) if t >= start]
    timed = ["--timestamps", "--max-step", "0.01"]
    published = rows(hya(["estimate", "--robot", "panda", *timed], log)[0])
    # q̂̇ for the published friction: the estimator's filter on q at the log's 1 ms (its steps
    # are 1 ms but for a few), x2 of each channel.
    filtered = rows(hya(["filter", "--dt", "0.001"], "".join(
        " ".join(repr(v) for v in q[k * N:(k + 1) * N]) + "\n" for k in range(len(time))))[0])
    identified = os.path.join(out, "identified")
    ours = rows(hya(["estimate", "--robot", os.path.join(identified, "identified.urdf"), "--friction",
                     os.path.join(identified, "friction.toml"), *timed], log)[0])
    print(f"`hya identify` on Gaz et al.'s Panda log ({len(time)} samples, {time[-1]:.1f} s); files in {out}.\n")
    print(summary.strip().splitlines()[-1] + "\n")
    print("RMS (N·m) over the last quarter of the log of what each model leaves of the filtered torque, "
          "joints 1 to 7:\n")
    print("| model | " + " | ".join(f"j{i + 1}" for i in range(N)) + " |")
    print("|---|" + "---|" * N)
    table = [
        ("published rigid bodies (hya's `panda`), no friction", [published[k][1:] for k in held]),
        ("published rigid bodies and friction",
         [[published[k][1 + i] + gaz_friction(i, filtered[k][N + i]) for i in range(N)] for k in held]),
        ("`hya identify`: its bodies and friction", [ours[k][1:] for k in held]),
    ]
    for label, residuals in table:
        print(f"| {label} | " + " | ".join(f"{v:.3f}" for v in rms(residuals)) + " |")


if __name__ == "__main__":
    main()
