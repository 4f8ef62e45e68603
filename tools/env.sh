#!/usr/bin/env bash
# Shared environment machinery for the README's commands: makes (once) and reuses a
# virtualenv inside the checkout (.venv, git-ignored) holding the pinned `bpy` module
# and the test tools. Re-provisions only when requirements-dev.txt changes.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$ROOT/.venv"
REQ="$ROOT/requirements-dev.txt"
STAMP="$VENV/.requirements.sha256"
PY="${PYTHON:-python3.11}"
command -v "$PY" >/dev/null 2>&1 || PY=python3

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
  local want="$1" ver
  ver="$("$PY" -c 'import sys; print("%d.%d" % sys.version_info[:2])')"
  if [ "$ver" != "3.11" ]; then
    echo "error: the bpy module for Blender 4.5 needs Python 3.11, found $PY = $ver" >&2
    echo "       set PYTHON=/path/to/python3.11" >&2
    exit 2
  fi
  echo "[env] provisioning $VENV (first run downloads Blender 4.5 as the bpy module) ..." >&2
  if [ ! -x "$VENV/bin/python" ]; then
    "$PY" -m venv "$VENV" || {
      echo "error: could not create a virtualenv; on Debian/Ubuntu: apt-get install python3.11-venv" >&2
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
