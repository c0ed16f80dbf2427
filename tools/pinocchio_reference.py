#!/usr/bin/env python3
"""Reference vectors from Pinocchio, an independent rigid-body dynamics implementation.

For each URDF given (default: every shipped robot), draws seeded random states and writes
`<out>/<robot>.csv`: one row per state and quantity,

    kind, q..., qd..., qdd..., value...

(q holds joint positions, one per degree of freedom, in Pinocchio's joint order) with kind `id` (value = rnea(q, qd, qdd)), `mass` (value = crba(q), full, row-major),
`gravity` (value = computeGeneralizedGravity(q)), `aba` (the third block holds a torque tau,
value = aba(q, qd, tau)), `id_dq` and `id_dqd` (value = dtau/dq and dtau/dqd from
computeRNEADerivatives(q, qd, qdd), row-major: row i is dtau_i); qd and qdd are zeros where
unused. The torques of `aba` rows come from a second generator (seed + 1000), so the other rows
do not depend on them. Gravity is
Pinocchio's default, 9.81 m/s^2 along -z. Numbers are printed with repr() so they round-trip.

Usage: tools/pinocchio_reference.sh [URDF...]  (installs `pin` into a virtualenv first)
"""
import argparse
import csv
from pathlib import Path

import numpy as np
import pinocchio as pin

ROOT = Path(__file__).resolve().parent.parent
STATES = 8


def configuration(model, angles):
    """Pinocchio's configuration for joint positions: (cos, sin) for continuous joints."""
    q = pin.neutral(model)
    for joint in model.joints[1:]:
        value = angles[joint.idx_v]
        if joint.nq == 2:
            q[joint.idx_q : joint.idx_q + 2] = [np.cos(value), np.sin(value)]
        else:
            q[joint.idx_q] = value
    return q


def reference_rows(urdf: Path, seed: int):
    model = pin.buildModelFromUrdf(str(urdf))
    data = model.createData()
    rng = np.random.default_rng(seed)
    torques = np.random.default_rng(seed + 1000)
    n = model.nv
    zeros = np.zeros(n)
    for _ in range(STATES):
        q = rng.uniform(-np.pi, np.pi, n)
        qd = rng.uniform(-2.0, 2.0, n)
        qdd = rng.uniform(-5.0, 5.0, n)
        config = configuration(model, q)
        yield ["id", *q, *qd, *qdd, *pin.rnea(model, data, config, qd, qdd)]
        mass = pin.crba(model, data, config)
        mass = np.triu(mass) + np.triu(mass, 1).T  # crba fills the upper triangle
        yield ["mass", *q, *zeros, *zeros, *mass.reshape(-1)]
        yield ["gravity", *q, *zeros, *zeros, *pin.computeGeneralizedGravity(model, data, config)]
        tau = torques.uniform(-20.0, 20.0, n)
        yield ["aba", *q, *qd, *tau, *pin.aba(model, data, config, qd, tau)]
        d_dq, d_dqd, _ = pin.computeRNEADerivatives(model, data, config, qd, qdd)
        yield ["id_dq", *q, *qd, *qdd, *np.asarray(d_dq).reshape(-1)]
        yield ["id_dqd", *q, *qd, *qdd, *np.asarray(d_dqd).reshape(-1)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("urdf", nargs="*", type=Path)
    parser.add_argument("--out", type=Path, default=ROOT / "tests" / "reference")
    args = parser.parse_args()
    urdfs = args.urdf or sorted((ROOT / "robots" / "urdf").glob("*.urdf"))
    args.out.mkdir(parents=True, exist_ok=True)
    for index, urdf in enumerate(urdfs):
        path = args.out / f"{urdf.stem}.csv"
        with path.open("w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow([f"# pinocchio {pin.__version__}, {urdf.name}, seed {index}"])
            for row in reference_rows(urdf, seed=index):
                writer.writerow([row[0], *map(repr, map(float, row[1:]))])
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
