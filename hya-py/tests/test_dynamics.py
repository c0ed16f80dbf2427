"""hya.Model against Pinocchio (an independent implementation) on every shipped arm and on a
URDF only these tests hold; batches against single calls; errors on bad input."""
import gc
import sys
import threading
import time

import numpy as np
import pinocchio as pin
import pytest

import hya
from conftest import DATA, urdf_path

ARMS = hya.Model.builtin_names()
TOL = 1e-9


def pinocchio_model(path):
    model = pin.buildModelFromUrdf(str(path))
    return model, model.createData()


def models():
    """(label, hya model, URDF path): generated and run-time paths of each shipped arm, and the
    tests' own URDF."""
    for name in ARMS:
        yield f"{name}-generated", hya.Model.builtin(name), urdf_path(name)
        yield f"{name}-urdf", hya.Model.from_urdf(str(urdf_path(name))), urdf_path(name)
    yield "branched_wrist", hya.Model.from_urdf(str(DATA / "branched_wrist.urdf")), DATA / "branched_wrist.urdf"


@pytest.mark.parametrize("label,model,path", list(models()), ids=lambda x: x if isinstance(x, str) else "")
def test_agrees_with_pinocchio(label, model, path, rng):
    pm, pd = pinocchio_model(path)
    assert list(pm.names)[1:] == model.joint_names, label
    for _ in range(8):
        q, qd, qdd = (rng.uniform(-1.5, 1.5, model.dof) for _ in range(3))
        np.testing.assert_allclose(model.inverse_dynamics(q, qd, qdd), pin.rnea(pm, pd, q, qd, qdd), rtol=0, atol=TOL)
        np.testing.assert_allclose(model.gravity(q), pin.computeGeneralizedGravity(pm, pd, q), rtol=0, atol=TOL)
        mass = pin.crba(pm, pd, q)
        mass = np.triu(mass) + np.triu(mass, 1).T
        np.testing.assert_allclose(model.mass_matrix(q), mass, rtol=0, atol=TOL)
        tau = rng.uniform(-5, 5, model.dof)
        np.testing.assert_allclose(model.forward_dynamics(q, qd, tau), pin.aba(pm, pd, q, qd, tau), rtol=1e-9, atol=TOL)
        pin.framesForwardKinematics(pm, pd, q)
        compared = [frame for frame in model.frame_names if pm.existFrame(frame)]
        assert len(compared) == len(model.frame_names), f"{label}: Pinocchio lacks frames"
        for frame in compared:
            pose = model.frame_pose(q, frame)
            reference = pd.oMf[pm.getFrameId(frame)].homogeneous
            np.testing.assert_allclose(pose, reference, rtol=0, atol=1e-12, err_msg=f"{label}: frame {frame}")
        pin.computeJointJacobians(pm, pd, q)
        pin.forwardKinematics(pm, pd, q, qd, np.zeros(model.dof))
        pin.updateFramePlacements(pm, pd)
        for frame in compared:
            fid = pm.getFrameId(frame)
            for local, reference_frame in ((False, pin.LOCAL_WORLD_ALIGNED), (True, pin.LOCAL)):
                np.testing.assert_allclose(model.frame_jacobian(q, frame, local=local),
                                           pin.getFrameJacobian(pm, pd, fid, reference_frame), rtol=0, atol=1e-12,
                                           err_msg=f"{label}: Jacobian of {frame}, local={local}")
            bias = pin.getFrameClassicalAcceleration(pm, pd, fid, pin.LOCAL_WORLD_ALIGNED)
            np.testing.assert_allclose(model.frame_acceleration_bias(q, qd, frame),
                                       np.concatenate([bias.linear, bias.angular]), rtol=0, atol=1e-12,
                                       err_msg=f"{label}: J̇q̇ of {frame}")
        ours = model.forward_dynamics_derivatives(q, qd, tau)
        theirs = list(pin.computeABADerivatives(pm, pd, q, qd, tau))
        theirs[2] = np.triu(theirs[2]) + np.triu(theirs[2], 1).T
        for what, a, b in zip(("dqdd/dq", "dqdd/dqd", "Minv"), ours, theirs):
            scale = max(1.0, np.abs(b).max())
            np.testing.assert_allclose(a, b, rtol=0, atol=1e-10 * scale, err_msg=f"{label}: {what}")


def dynamics(model, q, qd, qdd):
    """Every batch method's output on the states `(q, qd, qdd)` (`qdd` as torques for FD)."""
    return {
        "id": model.inverse_dynamics(q, qd, qdd),
        "mass": model.mass_matrix(q),
        "gravity": model.gravity(q),
        "fd": model.forward_dynamics(q, qd, qdd),
    }


@pytest.mark.parametrize("name", ARMS)
def test_a_batch_equals_row_by_row(name, rng):
    model = hya.Model.builtin(name)
    n = 17
    q, qd, qdd = (rng.uniform(-2, 2, (n, model.dof)) for _ in range(3))
    batch = dynamics(model, q, qd, qdd)
    batch["pose"] = model.frame_pose(q, model.frame_names[-1])
    batch["jacobian"] = model.frame_jacobian(q, model.frame_names[-1])
    batch["bias"] = model.frame_acceleration_bias(q, qd, model.frame_names[-1])
    batch["fd_derivatives"] = model.forward_dynamics_derivatives(q, qd, qdd)
    assert batch["jacobian"].shape == (n, 6, model.dof) and batch["bias"].shape == (n, 6)
    assert all(part.shape == (n, model.dof, model.dof) for part in batch["fd_derivatives"])
    assert batch["id"].shape == (n, model.dof) and batch["mass"].shape == (n, model.dof, model.dof)
    assert batch["pose"].shape == (n, 4, 4)
    for k in range(n):
        # Bit for bit: the batch runs the same code on the same numbers.
        assert np.array_equal(batch["id"][k], model.inverse_dynamics(q[k], qd[k], qdd[k]))
        assert np.array_equal(batch["mass"][k], model.mass_matrix(q[k]))
        assert np.array_equal(batch["gravity"][k], model.gravity(q[k]))
        assert np.array_equal(batch["fd"][k], model.forward_dynamics(q[k], qd[k], qdd[k]))
        assert np.array_equal(batch["pose"][k], model.frame_pose(q[k], model.frame_names[-1]))
        assert np.array_equal(batch["jacobian"][k], model.frame_jacobian(q[k], model.frame_names[-1]))
        assert np.array_equal(batch["bias"][k], model.frame_acceleration_bias(q[k], qd[k], model.frame_names[-1]))
        for part, single in zip(batch["fd_derivatives"], model.forward_dynamics_derivatives(q[k], qd[k], qdd[k])):
            assert np.array_equal(part[k], single)


@pytest.mark.parametrize("generated", [True, False], ids=["generated", "urdf"])
def test_a_batch_too_long_to_hold_the_gil_gives_the_same_rows(generated, rng):
    # Short batches read the arrays in place with the GIL held; one that would hold it past
    # about a millisecond (5000 generated states, 500 on the run-time model) runs on copies
    # without it. Both give the same rows, bit for bit.
    model = hya.Model.builtin("iiwa14") if generated else hya.Model.from_urdf(str(urdf_path("iiwa14")))
    n = 5000 if generated else 500
    q, qd, qdd = (rng.uniform(-2, 2, (n, model.dof)) for _ in range(3))
    long = dynamics(model, q, qd, qdd)
    for rows in (slice(0, 9), slice(n - 9, n)):
        short = dynamics(model, q[rows], qd[rows], qdd[rows])
        for key, values in short.items():
            assert np.array_equal(long[key][rows], values), key


class Counter(threading.Thread):
    """Counts while it holds the GIL, letting go of it for 0.1 ms after each count."""

    def __init__(self):
        super().__init__(daemon=True)
        self.count = 0
        self.stop = False
        self.counting = threading.Event()

    def run(self):
        self.counting.set()
        while not self.stop:
            self.count += 1
            time.sleep(1e-4)


def counted_during(call):
    """How often a `Counter` counted while `call()` ran. With a switch interval far longer than
    the call, CPython never takes the GIL from this thread by force (nor does the collector run
    finalizers, disabled here), so the counter counts only where the call lets go of the GIL."""
    interval, collecting = sys.getswitchinterval(), gc.isenabled()
    counter = Counter()
    sys.setswitchinterval(5.0)
    gc.disable()
    try:
        counter.start()
        counter.counting.wait()
        before = counter.count
        call()
        return counter.count - before
    finally:
        counter.stop = True
        counter.join()
        sys.setswitchinterval(interval)
        if collecting:
            gc.enable()


@pytest.mark.parametrize("generated", [True, False], ids=["generated", "run-time"])
def test_a_short_batch_holds_the_gil_and_a_long_one_lets_go(generated, rng):
    # The bounds: 4000 generated states or 400 on the run-time model are read in place with the
    # GIL held. Just under the bound, the other thread never counts; far over it (tens of
    # milliseconds of forward dynamics), it counts, given up to three tries on a loaded machine.
    model = hya.Model.builtin("iiwa14") if generated else hya.Model.from_urdf(str(urdf_path("iiwa14")))
    short, long = (3_900, 200_000) if generated else (390, 20_000)

    def call(n):
        q, qd, tau = (rng.uniform(-2, 2, (n, model.dof)) for _ in range(3))
        return lambda: model.forward_dynamics(q, qd, tau)

    for _ in range(3):
        assert counted_during(call(short)) == 0, f"{short} states: the GIL was let go"
    assert any(counted_during(call(long)) > 0 for _ in range(3)), f"{long} states: the GIL was held throughout"


def test_an_array_written_while_later_arguments_convert_is_checked_after(rng):
    # `q` is read in place; converting `qd` runs Python code that writes NaN into `q`. Every
    # argument is checked after all are converted, so the NaN is refused, not computed on.
    model = hya.Model.builtin("hya")
    q = rng.uniform(-1, 1, (4, 6))

    class Spoiler:
        def __array__(self, dtype=None, copy=None):
            q[2, 3] = np.nan
            return np.zeros((4, 6))

    with pytest.raises(ValueError, match=r"q\[2, 3\] = NaN"):
        model.inverse_dynamics(q, Spoiler(), np.zeros((4, 6)))


def test_any_memory_order_reads_the_same_rows(rng):
    model = hya.Model.builtin("ur5")
    q, qd, qdd = (rng.uniform(-1, 1, (9, 6)) for _ in range(3))
    expected = model.inverse_dynamics(q, qd, qdd)
    fortran = [np.asfortranarray(x) for x in (q, qd, qdd)]
    assert fortran[0].flags.f_contiguous and not fortran[0].flags.c_contiguous
    assert np.array_equal(model.inverse_dynamics(*fortran), expected)
    strided = [np.repeat(x, 2, axis=0)[::2] for x in (q, qd, qdd)]  # a view, not contiguous
    assert np.array_equal(model.inverse_dynamics(*strided), expected)
    assert np.array_equal(model.inverse_dynamics(q.T.copy().T, qd, qdd), expected)


def test_array_likes_are_accepted():
    model = hya.Model.builtin("hya")
    as_list = model.gravity([0.0] * 6)
    as_ints = model.gravity([0] * 6)
    as_f32 = model.gravity(np.zeros(6, dtype=np.float32))
    assert as_list.shape == (6,) and np.array_equal(as_list, as_ints) and np.array_equal(as_list, as_f32)
    assert np.abs(as_list).max() > 1.0  # HyA's gravity torques at zero are not zero


def test_bad_shapes_and_non_finite_values_name_the_argument():
    model = hya.Model.builtin("hya")
    good = np.zeros(6)
    with pytest.raises(ValueError, match=r"qd: shape \[5\]"):
        model.inverse_dynamics(good, np.zeros(5), good)
    with pytest.raises(ValueError, match=r"q: shape \[2, 3, 6\]"):
        model.gravity(np.zeros((2, 3, 6)))
    with pytest.raises(ValueError, match=r"qdd\[2\] = NaN"):
        model.inverse_dynamics(good, good, [0, 0, np.nan, 0, 0, 0])
    with pytest.raises(ValueError, match=r"tau\[1, 4\] = inf"):
        bad = np.zeros((3, 6))
        bad[1, 4] = np.inf
        model.forward_dynamics(np.zeros((3, 6)), np.zeros((3, 6)), bad)
    with pytest.raises(ValueError, match="qd: 2 row"):
        model.inverse_dynamics(np.zeros((3, 6)), np.zeros((2, 6)), np.zeros((3, 6)))
    with pytest.raises(ValueError, match="q: expected an array of numbers"):
        model.gravity("not numbers")
    with pytest.raises(KeyError, match="no frame `nowhere`"):
        model.frame_pose(good, "nowhere")
    with pytest.raises(KeyError, match="no frame `nowhere`"):
        model.frame_jacobian(good, "nowhere")
    with pytest.raises(ValueError, match=r"qd\[3\] = NaN"):
        model.frame_acceleration_bias(good, [0, 0, 0, np.nan, 0, 0], model.frame_names[-1])
    with pytest.raises(ValueError, match=r"tau: shape \[5\]"):
        model.forward_dynamics_derivatives(good, good, np.zeros(5))
    with pytest.raises(KeyError, match="no shipped robot `hyb`"):
        hya.Model.builtin("hyb")


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_a_non_finite_value_anywhere_in_a_batch_is_found(bad):
    # The check sums in blocks of eight values with a tail: every position of 3 × 6 values.
    model = hya.Model.builtin("hya")
    for at in range(18):
        tau = np.zeros((3, 6))
        tau.flat[at] = bad
        with pytest.raises(ValueError, match=rf"tau\[{at // 6}, {at % 6}\] = -?(NaN|inf)"):
            model.forward_dynamics(np.zeros((3, 6)), np.zeros((3, 6)), tau)


@pytest.mark.parametrize("name", ["ur5", "planar2"])
def test_results_that_overflow_are_refused_as_the_cli_and_the_c_abi_refuse_them(name):
    # q̇ = 1e160 squares past the largest double: finite inputs, non-finite torques.
    model = hya.Model.builtin(name)
    n = model.dof
    fast = np.zeros(n)
    fast[0] = 1e160
    with pytest.raises(ValueError, match=r"tau\[\d\] = -?(NaN|inf): the result is not finite"):
        model.inverse_dynamics(np.zeros(n), fast, np.zeros(n))
    batch = np.zeros((5, n))
    batch[3, 0] = 1e160
    with pytest.raises(ValueError, match=r"row 3: tau\[\d\] = -?(NaN|inf)"):
        model.inverse_dynamics(np.zeros((5, n)), batch, np.zeros((5, n)))
    with pytest.raises(ValueError, match=r"row 3: qdd\[\d\] = -?(NaN|inf)"):
        model.forward_dynamics(np.zeros((5, n)), batch, np.zeros((5, n)))


def test_a_broken_urdf_names_the_file_and_the_joint():
    path = DATA / "broken_joint.urdf"
    with pytest.raises(hya.UrdfError, match="broken_joint.urdf") as error:
        hya.Model.from_urdf(str(path))
    assert "bad_axis_joint" in str(error.value)
    assert isinstance(error.value, ValueError)
    with pytest.raises(hya.UrdfError, match="missing.urdf"):
        hya.Model.from_urdf(str(DATA / "missing.urdf"))
