#!/usr/bin/env python3
"""Joint-torque regressor rows from Pinocchio, an independent implementation.

For each URDF given (default: every shipped robot and the loader's messy test tree), draws
seeded random states and writes `<out>/<robot>.csv`, one row per state:

    q..., qd..., qdd..., Y...

with Y = computeJointTorqueRegressor(q, qd, qdd), n x 10 n, row-major; the columns of joint j
are its body's parameters in Pinocchio's order (m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy,
I_xz, I_yz, I_zz), the rotational inertia about the joint frame's origin. Gravity is
Pinocchio's default, 9.81 m/s^2 along -z. Numbers are printed with repr() so they round-trip.

Usage: tools/pinocchio_reference.sh (installs `pin` into a virtualenv, then runs this script
with the default URDFs), or tools/.venv/bin/python tools/regressor_reference.py [URDF...]
"""
import argparse
import csv
from pathlib import Path

import numpy as np
import pinocchio as pin

from pinocchio_reference import configuration

ROOT = Path(__file__).resolve().parent.parent
STATES = 4


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("urdf", nargs="*", type=Path)
    parser.add_argument("--out", type=Path, default=ROOT / "tests" / "reference" / "regressor")
    args = parser.parse_args()
    urdfs = args.urdf or [
        *sorted((ROOT / "robots" / "urdf").glob("*.urdf")),
        ROOT / "hya-urdf" / "tests" / "urdf" / "messy_tree.urdf",
        ROOT / "examples" / "own_arm" / "urdf" / "own_arm.urdf",
    ]
    args.out.mkdir(parents=True, exist_ok=True)
    for index, urdf in enumerate(urdfs):
        model = pin.buildModelFromUrdf(str(urdf))
        data = model.createData()
        rng = np.random.default_rng(100 + index)
        n = model.nv
        path = args.out / f"{urdf.stem}.csv"
        with path.open("w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow([f"# pinocchio {pin.__version__}, {urdf.name}, seed {100 + index}"])
            for _ in range(STATES):
                q = rng.uniform(-np.pi, np.pi, n)
                qd = rng.uniform(-2.0, 2.0, n)
                qdd = rng.uniform(-5.0, 5.0, n)
                y = pin.computeJointTorqueRegressor(model, data, configuration(model, q), qd, qdd)
                writer.writerow(map(repr, map(float, [*q, *qd, *qdd, *np.asarray(y).reshape(-1)])))
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
