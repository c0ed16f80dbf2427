"""Type stubs of hya. Units: rad, rad/s, rad/s², N·m, m, s. Every array argument accepts
anything array-like; one state is shape (dof,), a batch (n, dof)."""

from os import PathLike
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

ArrayLike = npt.ArrayLike
Array = npt.NDArray[np.float64]

class UrdfError(ValueError):
    """A URDF that cannot be loaded; the message names the file and the link or joint."""

class Model:
    """Rigid-body dynamics of a shipped arm (generated code) or of any URDF."""

    @staticmethod
    def from_urdf(path: Union[str, "PathLike[str]"]) -> "Model": ...
    @staticmethod
    def builtin(name: str) -> "Model": ...
    @staticmethod
    def builtin_names() -> List[str]: ...
    @property
    def dof(self) -> int: ...
    @property
    def joint_names(self) -> List[str]: ...
    @property
    def frame_names(self) -> List[str]: ...
    @property
    def generated(self) -> bool: ...
    def inverse_dynamics(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike) -> Array:
        """τ = M(q) q̈ + C(q, q̇) + G(q), N·m; (dof,) or (n, dof)."""
    def mass_matrix(self, q: ArrayLike) -> Array:
        """M(q), kg·m²; (dof, dof) or (n, dof, dof)."""
    def gravity(self, q: ArrayLike) -> Array:
        """G(q), N·m; (dof,) or (n, dof)."""
    def forward_dynamics(self, q: ArrayLike, qd: ArrayLike, tau: ArrayLike) -> Array:
        """q̈ = M⁻¹(τ − C − G), rad/s² (articulated-body algorithm); (dof,) or (n, dof)."""
    def frame_pose(self, q: ArrayLike, name: str) -> Array:
        """The frame's pose in the base frame, 4×4 homogeneous; (4, 4) or (n, 4, 4)."""
    def frame_jacobian(self, q: ArrayLike, name: str, local: bool = False) -> Array:
        """The frame's geometric Jacobian, linear rows then angular, world-aligned (local=True: in
        the frame's axes); (6, dof) or (n, 6, dof)."""
    def frame_acceleration_bias(self, q: ArrayLike, qd: ArrayLike, name: str) -> Array:
        """J̇ q̇ of the frame: its origin's classical acceleration and its angular acceleration at
        q̈ = 0, world-aligned; (6,) or (n, 6)."""
    def forward_dynamics_derivatives(self, q: ArrayLike, qd: ArrayLike, tau: ArrayLike) -> List[Array]:
        """[∂q̈/∂q, ∂q̈/∂q̇, M⁻¹], each (dof, dof) or (n, dof, dof), row i being ∂q̈_i."""

class DisturbanceEstimator:
    """d̂ = ID(q̂, q̂̇, q̂̈) − τ̂ from two third-order filters (Lu, Sandy & Buchli)."""

    def __init__(
        self,
        model: Model,
        zeta: float = 0.8,
        omega1: float = 50.0,
        omega2: float = 50.0,
        dt: float = 0.001,
        q0: Optional[ArrayLike] = None,
        tau0: Optional[ArrayLike] = None,
        t0: Optional[float] = None,
        friction: Optional[str] = None,
    ) -> None: ...
    def update(self, q: ArrayLike, tau: ArrayLike, t: Optional[float] = None) -> Array: ...
    def run(self, q_log: ArrayLike, tau_log: ArrayLike, t: Optional[ArrayLike] = None) -> Array: ...
    @property
    def disturbance(self) -> List[float]: ...

class _Observer:
    def __init__(
        self,
        model: Model,
        bandwidth: float = 50.0,
        dt: float = 0.001,
        q0: Optional[ArrayLike] = None,
        qd0: Optional[ArrayLike] = None,
        tau0: Optional[ArrayLike] = None,
    ) -> None: ...
    def update(self, q: ArrayLike, tau: ArrayLike, qd: Optional[ArrayLike] = None) -> Array: ...
    def run(self, q_log: ArrayLike, tau_log: ArrayLike, qd_log: Optional[ArrayLike] = None) -> Array: ...
    @property
    def disturbance(self) -> List[float]: ...

class MomentumObserver(_Observer):
    """Generalized-momentum observer, d̂ = K_O/(s + K_O) d; needs qd."""

class NonlinearDisturbanceObserver(_Observer):
    """Chen's observer with Y = β M(q0); needs qd."""

class ExtendedStateObserver(_Observer):
    """Model-assisted extended-state observer, poles at −bandwidth; angles only."""

class ThirdOrderFilter:
    """H(s) = ω1 ω2² / ((s + ω1)(s² + 2ζω2 s + ω2²)), one channel per entry of x0."""

    def __init__(
        self, x0: Sequence[float], zeta: float = 0.8, omega1: float = 50.0, omega2: float = 50.0, dt: float = 0.001
    ) -> None: ...
    def step(self, u: Sequence[float]) -> Tuple[List[float], List[float], List[float]]: ...

class ComputedTorque:
    """τ = M q̈_des + C + G − K_D ė − K_P e − d̂."""

    def __init__(
        self,
        model: Model,
        kp: Sequence[float],
        kd: Sequence[float],
        torque_limit: Optional[Sequence[float]] = None,
        friction: Optional[str] = None,
    ) -> None: ...
    def command(
        self,
        q: Sequence[float],
        qd: Sequence[float],
        q_des: Sequence[float],
        qd_des: Optional[Sequence[float]] = None,
        qdd_des: Optional[Sequence[float]] = None,
        d_hat: Optional[Sequence[float]] = None,
    ) -> List[float]: ...

class CartesianImpedance:
    """τ = Jᵀ(K_x e − D_x (J q̇ − ẋ_des)) + C + G − d̂ + P(−K_n (q − q_rest) − D_n q̇), on one frame."""

    frame: str
    def __init__(
        self,
        model: Model,
        stiffness: Sequence[float],
        damping: Sequence[float],
        frame: Optional[str] = None,
        posture_rest: Optional[Sequence[float]] = None,
        posture_stiffness: Optional[Sequence[float]] = None,
        posture_damping: Optional[Sequence[float]] = None,
        mu: float = 0.001,
        torque_limit: Optional[Sequence[float]] = None,
    ) -> None: ...
    def command(
        self,
        q: Sequence[float],
        qd: Sequence[float],
        position_des: Sequence[float],
        orientation_des: Sequence[Sequence[float]],
        twist_des: Optional[Sequence[float]] = None,
        d_hat: Optional[Sequence[float]] = None,
    ) -> List[float]: ...

def identify(
    model: Model,
    q: ArrayLike,
    tau: ArrayLike,
    dt: float,
    *,
    t: Optional[ArrayLike] = None,
    max_step: Optional[float] = None,
    held_out: float = 0.25,
    smoothing_rad_s: float = 0.05,
    bandwidth_rad_s: float = 50.0,
    prior_weight: Union[str, float, None] = None,
    armature: bool = False,
    keep_reversals: bool = False,
) -> Dict[str, Any]:
    """Base parameters and joint friction of `model` from a log's rows of q (rad) and tau (N·m),
    one per dt, or at the times t with dt their nominal step: what `hya identify` finds from the
    same rows, with `identified_urdf` the text it writes."""

def simulate(
    scenario: Union[str, Dict[str, Any]], method: str = "lu", seed: Optional[int] = None, quick: bool = False
) -> Dict[str, Any]:
    """Runs one method of a scenario; time series as NumPy arrays and the metrics as a dict.

    The series hold every control tick up to 30 000 ticks and every k-th tick of a longer run
    ("time" says which); the metrics use every tick."""

def rollouts(
    scenarios: Union[str, Dict[str, Any], List[Union[str, Dict[str, Any]]]],
    method: str = "lu",
    seeds: Optional[Sequence[int]] = None,
    quick: bool = False,
) -> Dict[str, Any]:
    """Runs one method of every scenario with every seed, in Rust on every core; the series
    stacked (T, runs, dof), scenario-major, with "metrics" and "runs" per run."""
