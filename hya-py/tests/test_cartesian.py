"""The Cartesian impedance controller against its law computed here with Pinocchio (frame pose,
Jacobian, C + G) and NumPy (the rotation's logarithm, the projector): the same torque to 1e-9."""
import numpy as np
import pinocchio as pin
import pytest

import hya
from conftest import urdf_path

STIFFNESS = [1500.0, 500.0, 600.0, 8.0, 23.0, 0.7]
DAMPING = [200.0, 70.0, 80.0, 1.0, 3.0, 0.1]
READY = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])


def law(pm, pd, frame, q, qd, target, twist, d_hat, posture, mu):
    """τ = Jᵀ(K e − D (J q̇ − ẋ_des)) + C + G − d̂ + P(−K_n (q − q_rest) − D_n q̇)."""
    fid = pm.getFrameId(frame)
    pin.framesForwardKinematics(pm, pd, q)
    pin.computeJointJacobians(pm, pd, q)
    pose = pd.oMf[fid]
    jacobian = pin.getFrameJacobian(pm, pd, fid, pin.LOCAL_WORLD_ALIGNED)
    position, orientation = target
    error = np.concatenate([position - pose.translation, pin.log3(orientation @ pose.rotation.T)])
    wrench = np.array(STIFFNESS) * error - np.array(DAMPING) * (jacobian @ qd - twist)
    tau = jacobian.T @ wrench + pin.rnea(pm, pd, q, qd, np.zeros(pm.nv)) - d_hat
    rest, kn, dn = posture
    projector = np.eye(pm.nv) - jacobian.T @ np.linalg.solve(jacobian @ jacobian.T + mu * mu * np.eye(6), jacobian)
    return tau + projector @ (-kn * (q - rest) - dn * qd)


@pytest.mark.parametrize("frame", ["panda_link8", "panda_link6"])
def test_the_command_equals_the_law_computed_with_pinocchio(frame, rng):
    model = hya.Model.builtin("panda")
    pm = pin.buildModelFromUrdf(str(urdf_path("panda")))
    pd = pm.createData()
    posture = (READY, np.full(7, 5.0), np.full(7, 2.0))
    controller = hya.CartesianImpedance(model, STIFFNESS, DAMPING, frame=frame, posture_rest=list(posture[0]),
                                        posture_stiffness=list(posture[1]), posture_damping=list(posture[2]))
    assert controller.frame == frame
    for _ in range(10):
        q, qd, d_hat = READY + 0.3 * rng.standard_normal(7), rng.standard_normal(7), rng.standard_normal(7)
        goal = READY + 0.3 * rng.standard_normal(7)
        pin.framesForwardKinematics(pm, pd, goal)
        target = (pd.oMf[pm.getFrameId(frame)].translation.copy(), pd.oMf[pm.getFrameId(frame)].rotation.copy())
        twist = 0.1 * rng.standard_normal(6)
        tau = controller.command(q, qd, list(target[0]), target[1].tolist(), twist_des=list(twist), d_hat=list(d_hat))
        expected = law(pm, pd, frame, q, qd, target, twist, d_hat, posture, 1e-3)
        np.testing.assert_allclose(tau, expected, rtol=1e-9, atol=1e-9)


def test_bad_gains_frames_and_orientations_are_refused():
    model = hya.Model.builtin("panda")
    with pytest.raises(ValueError, match="stiffness.*6 values"):
        hya.CartesianImpedance(model, STIFFNESS[:5], DAMPING)
    with pytest.raises(ValueError, match="damping"):
        hya.CartesianImpedance(model, STIFFNESS, [-1.0] + DAMPING[1:])
    with pytest.raises(ValueError, match="panda_hand.*panda_link8"):
        hya.CartesianImpedance(model, STIFFNESS, DAMPING, frame="panda_hand")
    with pytest.raises(ValueError, match="all given or none"):
        hya.CartesianImpedance(model, STIFFNESS, DAMPING, posture_rest=list(READY))
    controller = hya.CartesianImpedance(model, STIFFNESS, DAMPING)
    assert controller.frame == "panda_link8", "the last link by default"
    with pytest.raises(ValueError, match="orientation_des"):
        controller.command(READY, np.zeros(7), [0.3, 0.0, 0.5], [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]])
    with pytest.raises(ValueError, match=r"q\[0\]"):
        controller.command([np.nan] + [0.0] * 6, np.zeros(7), [0.3, 0.0, 0.5], np.eye(3).tolist())
    with pytest.raises(ValueError, match="posture_rest holds 6 values"):
        hya.CartesianImpedance(model, STIFFNESS, DAMPING, posture_rest=list(READY[:6]),
                               posture_stiffness=[1.0] * 7, posture_damping=[1.0] * 7)
