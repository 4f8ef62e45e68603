# SPDX-License-Identifier: GPL-3.0-or-later
"""The run's console: progress lines on stderr (unless --quiet) and error lines (always).
stdout is kept for the table at the end, so a run's result can be piped. No bpy.
"""
from __future__ import annotations

import sys
import threading


class Console:
    """Progress lines on stderr (unless quiet) and error lines (always)."""

    def __init__(self, quiet: bool):
        self.quiet = quiet
        self.lock = threading.Lock()

    def progress(self, message: str) -> None:
        if not self.quiet:
            self._write(message)

    def redraw(self, message: str) -> None:
        """Replace the current terminal line (a progress bar); "" clears it."""
        with self.lock:
            sys.stderr.write("\r\x1b[2K" + message + ("" if message else "\r"))
            sys.stderr.flush()

    def error(self, message: str) -> None:
        self._write(f"error: {message}")

    def _write(self, message: str) -> None:
        with self.lock:
            sys.stderr.write(message + "\n")
            sys.stderr.flush()


def duration(seconds: float) -> str:
    if seconds < 1.0:
        return "<1 s"
    if seconds < 90:
        return f"{seconds:.0f} s"
    return f"{int(seconds // 60)} min {int(seconds % 60):02d} s"
