"""glTF checks for the tests: the JSON chunk of a .glb, and the Khronos glTF-Validator
(the ``gltf-validator`` npm package, run by Node.js through tests/validate_gltf.js).

The package is installed once into a cache folder outside the checkout
(``$LQLOD_GLTF_VALIDATOR_DIR``, else ``~/.cache/lqlod-gltf-validator``) at the version
pinned below. Without Node.js or npm, or when the install fails (offline), the test
asking for it is skipped, saying why.
"""
from __future__ import annotations

import json
import os
import shutil
import struct
import subprocess
from pathlib import Path

import pytest

VALIDATOR_PACKAGE = "gltf-validator@2.0.0-dev.3.10"
SCRIPT = Path(__file__).resolve().parent / "validate_gltf.js"


def glb_json(path) -> dict:
    """The JSON chunk of a .glb (header, then the first chunk, which the spec makes JSON)."""
    data = Path(path).read_bytes()
    magic, version, _ = struct.unpack_from("<4sII", data, 0)
    assert magic == b"glTF" and version == 2, f"{path} is not a glTF 2 binary"
    length, kind = struct.unpack_from("<I4s", data, 12)
    assert kind == b"JSON", f"{path}: first chunk is {kind!r}, not JSON"
    return json.loads(data[20:20 + length])


def validator_dir() -> Path:
    """The folder with node_modules/gltf-validator, installed there if missing; skips the
    calling test when Node.js/npm are missing or the install fails."""
    folder = Path(os.environ.get("LQLOD_GLTF_VALIDATOR_DIR") or Path.home() / ".cache" / "lqlod-gltf-validator")
    if shutil.which("node") is None:
        pytest.skip("Node.js (node) is not on PATH: the Khronos glTF-Validator (npm gltf-validator) cannot run")
    if not (folder / "node_modules" / "gltf-validator" / "package.json").is_file():
        if shutil.which("npm") is None:
            pytest.skip("npm is not on PATH: cannot install the Khronos glTF-Validator (npm gltf-validator)")
        folder.mkdir(parents=True, exist_ok=True)
        proc = subprocess.run(["npm", "install", "--prefix", str(folder), "--no-audit", "--no-fund",
                               VALIDATOR_PACKAGE], capture_output=True, text=True, timeout=300)
        if proc.returncode != 0:
            pytest.skip(f"could not install {VALIDATOR_PACKAGE} into {folder} (offline?): {proc.stderr[-500:]}")
    return folder


def validate(path) -> dict:
    """The glTF-Validator's report of ``path`` (its JSON: issues.numErrors, .messages, ...)."""
    folder = validator_dir()
    proc = subprocess.run(["node", str(SCRIPT), str(path)], capture_output=True, text=True, timeout=300,
                          env={**os.environ, "NODE_PATH": str(folder / "node_modules")})
    assert proc.returncode == 0, f"the glTF-Validator did not run on {path}: {proc.stderr[-2000:]}"
    return json.loads(proc.stdout)


def issue_summary(report: dict) -> str:
    issues = report["issues"]
    lines = [f"{issues['numErrors']} errors, {issues['numWarnings']} warnings, {issues['numInfos']} infos, "
             f"{issues['numHints']} hints"]
    lines += [f"  [{m['severity']}] {m['code']} {m.get('pointer', '')}: {m['message']}" for m in issues["messages"]]
    return "\n".join(lines)
