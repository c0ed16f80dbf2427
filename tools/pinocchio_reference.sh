#!/usr/bin/env bash
# Installs Pinocchio (`pin` on PyPI) into tools/.venv and writes the reference CSV files.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
venv="${HYA_VENV:-$here/.venv}"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install -q pin numpy
"$venv/bin/python" "$here/pinocchio_reference.py" "$@"
