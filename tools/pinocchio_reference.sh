#!/usr/bin/env bash
# Installs Pinocchio (`pin` on PyPI) into tools/.venv and writes the reference CSV files: the
# dynamics (tests/reference/*.csv, of the URDFs given or every shipped robot) and the joint-torque
# regressor (tests/reference/regressor/, of the shipped robots and two test URDFs), frame kinematics
# and forward-dynamics derivatives (tests/reference/kinematics/).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
venv="${HYA_VENV:-$here/.venv}"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install -q pin numpy
"$venv/bin/python" "$here/pinocchio_reference.py" "$@"
"$venv/bin/python" "$here/regressor_reference.py"
"$venv/bin/python" "$here/kinematics_reference.py"
