"""hya.simulate: a scenario by name, from a TOML file and from a dict, as NumPy series."""
import numpy as np
import pytest

import hya
from conftest import ROOT


def test_a_builtin_scenario_returns_series_and_metrics():
    run = hya.simulate("goto_internal", method="lu", seed=1, quick=True)
    steps = len(run["time"])
    assert steps > 100 and run["method"] == "lu" and run["seed"] == 1
    for key in ("q", "q_des", "d_true", "d_hat", "tau_cmd"):
        assert run[key].shape == (steps, 6), key
        assert np.all(np.isfinite(run[key])), key
    assert len(run["metrics"]["rmse_q"]) == 6
    # The estimate follows the true disturbance better than zero does.
    assert np.abs(run["d_hat"] - run["d_true"]).mean() < np.abs(run["d_true"]).mean()


def test_a_toml_path_and_a_dict_give_the_same_run(tmp_path):
    tomllib = pytest.importorskip("tomllib")  # Python 3.11 and later
    text = (ROOT / "hya-sim" / "scenarios" / "planar2_goto.toml").read_text()
    path = tmp_path / "planar2_goto.toml"
    path.write_text(text)
    settings = tomllib.loads(text)
    from_file = hya.simulate(str(path), method="none", quick=True)
    from_dict = hya.simulate(settings, method="none", quick=True)
    assert np.array_equal(from_file["q"], from_dict["q"])


def test_bad_scenarios_are_named():
    tomllib = pytest.importorskip("tomllib")
    settings = tomllib.loads((ROOT / "hya-sim" / "scenarios" / "planar2_goto.toml").read_text())
    with pytest.raises(ValueError, match="duration_s"):
        hya.simulate(dict(settings, duration_s=-1.0))
    with pytest.raises(ValueError, match="start_s"):
        hya.simulate(dict(settings, task={"kind": "goto"}))
    with pytest.raises(ValueError, match="method `fast`"):
        hya.simulate("goto_internal", method="fast")
    # Every per-joint list that does not fit the arm at once, as `hya run` names them.
    plant = {k: v for k, v in settings["plant"].items() if k not in ("coulomb_nm", "static_nm")}
    with pytest.raises(ValueError, match=r"2 per-joint settings do not fit the arm's 2 joints.*static_nm.*coulomb_nm"):
        hya.simulate(dict(settings, plant=plant))


def test_rollouts_stack_seeds_and_equal_single_runs():
    seeds = [1, 2, 3]
    batch = hya.rollouts("goto_internal", method="lu", seeds=seeds, quick=True)
    steps = len(batch["time"])
    assert batch["q"].shape == (steps, 3, 6) and len(batch["metrics"]) == 3
    assert batch["runs"] == [("goto_internal", s) for s in seeds]
    for r, seed in enumerate(seeds):
        single = hya.simulate("goto_internal", method="lu", seed=seed, quick=True)
        assert np.array_equal(single["time"], batch["time"])
        for key in ("q", "q_des", "d_true", "d_hat", "tau_cmd"):
            assert np.array_equal(batch[key][:, r, :], single[key]), (key, seed)
        assert batch["metrics"][r] == single["metrics"]
    # Different seeds are different runs.
    assert not np.array_equal(batch["q"][:, 0, :], batch["q"][:, 1, :])


def test_rollouts_of_several_scenarios_and_their_refusals(tmp_path):
    tomllib = pytest.importorskip("tomllib")
    settings = tomllib.loads((ROOT / "hya-sim" / "scenarios" / "planar2_goto.toml").read_text())
    heavier = dict(settings, name="planar2_heavier")
    batch = hya.rollouts([settings, heavier], method="none", seeds=[5, 6], quick=True)
    assert batch["q"].shape[1:] == (4, 2)
    assert [name for name, _ in batch["runs"]] == [settings["name"]] * 2 + ["planar2_heavier"] * 2
    with pytest.raises(ValueError, match="scenario 1 .* time grid or arm differs"):
        hya.rollouts([settings, "goto_internal"], method="none", quick=True)
    with pytest.raises(ValueError, match="no scenario or no seed"):
        hya.rollouts("goto_internal", seeds=[])
    with pytest.raises(ValueError, match="integration steps"):
        hya.rollouts(dict(settings, duration_s=3000.0), seeds=list(range(1000)))
