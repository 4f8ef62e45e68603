# SPDX-License-Identifier: GPL-3.0-or-later
"""How messages name several things: the few first, then how many more."""
from __future__ import annotations


def listed_names(names, most: int) -> str:
    """'A, B, C' for ``names``: the first ``most`` of them, then "and N more"."""
    names = list(names)
    return ", ".join(names[:most]) + (f" and {len(names) - most} more" if len(names) > most else "")


def quoted_names(names, most: int = 6) -> str:
    """listed_names with each name in double quotes: '"A", "B", "C"'."""
    return listed_names([f'"{n}"' for n in names], most)
