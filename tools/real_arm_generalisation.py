#!/usr/bin/env python3
"""How `hya identify` generalises on real arms' logs: identified on the first half of a log,
evaluated on the second, the same evaluation for every model (hya identify's own held-out
table: the filtered torque, one sample per 1/ω), as relative RMS per joint,
RMS(τ − τ̂) / RMS(τ), and its mean over the joints.

    tools/real_arm_generalisation.py ur10e DYNAMIC_CALIBRATION_CHECKOUT [path/to/hya]
    tools/real_arm_generalisation.py panda PANDA_DYN_MODEL_CHECKOUT [path/to/hya]

ur10e: Mamedov et al.'s UR10e (github.com/shamilmamedov/dynamic_calibration; Innopolis
University): dataset_ur10e/identification_data/ur-20_02_19_14harm50sec.csv, 56.4 s at about
100 Hz with jittered timestamps (columns t, q1-6, qd1-6, measured current 1-6, ...), the torque
the motor currents times the drive gains identified with the data (UR10E_parameters.txt,
drvGains), and the URDF URe/urdf/ur10e.urdf: an arm no one here tuned anything to.
panda: Gaz et al.'s exciting trajectory (see tools/panda_real_log.py).

The checkouts' data are not ours to commit; this prints Markdown.
"""

import math
import os
import re
import subprocess
import sys
import tempfile

ARM, CHECKOUT = sys.argv[1], sys.argv[2]
HYA = sys.argv[3] if len(sys.argv) > 3 else os.path.join(os.path.dirname(__file__), "..", "target", "release", "hya")
# UR10E_parameters.txt, drvGains (N·m/A), as Mamedov et al. identified them.
UR10E_DRIVE_GAINS = [10.0, 10.6956, 8.4566, 9.0029, 9.4800, 10.1232]


def ur10e():
    path = os.path.join(CHECKOUT, "dataset_ur10e/identification_data/ur-20_02_19_14harm50sec.csv")
    rows = []
    with open(path) as f:
        for line in f:
            v = [float(x) for x in line.split(",")]
            t, q, current = v[0], v[1:7], v[13:19]
            rows.append([t, *q, *(g * i for g, i in zip(UR10E_DRIVE_GAINS, current))])
    robot = os.path.join(CHECKOUT, "URe/urdf/ur10e.urdf")
    return robot, rows, ["--dt", "0.01", "--timestamps", "--max-step", "0.05"], 6


def panda():
    def numbers(name):
        with open(os.path.join(CHECKOUT, "matlab/data/Exciting_Traj/Trajectory_1/rbt_log", name)) as f:
            return [float(line) for line in f if line.strip()]
    time, q, tau = numbers("exciting_traj_time.txt"), numbers("exciting_traj_positions.txt"), numbers(
        "exciting_traj_torques.txt")
    rows = [[t, *q[k * 7:(k + 1) * 7], *tau[k * 7:(k + 1) * 7]] for k, t in enumerate(time)]
    return "panda", rows, ["--dt", "0.001", "--timestamps", "--max-step", "0.01"], 7


def identify(robot, log, timing, n, extra):
    out = os.path.join(tempfile.mkdtemp(prefix="hya-generalisation-"), "identified")
    args = [HYA, "identify", "--robot", robot, *timing, "--held-out", "0.5", "--out", out, *extra]
    done = subprocess.run(args, input=log, capture_output=True, text=True)
    if done.returncode != 0:
        return None, done.stderr.strip().removeprefix("hya: "), out
    with open(os.path.join(out, "report.md")) as f:
        report = f.read()
    table = report.split("## Torque prediction on the held-out part")[1].split("\n\n")[1].splitlines()
    header = [c.strip() for c in table[0].strip("|").split("|")]
    cells = [[c.strip() for c in line.strip("|").split("|")] for line in table[2:2 + n]]
    measured = [float(c[1]) for c in cells]
    models = {name: [float(c[k]) / m for c, m in zip(cells, measured)] for k, name in enumerate(header) if k >= 2}
    weight = re.search(r"prior weight (\S+)\)", done.stderr).group(1)
    return models, weight, out


def main():
    robot, rows, timing, n = {"ur10e": ur10e, "panda": panda}[ARM]()
    log = "".join(" ".join(repr(v) for v in row) + "\n" for row in rows)
    print(f"`hya identify --held-out 0.5` on the {ARM} log ({len(rows)} rows, {rows[-1][0] - rows[0][0]:.1f} s): "
          "RMS(τ − τ̂)/RMS(τ) per joint on the second half, and the mean.\n")
    print("| model | " + " | ".join(f"j{i + 1}" for i in range(n)) + " | mean |")
    print("|---|" + "---|" * (n + 1))
    line = lambda label, v: print(f"| {label} | " + " | ".join(f"{x:.3f}" for x in v) + f" | {sum(v) / n:.3f} |")
    shown = set()  # the baselines printed: "nominal", and the joint law fitted alone per (armature, reversals)
    for label, extra in [("log alone (`--prior-weight 0`)", ["--prior-weight", "0"]),
                         ("log alone, armature (`--prior-weight 0 --armature`)", ["--prior-weight", "0", "--armature"]),
                         ("prior, λ chosen (`--prior-weight auto`)", ["--prior-weight", "auto"]),
                         ("prior and armature (`--prior-weight auto --armature`)", ["--prior-weight", "auto", "--armature"]),
                         ("log alone, reversals kept (`--prior-weight 0 --keep-reversals`)",
                          ["--prior-weight", "0", "--keep-reversals"]),
                         ("prior, reversals kept (`--prior-weight auto --keep-reversals`)",
                          ["--prior-weight", "auto", "--keep-reversals"])]:
        models, weight, _ = identify(robot, log, timing, n, extra)
        if models is None:
            print(f"| `hya identify`, {label} | refused: {weight} |")
            continue
        if "nominal" not in shown:
            line("nominal URDF", models["nominal model"])
            shown.add("nominal")
        law = ("--armature" in extra, "--keep-reversals" in extra)
        if law not in shown:
            what = "friction and armature fit" if law[0] else "friction fit"
            line(f"nominal URDF + {what}" + (", reversals kept" if law[1] else ""), models["nominal model + friction fit"])
            shown.add(law)
        line(f"`hya identify`, {label}; λ = {weight}", models["identified model"])

if __name__ == "__main__":
    main()
