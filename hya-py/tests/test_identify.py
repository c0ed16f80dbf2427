"""hya.identify: identification on arrays, the same library calls as `hya identify`."""
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import hya

from conftest import ROOT

DT = 0.001
SECONDS = 24.0
# Friction the log carries beyond the rigid body: c tanh(q̇/s) + v q̇ + o per joint, smooth
# enough (s = 0.5 rad/s) that the filters' smoothing of it biases the fit little.
SMOOTHING = 0.5
COULOMB = np.array([1.5, 0.8])
VISCOUS = np.array([0.6, 0.3])
OFFSET = np.array([0.2, -0.1])


def exciting_log(model):
    """q, q̇, q̈ of two sums of sines and τ = ID + friction, one row per DT."""
    t = np.arange(0.0, SECONDS, DT)
    q, qd, qdd = (np.zeros((t.size, 2)) for _ in range(3))
    for j, (amplitudes, frequencies) in enumerate([((0.6, 0.3), (0.31, 0.83)), ((0.8, 0.25), (0.47, 1.13))]):
        for a, f in zip(amplitudes, frequencies):
            w = 2 * np.pi * f
            q[:, j] += a * np.sin(w * t + j)
            qd[:, j] += a * w * np.cos(w * t + j)
            qdd[:, j] -= a * w * w * np.sin(w * t + j)
    tau = model.inverse_dynamics(q, qd, qdd) + COULOMB * np.tanh(qd / SMOOTHING) + VISCOUS * qd + OFFSET
    return t, q, tau


def test_identify_finds_the_friction_and_predicts_better_than_the_nominal_model():
    model = hya.Model.builtin("planar2")
    _, q, tau = exciting_log(model)
    found = hya.identify(model, q, tau, DT, smoothing_rad_s=SMOOTHING)
    assert found["rows"] == q.shape[0] and found["gaps"] == 0
    # The filters' lag biases the fit a little (4-6 % on the Coulomb levels here): within 10 %.
    np.testing.assert_allclose(found["friction"]["coulomb_nm"], COULOMB, rtol=0.1)
    np.testing.assert_allclose(found["friction"]["viscous_nm_s"], VISCOUS, rtol=0.1, atol=0.02)
    rms = found["held_out_rms_nm"]
    assert all(i < 0.2 * n for i, n in zip(rms["identified"], rms["nominal"])), rms
    assert "<robot" in found["identified_urdf"]
    # Each joint's rows near its reversals (here, with s = 0.5 rad/s, wherever it moves slower
    # than 1.5 rad/s within 0.2 s of the sample: most of this log) are left out, unless kept.
    assert len(found["fitted_rows"]) == 2
    assert all(0 < r < found["fitted_samples"] for r in found["fitted_rows"])
    kept = hya.identify(model, q, tau, DT, smoothing_rad_s=SMOOTHING, keep_reversals=True)
    assert kept["fitted_rows"] == [kept["fitted_samples"]] * 2


def test_identify_refuses_what_the_command_line_refuses():
    model = hya.Model.builtin("planar2")
    t, q, tau = exciting_log(model)
    with pytest.raises(ValueError, match="held_out"):
        hya.identify(model, q, tau, DT, held_out=0.95)
    with pytest.raises(ValueError, match="strictly increase"):
        back = t.copy()
        back[5] = back[4]
        hya.identify(model, q, tau, DT, t=back)
    with pytest.raises(ValueError, match="needs at least"):
        hya.identify(model, q[:500], tau[:500], DT)


def hya_binary():
    """The command line built by `cargo test` or `cargo build` (CARGO_TARGET_DIR honoured)."""
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    for profile in ("debug", "release"):
        binary = target / profile / "hya"
        if binary.exists():
            return binary
    return None


@pytest.mark.skipif(hya_binary() is None, reason="no hya binary built (cargo build -p hya-cli)")
def test_identify_equals_the_command_line_on_the_same_rows(tmp_path):
    model = hya.Model.builtin("planar2")
    t, q, tau = exciting_log(model)
    t = t + 0.0002 * np.sin(37.0 * t)  # jittered timestamps, filtered over each step
    rows = "\n".join(",".join(repr(float(x)) for x in (tk, *qk, *tk_tau)) for tk, qk, tk_tau in zip(t, q, tau))
    log = tmp_path / "log.csv"
    log.write_text(rows + "\n")
    out = tmp_path / "identified"
    with open(log) as stdin:
        subprocess.run(
            [hya_binary(), "identify", "--robot", "planar2", "--dt", repr(DT), "--timestamps", "--out", out],
            stdin=stdin,
            check=True,
            capture_output=True,
        )
    found = hya.identify(model, q, tau, DT, t=t)
    # The identified URDF holds every body's parameters in shortest round-trip form: equal text
    # is equal numbers, bit for bit.
    assert found["identified_urdf"] == (out / "identified.urdf").read_text()
    friction = (out / "friction.toml").read_text()
    for key in ("coulomb_nm", "viscous_nm_s", "offset_nm"):
        line = next(l for l in friction.splitlines() if l.startswith(key))
        written = [float(x) for x in line.split("[")[1].split("]")[0].split(",")]
        np.testing.assert_allclose(written, found["friction"][key], rtol=0, atol=5e-7)
