"""Keeping a large run's memory in the process instead of asking the kernel for it anew.

Every pass allocates and frees arrays the size of the mesh. Under glibc's malloc an array
above 32 MB (the largest mmap threshold it allows; a (k, 3) float64 array at about 1.4M
rows) is always a fresh mmap, so every pass pays for zeroing its pages again, and NumPy
asks the kernel for huge pages on every array of 4 MB and more, which with the usual
``defrag=madvise`` setting may compact memory synchronously while the array is first
written. On the ogre subdivided to 7.9M faces, to 10 % in a plain Python process, that was
41 of 100 s in the kernel, and the same bench run an hour apart took 62 s and 90 s.

For the run, large arrays come from malloc's heap (no mmap, no trimming) without huge
pages; afterwards the settings go back and the heap's free memory is returned to the
system (``malloc_trim``), so nothing is kept after the run. Only where glibc's malloc
serves the process: Blender's own binary brings its own allocator, and other systems are
left as they are.
"""
from __future__ import annotations

import contextlib
import ctypes
import sys

# Faces from which it pays: 15 % less time on the 2M-face ogre, 34 % on the 7.9M one; the
# same or slower on the 124k ogre and the 69k bunny, whose arrays stay under 32 MB.
MIN_FACES = 1_000_000

# glibc's mallopt parameters (malloc.h) and the defaults the run restores.
_M_TRIM_THRESHOLD, _M_MMAP_MAX = -1, -4
_DEFAULT_TRIM_THRESHOLD = 128 * 1024
_DEFAULT_MMAP_MAX = 65536
_INT_MAX = 2**31 - 1  # mallopt takes a C int


@contextlib.contextmanager
def reused_memory(faces: int):
    """Within the block, large arrays reuse the process's own freed memory (see the
    module's docstring) when ``faces`` >= MIN_FACES and glibc's malloc is in use; the
    settings are restored and free memory released on leaving, also on an exception."""
    libc = _glibc_allocator() if faces >= MIN_FACES else None
    if libc is None:
        yield
        return
    hugepage = _hugepage_switch()
    before = hugepage(False) if hugepage else None
    libc.mallopt(_M_MMAP_MAX, 0)
    libc.mallopt(_M_TRIM_THRESHOLD, _INT_MAX)
    try:
        yield
    finally:
        libc.mallopt(_M_MMAP_MAX, _DEFAULT_MMAP_MAX)
        libc.mallopt(_M_TRIM_THRESHOLD, _DEFAULT_TRIM_THRESHOLD)
        if hugepage:
            hugepage(before)
        libc.malloc_trim(0)


def _glibc_allocator():
    """glibc, when its malloc is the one this process uses; else None."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        libc = ctypes.CDLL("libc.so.6")
        process = ctypes.CDLL(None)
        libc.mallopt, libc.malloc_trim  # noqa: B018  (musl and others have neither)
    except (OSError, AttributeError):
        return None
    # A binary that links another allocator (Blender's jemalloc) exports its own malloc.
    address = ctypes.cast(process.malloc, ctypes.c_void_p).value
    return libc if address == ctypes.cast(libc.malloc, ctypes.c_void_p).value else None


def _hugepage_switch():
    """NumPy's switch for asking huge pages (returns the previous setting), or None."""
    import numpy as np

    multiarray = getattr(getattr(np, "_core", None), "multiarray", None) or np.core.multiarray
    return getattr(multiarray, "_set_madvise_hugepage", None)
