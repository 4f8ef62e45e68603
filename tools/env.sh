#!/usr/bin/env bash
# Shared environment machinery for the README's commands: makes (once) and reuses a
# virtualenv inside the checkout (.venv, git-ignored) holding the pinned `bpy` module
# and the test tools. Re-provisions only when requirements-dev.txt changes.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
REQ_DEV="$ROOT/requirements-dev.txt"
# The Blender line requirements-dev.txt pins (its `bpy==X.Y.*` line): the default.
DEFAULT_BLENDER="$(sed -n 's/^bpy==\([0-9]*\.[0-9]*\).*/\1/p' "$REQ_DEV")"
# LQLOD_BLENDER=X.Y (or `./lod.sh test --blender X.Y`) picks another Blender line: its
# own virtualenv under .venvs/, the same requirements with that bpy.
BLENDER="${LQLOD_BLENDER:-$DEFAULT_BLENDER}"
if [ "$BLENDER" = "$DEFAULT_BLENDER" ]; then
  VENV="$ROOT/.venv"
  REQ="$REQ_DEV"
else
  VENV="$ROOT/.venvs/blender-$BLENDER"
  REQ="$VENV.requirements.txt"
  mkdir -p "$ROOT/.venvs"
  sed "s/^bpy==.*/bpy==$BLENDER.*/" "$REQ_DEV" > "$REQ.tmp" && mv "$REQ.tmp" "$REQ"
fi
STAMP="$VENV/.requirements.sha256"

# The Python each bpy module is built for: Blender 4.x and 5.0 use 3.11, 5.1 and later 3.13.
python_for_blender() {
  case "$1" in
    4.*|5.0) echo 3.11 ;;
    *) echo 3.13 ;;
  esac
}

# A python of version $1 that runs: $PYTHON if set, else pythonX.Y on PATH, else pyenv's.
find_python() {
  local want="$1" cand
  if [ -n "${PYTHON:-}" ]; then
    echo "$PYTHON"
    return 0
  fi
  for cand in "python$want" "${PYENV_ROOT:-$HOME/.pyenv}"/versions/"$want".*/bin/"python$want"; do
    if "$cand" -c 'import sys' >/dev/null 2>&1; then
      echo "$cand"
      return 0
    fi
  done
  return 1
}

_env_ready() {
  [ -x "$VENV/bin/python" ] && [ -f "$STAMP" ] && [ "$(cat "$STAMP")" = "$1" ]
}

ensure_env() {
  local want
  want="$(sha256sum "$REQ" | cut -d' ' -f1)"
  _env_ready "$want" && return 0
  # Two commands started together (e.g. tests and demo) must not pip-install into the
  # same venv at once: the second waits, then finds the env ready.
  mkdir -p "$VENV"
  if command -v flock >/dev/null 2>&1; then
    exec 9>"$VENV/.provision.lock"
    flock 9
  fi
  if ! _env_ready "$want"; then
    _provision "$want"
  fi
  if command -v flock >/dev/null 2>&1; then
    exec 9>&-
  fi
}

_provision() {
  local want="$1" ver pyver PY
  pyver="$(python_for_blender "$BLENDER")"
  if ! PY="$(find_python "$pyver")"; then
    echo "error: the bpy module for Blender $BLENDER needs Python $pyver, and none was found" >&2
    echo "       (looked for python$pyver on PATH and under ${PYENV_ROOT:-$HOME/.pyenv}/versions)." >&2
    echo "       Install it (e.g. 'pyenv install $pyver', or your system's python$pyver and" >&2
    echo "       python$pyver-venv packages), or set PYTHON=/path/to/python$pyver" >&2
    exit 2
  fi
  ver="$("$PY" -c 'import sys; print("%d.%d" % sys.version_info[:2])')"
  if [ "$ver" != "$pyver" ]; then
    echo "error: the bpy module for Blender $BLENDER needs Python $pyver, found $PY = $ver" >&2
    echo "       set PYTHON=/path/to/python$pyver" >&2
    exit 2
  fi
  echo "[env] provisioning $VENV (first run downloads Blender $BLENDER as the bpy module, Python $pyver) ..." >&2
  if [ ! -x "$VENV/bin/python" ]; then
    "$PY" -m venv "$VENV" || {
      echo "error: could not create a virtualenv; on Debian/Ubuntu: apt-get install python$pyver-venv" >&2
      exit 2
    }
  fi
  "$VENV/bin/python" -m pip install --quiet --upgrade pip >&2
  "$VENV/bin/python" -m pip install --quiet -r "$REQ" >&2 || {
    echo "error: installing $REQ failed (network access to PyPI is needed on the first run)" >&2
    exit 2
  }
  echo "$want" > "$STAMP"
  echo "[env] ready" >&2
}

# Blender must never read or write the real user's configuration from these commands.
isolate_blender_user_dirs() {
  local base="${LQLOD_BLENDER_HOME:-$ROOT/.blender-user}"
  mkdir -p "$base"/{config,scripts,datafiles,extensions}
  export BLENDER_USER_RESOURCES="$base"
  export BLENDER_USER_CONFIG="$base/config"
  export BLENDER_USER_SCRIPTS="$base/scripts"
  export BLENDER_USER_DATAFILES="$base/datafiles"
  export BLENDER_USER_EXTENSIONS="$base/extensions"
}
