# SPDX-License-Identifier: GPL-3.0-or-later
"""The one place the add-on imports the pure-NumPy ``core`` package from.

Installed in Blender, ``addon`` and ``core`` are sibling subpackages of the extension's
root package (``bl_ext.<repo>.line_quadric_lod``), so from here (``<root>.addon.pure``)
``core`` is reached relatively. Tests, benches and the command line put the repository
root on sys.path instead and import ``addon`` as a top-level package, which has no parent
for ``...`` to reach; there ``core`` is itself top-level. Deciding by our package name
rather than by catching ImportError keeps a genuine import error inside core visible
instead of silently falling back to a different copy of it.
"""
if __package__ and __package__.count(".") >= 2:  # <root>.addon.pure
    from ... import core
else:  # ``addon`` imported as a top-level package (tests, benches, command line)
    import core

__all__ = ["core"]
