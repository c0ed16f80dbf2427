"""hya: model-based control of robot arms under disturbances.

Rigid-body dynamics of the shipped arms (generated code) and of any URDF, on NumPy arrays; the
nonlinear disturbance estimator of Lu, Sandy & Buchli and the observers it is compared with; the
computed-torque and Cartesian impedance controllers; and the simulator of the paper's experiments. Units: rad, rad/s,
rad/s², N·m, m, s.
"""

from ._hya import (
    CartesianImpedance,
    ComputedTorque,
    DisturbanceEstimator,
    ExtendedStateObserver,
    Model,
    MomentumObserver,
    NonlinearDisturbanceObserver,
    ThirdOrderFilter,
    UrdfError,
    identify,
    rollouts,
    simulate,
)

__all__ = [
    "CartesianImpedance",
    "ComputedTorque",
    "DisturbanceEstimator",
    "ExtendedStateObserver",
    "Model",
    "MomentumObserver",
    "NonlinearDisturbanceObserver",
    "ThirdOrderFilter",
    "UrdfError",
    "identify",
    "rollouts",
    "simulate",
]
