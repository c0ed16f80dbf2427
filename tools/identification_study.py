#!/usr/bin/env python3
"""Identification on the simulated HyA, from the command line a user has.

An exciting trajectory (`hya excite`) is tracked by the simulated arm (`hya track`, the
paper's controller, plant seed 3: parameters perturbed by up to 10 %, hydraulic actuators,
sensors with quantisation, noise and pressure offsets), and `hya identify` fits the log,
held against the plant's true rigid body (`--compare true.urdf`). The plant's friction is
varied, from the testbed's default (LuGre with Stribeck and a ±30 % position profile) down to
none, to show which part of the friction the identification's model cannot take; and the
filters' bandwidth varied on the same logs.

Then what the identified model and friction leave: a second trajectory (another excite seed)
on the same plant, `hya estimate` on its log with the nominal model, the identified one and
the identified one with its friction (RMS of d̂); and `hya track` of that trajectory with the
controller on each model (scenario keys `controller.model_urdf`, `controller.friction_toml`).

    cargo build --release -p hya-cli && tools/identification_study.py [path/to/hya]

Prints Markdown tables; everything is written under a temporary folder.
"""

import math
import os
import re
import subprocess
import sys
import tempfile

HYA = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "target", "release", "hya")
JOINTS = ["SAA", "SFE", "HR", "EFE", "WR", "WFE"]
PLANT_SEED = "3"
SETTLING_S = 2.0  # left out of every RMS: the estimator's and the loop's start
BANDWIDTHS = [25, 50, 100, 200]  # the filters' bandwidths compared, rad/s (50: the default)

# The plant's friction, most realistic first.
PLANTS = [
    ("LuGre, Stribeck, ±30 % position profile (the testbed's default)", ""),
    ("LuGre, Stribeck, no position profile", "coulomb_position_variation = 0.0\n"),
    ("smooth tanh, Stribeck, no position profile", 'friction = "smooth"\ncoulomb_position_variation = 0.0\n'),
    (
        "smooth tanh, no Stribeck, no position profile (the fit's own law)",
        'friction = "smooth"\ncoulomb_position_variation = 0.0\nstatic_nm = [5.0, 5.0, 3.0, 3.0, 2.0, 2.0]\n',
    ),
    ("none", 'friction = "off"\n'),
]


def hya(args, stdin=""):
    done = subprocess.run([HYA, *args], input=stdin, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"hya {' '.join(args)}: {done.stderr}")
    return done.stdout


def scenario(folder, name, plant="", controller=""):
    path = os.path.join(folder, f"{name}.toml")
    with open(path, "w") as f:
        f.write(f'name = "{name}"\ndescription = "identification study"\nduration_s = 1.0\nmethods = ["lu"]\n')
        f.write('[task]\nkind = "hold"\n')
        f.write(f"[controller]\n{controller}[plant]\n{plant}")
    return path


def rows(text):
    """The numeric rows of hya's output (its header line left out; cells comma- or blank-separated)."""
    return [[float(v) for v in line.replace(",", " ").split()]
            for line in text.splitlines() if line and line[0] in "-0123456789"]


def rms_columns(table, skip_s):
    kept = [r for r in table if r[0] >= skip_s]
    return [math.sqrt(sum(r[c] ** 2 for r in kept) / len(kept)) for c in range(1, len(kept[0]))]


def report_numbers(path):
    """Held-out RMS per joint (measured torque, then each model), the base parameters (nominal,
    identified, σ, true, deviation) and the prior weight λ."""
    text = open(path).read()
    held = [[float(x) for x in re.findall(r"\| ([-\d.]+)", line)] for line in text.splitlines()
            if any(line.startswith(f"| {j} | ") for j in JOINTS) and "±" not in line][:len(JOINTS)]
    # Base table cells: #, named after, nominal, identified, σ, (identified − nominal)/σ, compared,
    # (identified − compared)/σ.
    cells = [re.split(r"\s*\|\s*", line) for line in text.splitlines() if re.match(r"\| \d+ \| ", line)]
    base = [[float(c[k]) for k in (3, 4, 5, 7, 8)] for c in cells]
    weight = re.search(r"weight λ = (\S+):", text)
    return held, base, float(weight.group(1)) if weight else 0.0


def tracking_rms(log, reference):
    wanted = {round(r[0], 6): r[1:1 + len(JOINTS)] for r in rows(reference)}
    errors = [[q - w for q, w in zip(r[1:1 + len(JOINTS)], wanted[round(r[0], 6)])]
              for r in rows(log) if round(r[0], 6) in wanted and r[0] >= SETTLING_S]
    return [math.sqrt(sum(e[j] ** 2 for e in errors) / len(errors)) for j in range(len(JOINTS))]


def fmt(values, digits=3):
    return " / ".join(f"{v:.{digits}f}" for v in values)


def main():
    folder = tempfile.mkdtemp(prefix="hya-identification-")
    fit_reference = hya(["excite", "--robot", "hya", "--periods", "3", "--seed", "1"])
    test_reference = hya(["excite", "--robot", "hya", "--periods", "2", "--seed", "2"])
    print(f"Logs: 30 s of `hya excite --seed 1` fitted (the last quarter held out), plant seed {PLANT_SEED}; "
          f"`{HYA}`; files in {folder}.\n")
    print("| plant friction | `--prior-weight` | held-out RMS, nominal (N·m) | held-out RMS, identified (N·m) "
          "| ‖π_b − π_b,true‖ nominal | identified | largest deviation (σ) | λ |")
    print("|---|---|---|---|---|---|---|---|")
    identified = None
    logs = []
    for k, (label, plant) in enumerate(PLANTS):
        truth, out = os.path.join(folder, f"truth{k}"), os.path.join(folder, f"identified{k}")
        log = hya(["track", "--robot", "hya", "--seed", PLANT_SEED, "--scenario", scenario(folder, f"plant{k}", plant),
                   "--out", truth], fit_reference)
        logs.append((label, log, os.path.join(truth, "true.urdf")))
        for prior in ("0", "auto"):
            hya(["identify", "--robot", "hya", "--dt", "0.001", "--timestamps", "--compare",
                 os.path.join(truth, "true.urdf"), "--prior-weight", prior, "--out", out + prior], log)
            held, base, weight = report_numbers(os.path.join(out + prior, "report.md"))
            nominal_error = math.sqrt(sum((b[0] - b[3]) ** 2 for b in base))
            identified_error = math.sqrt(sum((b[1] - b[3]) ** 2 for b in base))
            largest = max(abs(b[4]) for b in base)
            print(f"| {label} | {prior} | {fmt(h[1] for h in held)} | {fmt(h[2] for h in held)} | {nominal_error:.3f} "
                  f"| {identified_error:.3f} | {largest:.1f} | {weight:g} |")
        if k == 0:
            identified = out

    print("\nThe filters' bandwidth (`--bandwidth-rad-s`, the regressor's q̂, q̂̇, q̂̈ and the torque "
          "alike; `--prior-weight 0`) on the same logs, and the default bandwidth with every joint's rows near its "
          "reversals fitted too (`--keep-reversals`): the parameters' distance from the truth and the largest "
          "deviation in σ:\n")
    variants = [(b, [], f"ω = {b} rad/s") for b in BANDWIDTHS] + [(50, ["--keep-reversals"], "ω = 50, reversals kept")]
    print("| plant friction | " + " | ".join(name for _, _, name in variants) + " |")
    print("|---|" + "---|" * len(variants))
    for label, log, truth in logs:
        cells = []
        for bandwidth, extra, _ in variants:
            out = os.path.join(folder, f"bandwidth{bandwidth}-{len(cells)}-{hash(label) & 0xffff}")
            hya(["identify", "--robot", "hya", "--dt", "0.001", "--timestamps", "--compare", truth,
                 "--bandwidth-rad-s", str(bandwidth), "--out", out, *extra], log)
            _, base, _ = report_numbers(os.path.join(out, "report.md"))
            distance = math.sqrt(sum((b[1] - b[3]) ** 2 for b in base))
            cells.append(f"{distance:.3f}, {max(abs(b[4]) for b in base):.1f} σ")
        print(f"| {label} | " + " | ".join(cells) + " |")

    print("\nOn a second trajectory (`hya excite --seed 2`, 20 s) of the default plant, the first "
          f"{SETTLING_S:.0f} s left out, per joint {', '.join(JOINTS)}:\n")
    models = [("nominal", None, None)]
    files = {prior: [os.path.join(identified + prior, name) for name in ("identified.urdf", "friction.toml")]
             for prior in ("0", "auto")}
    for prior, (urdf, friction) in files.items():
        models += [(f"identified rigid body (`--prior-weight {prior}`)", urdf, None),
                   (f"identified rigid body and friction (`--prior-weight {prior}`)", urdf, friction)]
    # The two models' files swapped: which of them, bodies or friction, the loop answers to.
    models += [("rigid body of `0`, friction of `auto`", files["0"][0], files["auto"][1]),
               ("rigid body of `auto`, friction of `0`", files["auto"][0], files["0"][1])]
    log = hya(["track", "--robot", "hya", "--seed", PLANT_SEED, "--scenario", scenario(folder, "default")],
              test_reference)
    print("| model | RMS of d̂ on the nominal controller's log (N·m) | tracking RMS, `lu` on this model (mrad) "
          "| tracking RMS, `none` on this model (mrad) |")
    print("|---|---|---|---|")
    for k, (label, urdf, friction) in enumerate(models):
        args = ["estimate", "--robot", urdf or "hya", "--timestamps"] + (["--friction", friction] if friction else [])
        controller = (f'model_urdf = "{urdf}"\n' if urdf else "") + (f'friction_toml = "{friction}"\n' if friction else "")
        d_hat = rms_columns(rows(hya(args, log)), SETTLING_S)
        path = scenario(folder, f"controller{k}", controller=controller)
        tracked = [tracking_rms(hya(["track", "--robot", "hya", "--seed", PLANT_SEED, "--scenario", path,
                                     "--method", method], test_reference), test_reference)
                   for method in ["lu", "none"]]
        print(f"| {label} | {fmt(d_hat, 2)} | {fmt((1e3 * e for e in tracked[0]), 1)} "
              f"| {fmt((1e3 * e for e in tracked[1]), 1)} |")


if __name__ == "__main__":
    main()
