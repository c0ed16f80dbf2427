#!/usr/bin/env python3
"""Frame kinematics and forward-dynamics derivatives from Pinocchio, for the Rust tests.

For each URDF given (default: every shipped robot and the loader's messy tree and slider arm, held out), draws seeded
random states and writes `<out>/<robot>.csv`, one row per state and quantity:

    jacobian, FRAME, q..., J...          J = getFrameJacobian(LOCAL_WORLD_ALIGNED), 6 x n row-major
                                         (linear rows, then angular)
    bias, FRAME, q..., qd..., a...       a = getFrameClassicalAcceleration(LOCAL_WORLD_ALIGNED) after
                                         forwardKinematics(q, qd, 0): J̇ q̇, linear then angular
    fd_derivatives, -, q..., qd..., tau..., dqdd_dq..., dqdd_dqd..., Minv...
                                         computeABADerivatives(q, qd, tau), each n x n row-major

for every link of the URDF (a link behind a fixed joint included). Numbers are printed with repr()
so they round-trip.

Usage: tools/pinocchio_reference.sh (installs `pin` into a virtualenv first), or
       python3 tools/kinematics_reference.py [URDF...] with `pin` installed.
"""
import argparse
import csv
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin

from pinocchio_reference import configuration

ROOT = Path(__file__).resolve().parent.parent
STATES = 4


def links(urdf: Path):
    return [link.get("name") for link in ET.parse(urdf).getroot().iter("link")]


def reference_rows(urdf: Path, seed: int):
    model = pin.buildModelFromUrdf(str(urdf))
    data = model.createData()
    rng = np.random.default_rng(seed)
    n = model.nv
    names = links(urdf)
    for _ in range(STATES):
        q = rng.uniform(-np.pi, np.pi, n)
        qd = rng.uniform(-2.0, 2.0, n)
        tau = rng.uniform(-20.0, 20.0, n)
        config = configuration(model, q)
        pin.computeJointJacobians(model, data, config)
        pin.updateFramePlacements(model, data)
        for name in names:
            frame = model.getFrameId(name, pin.BODY)
            jacobian = pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
            yield ["jacobian", name, *q, *jacobian.reshape(-1)]
        pin.forwardKinematics(model, data, config, qd, np.zeros(n))
        pin.updateFramePlacements(model, data)
        for name in names:
            frame = model.getFrameId(name, pin.BODY)
            bias = pin.getFrameClassicalAcceleration(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
            yield ["bias", name, *q, *qd, *bias.linear, *bias.angular]
        by_q, by_qd, inverse = pin.computeABADerivatives(model, data, config, qd, tau)
        inverse = np.triu(inverse) + np.triu(inverse, 1).T  # the upper triangle is filled
        rows = [np.asarray(m).reshape(-1) for m in (by_q, by_qd, inverse)]
        yield ["fd_derivatives", "-", *q, *qd, *tau, *np.concatenate(rows)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("urdf", nargs="*", type=Path)
    parser.add_argument("--out", type=Path, default=ROOT / "tests" / "reference" / "kinematics")
    args = parser.parse_args()
    urdfs = args.urdf or [
        *sorted((ROOT / "robots" / "urdf").glob("*.urdf")),
        ROOT / "hya-urdf" / "tests" / "urdf" / "messy_tree.urdf",
        ROOT / "hya-urdf" / "tests" / "urdf" / "slider_arm.urdf",
    ]
    args.out.mkdir(parents=True, exist_ok=True)
    for index, urdf in enumerate(urdfs):
        path = args.out / f"{urdf.stem}.csv"
        with path.open("w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow([f"# pinocchio {pin.__version__}, {urdf.name}, seed {100 + index}"])
            for row in reference_rows(urdf, seed=100 + index):
                writer.writerow([row[0], row[1], *map(repr, map(float, row[2:]))])
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
