#!/usr/bin/env python3
"""The paper's goto task on a simulated HyA, and the true against the estimated disturbance.

Runs HyA's goto experiment (quick version) with the paper's estimator (method "lu") through
hya's simulator, loads the arm from its URDF (any URDF loads the same way) and re-estimates the
disturbance from the recorded joint angles and commanded torques with hya.DisturbanceEstimator,
as one would from the log of a real run, and plots the true disturbance against both estimates
per joint. The in-loop estimate reads the simulated sensors (encoder counts, torques from
chamber pressures); the re-estimate reads the simulator's true angles and its commands. Plotting needs
matplotlib (`pip install matplotlib`); without it the script prints a summary.

    pip install ./hya-py
    python examples/python/goto_disturbance.py [--urdf robots/urdf/hya.urdf] [--out goto.png]
"""
import argparse
from pathlib import Path

import numpy as np

import hya

ROOT = Path(__file__).resolve().parents[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--urdf", default=str(ROOT / "robots" / "urdf" / "hya.urdf"))
    parser.add_argument("--out", default="goto_disturbance.png")
    args = parser.parse_args()

    model = hya.Model.from_urdf(args.urdf)
    print(model, "joints:", ", ".join(model.joint_names))
    run = hya.simulate("goto_internal", method="lu", seed=1, quick=True)
    t, d_true, d_hat = run["time"], run["d_true"], run["d_hat"]

    # The same estimate from the log alone: the recorded angles and commanded torques.
    estimator = hya.DisturbanceEstimator(model, q0=run["q"][0], tau0=run["tau_cmd"][0])
    d_log = estimator.run(run["q"][1:], run["tau_cmd"][1:])
    rms = lambda error: np.sqrt((error**2).mean(axis=0)).round(3)  # noqa: E731
    print("RMS of d_true − d̂ per joint (N·m), in the loop:", rms(d_true - d_hat))
    print("RMS of d_true − d̂ per joint (N·m), from the log:", rms(d_true[1:] - d_log))

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no figure")
        return
    fig, axes = plt.subplots(model.dof, 1, sharex=True, figsize=(8, 2 * model.dof))
    for i, ax in enumerate(axes):
        ax.plot(t, d_true[:, i], label="true d", color="black", linewidth=1)
        ax.plot(t, d_hat[:, i], label="d̂ (in the loop)", linewidth=1)
        ax.plot(t[1:], d_log[:, i], label="d̂ (from the log)", linestyle="--", linewidth=1)
        ax.set_ylabel(f"{model.joint_names[i]}\nN·m")
    axes[0].legend(loc="upper right", fontsize="small")
    axes[-1].set_xlabel("time (s)")
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print("wrote", args.out)


if __name__ == "__main__":
    main()
