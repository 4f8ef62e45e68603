# SPDX-License-Identifier: GPL-3.0-or-later
"""How messages name several things: the few first, then how many more."""
from __future__ import annotations


def quoted_names(names, most: int = 6) -> str:
    """'"A", "B", "C"' for ``names``, the first ``most`` of them and "and N more" beyond."""
    names = list(names)
    shown = ", ".join(f'"{n}"' for n in names[:most])
    return shown + (f" and {len(names) - most} more" if len(names) > most else "")
