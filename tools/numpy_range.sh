#!/usr/bin/env bash
# The core tests under the oldest and newest NumPy that core promises to support (1.24
# and 2.x), each in a throwaway virtualenv outside the checkout. Blender's own NumPy is
# what `./lod.sh test` uses; this covers the rest of the range. Needs PyPI; not run by CI.
#   tools/numpy_range.sh [numpy versions...]   (default: 1.24 2)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PY="${PYTHON:-python3.11}"
command -v "$PY" >/dev/null 2>&1 || PY=python3
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
status=0
for version in "${@:-1.24 2}"; do
  for v in $version; do
    env="$WORK/numpy-$v"
    "$PY" -m venv "$env"
    "$env/bin/pip" install -q "numpy==$v.*" pytest hypothesis
    echo "== numpy $("$env/bin/python" -c 'import numpy; print(numpy.__version__)')"
    # Core only: the bpy tests need Blender's own NumPy. Warnings are errors, so a
    # deprecation shows up before the version that removes it.
    (cd "$ROOT" && "$env/bin/python" -m pytest -q -p no:cacheprovider \
        -W error::DeprecationWarning -W error::RuntimeWarning tests/test_core_*.py) || status=1
  done
done
exit $status
