#!/usr/bin/env python3
"""Reference for `hya estimate --timestamps`: a jittered log of planar2 and its d̂, from NumPy/SciPy.

Writes hya-cli/tests/data/timestamped_planar2_log.csv (header `t,q1,q2,qd1,qd2,tau1,tau2`,
comma-separated: the velocities are there for `--columns` to skip) and
timestamped_planar2_estimate.csv (rows `t d̂1 d̂2`), which hya-cli/tests/cli/timestamps.rs compares
with hya to 1e-9. Independent of hya's code: the arm's inverse dynamics in closed form from
robots/urdf/planar2.urdf's figures, each step's first-order-hold discretisation from
scipy.linalg.expm of the augmented matrix

    exp([[A T, B T, 0], [0, 0, 1], [0, 0, 0]]) = [[Φ, Γa, Γb], [0, 1, 1], [0, 0, 1]]
    x_{k+1} = Φ x_k + (Γa − Γb) u_k + Γb u_{k+1}

for the paper's filter (ζ = 0.8, ω1 = ω2 = 50 rad/s), and hya's documented rule for gaps: a step
longer than 100 / max(ω1, ω2) = 2 s restarts the estimator at rest, shorter ones are bridged.

The log: the arm follows smooth sinusoids under a known disturbance d(t), τ = ID(q, q̇, q̈) − d,
sampled at a 100 Hz controller's times: steps drawn from 10 to 16 ms, one in twelve a 30 to 45 ms
gap, one 2.5 s gap (a restart), times rounded to the microsecond as a logger prints them.

Run: python3 tools/timestamped_estimate_reference.py  (numpy, scipy)
"""

import os

import numpy as np
from scipy.linalg import expm

G = 9.81  # hya's STANDARD_GRAVITY
M1, M2, L1, C1, C2, I1, I2 = 3.0, 2.0, 0.5, 0.25, 0.2, 0.06, 0.03  # planar2.urdf
ZETA, OMEGA1, OMEGA2 = 0.8, 50.0, 50.0
LONGEST_BRIDGE_S = 100.0 / max(OMEGA1, OMEGA2)

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "hya-cli", "tests", "data")


def inverse_dynamics(q, qd, qdd):
    """τ = M(q) q̈ + C(q, q̇) + G(q) of a two-link arm swinging about y (z up, gravity −z)."""
    q1, q2 = q
    h = M2 * L1 * C2 * np.sin(q2)
    m12 = I2 + M2 * (C2**2 + L1 * C2 * np.cos(q2))
    m = np.array([[I1 + I2 + M1 * C1**2 + M2 * (L1**2 + C2**2 + 2 * L1 * C2 * np.cos(q2)), m12], [m12, I2 + M2 * C2**2]])
    c = np.array([-h * (2 * qd[0] * qd[1] + qd[1] ** 2), h * qd[0] ** 2])
    g = -G * np.array([(M1 * C1 + M2 * L1) * np.cos(q1) + M2 * C2 * np.cos(q1 + q2), M2 * C2 * np.cos(q1 + q2)])
    return m @ qdd + c + g


def trajectory(t):
    """q, q̇, q̈ and the disturbance d at time t."""
    a1, f1, a2, f2 = 0.3, 0.5, 0.4, 0.8
    w1, w2 = 2 * np.pi * f1, 2 * np.pi * f2
    q = np.array([-0.5 + a1 * np.sin(w1 * t), 0.8 + a2 * np.sin(w2 * t + 0.3)])
    qd = np.array([a1 * w1 * np.cos(w1 * t), a2 * w2 * np.cos(w2 * t + 0.3)])
    qdd = np.array([-a1 * w1**2 * np.sin(w1 * t), -a2 * w2**2 * np.sin(w2 * t + 0.3)])
    d = np.array([2.0 * np.sin(2 * np.pi * 0.3 * t), -1.0 + 0.5 * np.cos(2 * np.pi * 1.1 * t)])
    return q, qd, qdd, d


def times(rng):
    t, out = 0.25, [0.25]
    while t < 4.5:
        step = rng.uniform(0.030, 0.045) if rng.random() < 1 / 12 else rng.uniform(0.010, 0.016)
        if len(out) == 80:
            step = 2.5
        t = round(t + step, 6)
        out.append(t)
    return out


def foh(step_s):
    """Φ, γ_now = Γa − Γb, γ_next = Γb over one step."""
    a = np.array(
        [[0, 1, 0], [0, 0, 1], [-OMEGA1 * OMEGA2**2, -(OMEGA2**2 + 2 * ZETA * OMEGA1 * OMEGA2), -(OMEGA1 + 2 * ZETA * OMEGA2)]]
    )
    b = np.array([0, 0, OMEGA1 * OMEGA2**2])
    aug = np.zeros((5, 5))
    aug[:3, :3] = a * step_s
    aug[:3, 3] = b * step_s
    aug[3, 4] = 1.0
    e = expm(aug)
    return e[:3, :3], e[:3, 3] - e[:3, 4], e[:3, 4]


def estimate(log):
    """Rows (t, d̂) of the estimator over rows (t, q, τ)."""
    out = []
    xq = xt = None
    for k, (t, q, tau) in enumerate(log):
        if k > 0 and t - log[k - 1][0] <= LONGEST_BRIDGE_S:
            phi, now, nxt = foh(t - log[k - 1][0])
            xq = phi @ xq + np.outer(now, log[k - 1][1]) + np.outer(nxt, q)
            xt = phi @ xt + np.outer(now, log[k - 1][2]) + np.outer(nxt, tau)
        else:  # first row or a restart: at rest
            xq = np.vstack([q, np.zeros(2), np.zeros(2)])
            xt = np.vstack([tau, np.zeros(2), np.zeros(2)])
        out.append((t, inverse_dynamics(xq[0], xq[1], xq[2]) - xt[0]))
    return out


def main():
    rng = np.random.default_rng(22)
    log, lines = [], ["# planar2 under a known disturbance, 100 Hz jittered, gaps; tools/timestamped_estimate_reference.py"]
    lines.append("t,q1,q2,qd1,qd2,tau1,tau2")
    for t in times(rng):
        q, qd, qdd, d = trajectory(t)
        tau = inverse_dynamics(q, qd, qdd) - d
        fields = [t, *q, *qd, *tau]
        text = ",".join(repr(float(v)) for v in fields)
        lines.append(text)
        parsed = [float(v) for v in text.split(",")]
        log.append((parsed[0], np.array(parsed[1:3]), np.array(parsed[5:7])))
    with open(os.path.join(OUT, "timestamped_planar2_log.csv"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(OUT, "timestamped_planar2_estimate.csv"), "w") as f:
        f.write("# t d1 d2 from tools/timestamped_estimate_reference.py (scipy.linalg.expm per step)\n")
        for t, d_hat in estimate(log):
            f.write(" ".join(repr(float(v)) for v in (t, *d_hat)) + "\n")
    print(f"{len(log)} rows")


if __name__ == "__main__":
    main()
