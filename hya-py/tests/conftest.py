"""Shared fixtures: the repository's URDFs and a seeded generator."""
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
DATA = Path(__file__).resolve().parent / "data"


def urdf_path(name):
    """A shipped arm's URDF in the repository, or one of the tests' own."""
    shipped = ROOT / "robots" / "urdf" / f"{name}.urdf"
    return shipped if shipped.exists() else DATA / f"{name}.urdf"


@pytest.fixture
def rng():
    return np.random.default_rng(20261123)
