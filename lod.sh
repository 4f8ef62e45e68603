#!/usr/bin/env bash
# Line Quadric LOD: the README's commands.
#   ./lod.sh demo              provision, then make LODs of the built-in sample into out/sample
#   ./lod.sh test [pytest ...] provision, then run the whole test suite
#   ./lod.sh run  [cli ...]    provision, then run the command line with your arguments
#   ./lod.sh CMD --blender X.Y ...  the same against another Blender line (e.g. 5.2)
# Provisioning (tools/env.sh) creates .venv inside this folder once, with the pinned bpy
# module (Blender 4.5 LTS); later runs reuse it and start in seconds. Another Blender line
# gets its own virtualenv under .venvs/ (with the Python its bpy module needs).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if [ "${2:-}" = "--blender" ]; then
  [ -n "${3:-}" ] || { echo "error: --blender needs a version, e.g. --blender 5.2" >&2; exit 2; }
  export LQLOD_BLENDER="$3"
  set -- "$1" "${@:4}"
fi
# shellcheck source=tools/env.sh
source "$ROOT/tools/env.sh"

usage() {
  sed -n '2,6s/^# \{0,1\}//p' "$0" >&2
}

require_cli() {
  if [ ! -f "$ROOT/__main__.py" ]; then
    echo "error: the command line (__main__.py) is not in this checkout yet; nothing to run" >&2
    exit 1
  fi
}

cmd="${1:-}"
[ $# -gt 0 ] && shift
case "$cmd" in
  demo)
    require_cli
    ensure_env
    isolate_blender_user_dirs
    cd "$ROOT"
    exec "$VENV/bin/python" "$ROOT" --sample --output-dir out/sample "$@"
    ;;
  run)
    require_cli
    ensure_env
    isolate_blender_user_dirs
    # No cd: paths in the arguments are relative to where the user is.
    exec "$VENV/bin/python" "$ROOT" "$@"
    ;;
  test)
    ensure_env
    # The tests isolate every Blender child themselves (tests/bpy_harness.py); this also
    # keeps anything that slips past them away from the real ~/.config/blender.
    LQLOD_BLENDER_HOME="$ROOT/.blender-user/tests-$BLENDER" isolate_blender_user_dirs
    cd "$ROOT"
    exec "$VENV/bin/python" -m pytest "$@"
    ;;
  -h|--help|help)
    usage
    ;;
  *)
    usage
    exit 2
    ;;
esac
