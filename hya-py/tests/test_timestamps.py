"""DisturbanceEstimator over samples with their own times: the jittered planar2 log with gaps
against its NumPy/SciPy reference (tools/timestamped_estimate_reference.py), stepping against a
whole run, and bad times refused."""
import numpy as np
import pytest

import hya
from conftest import ROOT

CLI_DATA = ROOT / "hya-cli" / "tests" / "data"


def jittered_log():
    """Columns t, q1, q2, qd1, qd2, tau1, tau2 of the log, and the reference rows t, d̂1, d̂2."""
    log = np.loadtxt(CLI_DATA / "timestamped_planar2_log.csv", delimiter=",", comments="#", skiprows=2)
    reference = np.loadtxt(CLI_DATA / "timestamped_planar2_estimate.csv")
    return log[:, 0], log[:, 1:3], log[:, 5:7], reference


def started(t, q, tau):
    return hya.DisturbanceEstimator(hya.Model.builtin("planar2"), q0=q[0], tau0=tau[0], t0=t[0])


def test_a_jittered_log_with_gaps_matches_the_scipy_reference():
    t, q, tau, reference = jittered_log()
    estimator = started(t, q, tau)
    d_hat = np.vstack([estimator.disturbance, estimator.run(q[1:], tau[1:], t=t[1:])])
    assert d_hat.shape == (110, 2)
    assert np.abs(d_hat - reference[:, 1:]).max() < 1e-9


def test_stepping_with_times_equals_running_with_them():
    t, q, tau, _ = jittered_log()
    stepped, whole = started(t, q, tau), started(t, q, tau)
    by_step = np.array([stepped.update(q[k], tau[k], t=t[k]) for k in range(1, len(t))])
    assert np.array_equal(by_step, whole.run(q[1:], tau[1:], t=t[1:]))


def test_bad_times_are_refused_and_change_nothing():
    t, q, tau, _ = jittered_log()
    estimator = started(t, q, tau)
    estimator.update(q[1], tau[1], t=t[1])
    before = estimator.disturbance
    with pytest.raises(ValueError, match="t"):
        estimator.update(q[2], tau[2], t=t[1])
    with pytest.raises(ValueError, match="3 times, but q_log has 2 rows"):
        estimator.run(q[2:4], tau[2:4], t=t[2:5])
    with pytest.raises(ValueError, match="every sample needs its time"):
        estimator.update(q[2], tau[2])
    plain = hya.DisturbanceEstimator(hya.Model.builtin("planar2"), q0=q[0], tau0=tau[0])
    with pytest.raises(ValueError, match="t0"):
        plain.run(q[1:3], tau[1:3], t=t[1:3])
    assert before == estimator.disturbance, "nothing above changed the estimator"
    estimator.update(q[2], tau[2], t=t[2])
    assert before != estimator.disturbance
    # A log stops at its first bad row, which it names.
    with pytest.raises(ValueError, match="row 1"):
        estimator.run(q[3:5], tau[3:5], t=[t[3], t[3]])
