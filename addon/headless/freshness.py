# SPDX-License-Identifier: GPL-3.0-or-later
"""Is an asset's LOD output up to date? A rerun of an interrupted batch skips what is.

After an asset's outputs are written, a small stamp beside the first of them records a
key: the input's content (and the files a .gltf or .obj pulls in), the options that shape
the output and the tool's version. A later run with the same key and every output still
there has nothing to do for that asset. Content, not modification times, because
asset libraries are copied, synced and checked out, which changes times and not bytes.
No bpy here.
"""
from __future__ import annotations

import functools
import hashlib
import json
import os
import re
from pathlib import Path
from urllib.parse import unquote
from typing import Optional

STAMP_SUFFIX = ".lqlod.json"
_CHUNK = 1 << 20


def _file_digest(path: Path, digest) -> None:
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(_CHUNK), b""):
            digest.update(block)


def companion_files(path: Path) -> list:
    """Files ``path`` loads besides itself: a .gltf's buffers and images, an .obj's
    material libraries (those that exist; embedded data: URIs are in the file itself)."""
    suffix = path.suffix.lower()
    names = []
    try:
        if suffix == ".gltf":
            data = json.loads(path.read_text(encoding="utf-8"))
            # URIs are percent-encoded ("my%20rock.bin").
            names = [unquote(item.get("uri", "")) for key in ("buffers", "images") for item in data.get(key, [])]
        elif suffix == ".obj":
            with open(path, encoding="utf-8", errors="replace") as fh:
                names = [name for line in fh if (m := re.match(r"\s*mtllib\s+(.+)", line))
                         for name in m.group(1).split()]
    except (OSError, ValueError, AttributeError):
        return []  # the importer will say what is wrong with the file itself
    files = []
    for name in names:
        if name and not name.startswith("data:"):
            candidate = (path.parent / name).resolve()
            if candidate.is_file():
                files.append(candidate)
    return files


@functools.lru_cache(maxsize=1)
def tool_fingerprint() -> str:
    """sha256 of this tool's own code (core/ and addon/): a new version, or any change to
    how LODs are made, makes every earlier output out of date."""
    root = Path(__file__).resolve().parents[2]
    digest = hashlib.sha256()
    for path in sorted([*root.glob("core/**/*.py"), *root.glob("addon/**/*.py")]):
        digest.update(str(path.relative_to(root)).encode() + b"\0")
        _file_digest(path, digest)
    return digest.hexdigest()


def asset_key(input_path: Optional[Path], options: dict) -> str:
    """sha256 over the tool's code, the options (JSON-able), the input's bytes and its
    companion files'."""
    digest = hashlib.sha256()
    digest.update(tool_fingerprint().encode())
    digest.update(json.dumps(options, sort_keys=True, default=str).encode())
    if input_path is not None:
        for path in [Path(input_path)] + companion_files(Path(input_path)):
            digest.update(path.name.encode() + b"\0")
            _file_digest(path, digest)
    return digest.hexdigest()


def stamp_path(outputs: list) -> Path:
    first = Path(outputs[0])
    return first.with_name("." + first.name + STAMP_SUFFIX)


def up_to_date(outputs: list, key: str) -> bool:
    """True if every output exists and the stamp beside them carries ``key``."""
    if not outputs or not all(Path(out).is_file() for out in outputs):
        return False
    try:
        stamp = json.loads(stamp_path(outputs).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return stamp.get("key") == key and sorted(stamp.get("outputs", [])) == sorted(Path(o).name for o in outputs)


def mark_done(outputs: list, key: str) -> None:
    """Write the stamp (atomically: a crash leaves the old stamp or none, never half)."""
    path = stamp_path(outputs)
    tmp = path.with_name(path.name + f".{os.getpid()}.tmp")
    tmp.write_text(json.dumps({"key": key, "outputs": sorted(Path(o).name for o in outputs)}), encoding="utf-8")
    os.replace(tmp, path)


def forget(outputs: list) -> None:
    """Drop the stamp before outputs are rewritten, so a run cut short in between is
    never taken for done."""
    try:
        stamp_path(outputs).unlink()
    except FileNotFoundError:
        pass
