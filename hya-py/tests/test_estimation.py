"""The estimator, observers, filter and controller: a log run in one call equals stepping it,
the estimator follows a disturbance it is shown, and bad input is refused without harm."""
from pathlib import Path

import numpy as np
import pytest

import hya


def log(model, rng, ticks=400):
    """A smooth joint-angle log about HyA's home and torques with a known offset."""
    t = np.arange(ticks) * 1e-3
    home = np.array([0.0, 0.0, -0.78, 0.78, 0.78, 0.0])
    q = home + 0.05 * np.sin(2 * np.pi * np.outer(t, [0.5, 0.7, 0.9, 1.1, 1.3, 1.5]))
    tau = model.gravity(q) + rng.normal(0.0, 0.01, q.shape)
    qd = np.gradient(q, 1e-3, axis=0)
    return q, qd, tau


OBSERVERS = [
    ("lu", lambda m, q0, qd0, tau0: hya.DisturbanceEstimator(m, q0=q0, tau0=tau0), False),
    ("momentum", lambda m, q0, qd0, tau0: hya.MomentumObserver(m, q0=q0, qd0=qd0, tau0=tau0), True),
    ("chen", lambda m, q0, qd0, tau0: hya.NonlinearDisturbanceObserver(m, q0=q0, qd0=qd0, tau0=tau0), True),
    ("eso", lambda m, q0, qd0, tau0: hya.ExtendedStateObserver(m, q0=q0, qd0=qd0, tau0=tau0), False),
]


@pytest.mark.parametrize("name,make,velocity", OBSERVERS, ids=[o[0] for o in OBSERVERS])
def test_running_a_log_equals_stepping_it(name, make, velocity, rng):
    model = hya.Model.builtin("hya")
    q, qd, tau = log(model, rng)
    stepped, whole = make(model, q[0], qd[0], tau[0]), make(model, q[0], qd[0], tau[0])
    by_step = np.array([stepped.update(q[k], tau[k], *((qd[k],) if velocity else ())) for k in range(len(q))])
    at_once = whole.run(q, tau, *((qd,) if velocity else ()))
    assert at_once.shape == q.shape
    assert np.array_equal(by_step, at_once), name
    assert np.array_equal(np.array(whole.disturbance), at_once[-1])


def test_the_estimator_follows_a_constant_disturbance_through_its_filter():
    # A held arm whose measured torque falls short of gravity by a constant δ: d = G − τ = δ.
    model = hya.Model.builtin("hya")
    q0 = np.array([0.0, 0.0, -0.78, 0.78, 0.78, 0.0])
    delta = np.array([3.0, -2.0, 1.0, 0.5, -0.25, 0.1])
    estimator = hya.DisturbanceEstimator(model, q0=q0)
    ticks = 500
    d_hat = estimator.run(np.tile(q0, (ticks, 1)), np.tile(model.gravity(q0) - delta, (ticks, 1)))
    # The unit step response of the paper's filter at 0.5 s is within 1e-6 of one.
    np.testing.assert_allclose(d_hat[-1], delta, rtol=0, atol=1e-5)
    assert np.all(np.abs(d_hat[5]) < np.abs(delta) * 0.1)  # and it gets there through the filter


def test_the_filter_reproduces_a_ramp_and_its_derivatives():
    f = hya.ThirdOrderFilter([0.0, 1.0], dt=1e-3)
    for k in range(1, 2001):
        x, xd, xdd = f.step([0.5 * k * 1e-3, 1.0])
    # Past the transient a ramp of slope 0.5 comes out delayed by the group delay, slope intact.
    assert abs(xd[0] - 0.5) < 1e-9 and abs(xdd[0]) < 1e-9
    assert x[1] == pytest.approx(1.0, abs=1e-9) and xd[1] == pytest.approx(0.0, abs=1e-9)


def test_bad_input_is_refused_and_changes_nothing():
    model = hya.Model.builtin("hya")
    q0 = np.array([0.0, 0.0, -0.78, 0.78, 0.78, 0.0])
    estimator = hya.DisturbanceEstimator(model, q0=q0)
    before = list(estimator.disturbance)
    with pytest.raises(ValueError, match="tau"):
        estimator.update(q0, [np.nan] * 6)
    with pytest.raises(ValueError, match=r"q: shape \[5\]"):
        estimator.update(q0[:5], np.zeros(6))
    assert list(estimator.disturbance) == before
    with pytest.raises(ValueError, match="qd"):
        hya.MomentumObserver(model, q0=q0).update(q0, np.zeros(6))
    with pytest.raises(ValueError, match="zeta"):
        hya.DisturbanceEstimator(model, zeta=-1.0)
    # The limits `hya filter` and the C ABI refuse too (hya-core's FilterParams).
    with pytest.raises(ValueError, match="zeta.*0.001"):
        hya.ThirdOrderFilter([0.0], zeta=1e-4)
    with pytest.raises(ValueError, match="at least 1e-6"):
        hya.ThirdOrderFilter([0.0], omega1=0.5, dt=1e-6)
    with pytest.raises(ValueError, match="u: 1 values, expected 2"):
        hya.ThirdOrderFilter([0.0, 0.0]).step([1.0])


class Spoiler:
    """An array-like whose conversion writes NaN into another argument, read before it."""

    def __init__(self, victim, at, value):
        self.victim, self.at, self.value = victim, at, value

    def __array__(self, dtype=None, copy=None):
        self.victim[self.at] = np.nan
        return self.value


def test_an_argument_written_while_a_later_one_converts_is_refused():
    # Every argument is converted before any is checked, in single steps and in logs alike.
    model = hya.Model.builtin("hya")
    q0 = np.array([0.0, 0.0, -0.78, 0.78, 0.78, 0.0])
    estimator = hya.MomentumObserver(model, q0=q0)
    q = q0.copy()
    with pytest.raises(ValueError, match=r"q\[3\] = NaN: not finite"):
        estimator.update(q, model.gravity(q0), qd=Spoiler(q, 3, np.zeros(6)))
    q_log = np.tile(q0, (4, 1))
    with pytest.raises(ValueError, match=r"q_log\[2, 3\] = NaN: not finite"):
        estimator.run(q_log, np.tile(model.gravity(q0), (4, 1)), Spoiler(q_log, (2, 3), np.zeros((4, 6))))


def test_computed_torque_cancels_the_estimate():
    model = hya.Model.builtin("hya")
    q = np.array([0.1, -0.2, -0.7, 0.8, 0.7, 0.1])
    controller = hya.ComputedTorque(model, kp=[100.0] * 6, kd=[10.0] * 6)
    d_hat = [1.0, -2.0, 0.5, 0.0, 0.25, -0.1]
    without = np.array(controller.command(q, np.zeros(6), q))
    with_estimate = np.array(controller.command(q, np.zeros(6), q, d_hat=d_hat))
    # On the reference, at rest: gravity, then gravity minus d̂.
    np.testing.assert_allclose(without, model.gravity(q), rtol=0, atol=1e-12)
    np.testing.assert_allclose(with_estimate, model.gravity(q) - d_hat, rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="kd: 5 values, expected 6"):
        hya.ComputedTorque(model, kp=[1.0] * 6, kd=[1.0] * 5)


def test_help_shows_the_papers_equation_and_defaults():
    import inspect

    doc = hya.DisturbanceEstimator.__doc__
    assert "d̂ = ID(q̂, q̂̇, q̂̈) − τ̂" in doc and "ω1 ω2²" in doc
    defaults = {k: p.default for k, p in inspect.signature(hya.DisturbanceEstimator).parameters.items()}
    # The paper's filter: ζ = 0.8, ω1 = ω2 = 50 rad/s, at HyA's 1 kHz control rate.
    assert (defaults["zeta"], defaults["omega1"], defaults["omega2"], defaults["dt"]) == (0.8, 50.0, 50.0, 0.001)
    for observer in (hya.MomentumObserver, hya.NonlinearDisturbanceObserver, hya.ExtendedStateObserver):
        assert inspect.signature(observer).parameters["bandwidth"].default == 50.0


def test_a_urdf_model_is_used_as_loaded_not_reloaded_from_its_path(tmp_path, monkeypatch):
    from conftest import DATA

    monkeypatch.chdir(DATA)
    model = hya.Model.from_urdf("branched_wrist.urdf")  # a relative path
    monkeypatch.chdir(tmp_path)  # where that path leads nowhere
    q0 = np.array([0.1, -0.2, 0.3])
    estimator = hya.DisturbanceEstimator(model, q0=q0)
    np.testing.assert_allclose(estimator.disturbance, np.zeros(3), atol=1e-12)
    controller = hya.ComputedTorque(model, kp=[1.0] * 3, kd=[1.0] * 3)
    np.testing.assert_allclose(controller.command(q0, np.zeros(3), q0), model.gravity(q0), atol=1e-12)


def test_an_identified_friction_file_adds_its_joint_law_at_the_filtered_motion(tmp_path, rng):
    # d̂ with the file minus d̂ without it is τ_f(q̂̇) + I_a q̂̈, the filter's own q̂̇ and q̂̈ (the
    # paper's filter on q, started at rest at q0, as the estimator's is).
    model = hya.Model.builtin("hya")
    q, _, tau = log(model, rng)
    coulomb, viscous, offset, armature = [1.5, 1.2, 0.8, 0.6, 0.3, 0.2], [0.5] * 6, [0.1] * 6, [0.02] * 6
    friction = tmp_path / "friction.toml"
    friction.write_text(
        "smoothing_rad_s = 0.05\n"
        f"coulomb_nm = {coulomb}\nviscous_nm_s = {viscous}\noffset_nm = {offset}\narmature_kg_m2 = {armature}\n"
    )
    rigid = hya.DisturbanceEstimator(model, q0=q[0], tau0=tau[0]).run(q, tau)
    with_law = hya.DisturbanceEstimator(model, q0=q[0], tau0=tau[0], friction=str(friction)).run(q, tau)
    filt = hya.ThirdOrderFilter(list(q[0]))
    # The estimator filters each row before it forms d̂: the state after row k.
    states = [filt.step(list(qk)) for qk in q]
    qd_hat = np.array([filt_state[1] for filt_state in states])
    qdd_hat = np.array([filt_state[2] for filt_state in states])
    law = (np.array(coulomb) * np.tanh(qd_hat / 0.05) + np.array(viscous) * qd_hat + np.array(offset)
           + np.array(armature) * qdd_hat)
    np.testing.assert_allclose(with_law - rigid, law, rtol=0, atol=1e-9)
    with pytest.raises(ValueError, match="friction"):
        hya.DisturbanceEstimator(model, friction=str(tmp_path / "missing.toml"))
    controller = hya.ComputedTorque(model, [100.0] * 6, [20.0] * 6, friction=str(friction))
    plain = hya.ComputedTorque(model, [100.0] * 6, [20.0] * 6)
    qd = [0.1] * 6
    added = np.array(controller.command(list(q[0]), qd, list(q[0]))) - np.array(plain.command(list(q[0]), qd, list(q[0])))
    np.testing.assert_allclose(added, np.array(coulomb) * np.tanh(0.1 / 0.05) + 0.5 * 0.1 + 0.1, rtol=0, atol=1e-12)


REFUSED_FRICTION = Path(__file__).resolve().parents[2] / "hya-ident" / "tests" / "friction" / "refused"


@pytest.mark.parametrize("path", sorted(REFUSED_FRICTION.glob("*.toml")), ids=lambda p: p.name)
def test_bad_friction_files_are_refused_as_the_library_refuses_them(path):
    # hya-ident's corpus, for a 2-joint arm: each file's first line lists the words its message
    # must hold; the CLI and the C ABI are held to the same files.
    words = [path.name] + path.read_text().splitlines()[0].removeprefix("# expect: ").split(" | ")
    model = hya.Model.builtin("planar2")
    for make in (lambda: hya.DisturbanceEstimator(model, friction=str(path)),
                 lambda: hya.ComputedTorque(model, [1.0] * 2, [1.0] * 2, friction=str(path))):
        with pytest.raises(ValueError) as refused:
            make()
        for word in words:
            assert word in str(refused.value), f"{refused.value!s} lacks {word!r}"


def test_the_refused_friction_corpus_is_there():
    assert len(list(REFUSED_FRICTION.glob("*.toml"))) >= 9
