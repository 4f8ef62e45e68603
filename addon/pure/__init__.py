# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's Blender-independent part: NumPy, the core and the standard library only.

Everything here runs without Blender (tests, benches, a worker thread), and
tests/test_core_purity.py keeps it that way: no Blender module is imported, and relative
imports stay inside this package or reach ``core`` (through ``_core``). The Blender side
(``addon/``) reads Blender data into these modules' arrays and writes their results back.

Modules (one idea each):
    _core           where ``core`` is imported from (extension vs. top-level layout)
    phases          LodInput and LodOutput: what the LOD run's phases hand on (addon/lod.py)
    compute         the compute phase: simplify and measure a LodInput into a LodOutput
    settings        SETTINGS, the one table of the settings, and what derives from it: LodSettings,
                    the command line's options; LodError, LodCancelled
    options         the core.Options of a run: the settings table's fields (core_options_of),
                    the mesh's attributes, feature edges, importance and poses (mesh_options)
    importance      what the Importance settings mean as core parameters, and how dense the
                    painted region came out (the report)
    edges           edge bookkeeping (feature edges, sharp edges, seams)
    mesh_data       MeshData, the arrays a mesh is read into and written from, and the
                    corner normals Blender will shade them with
    rebuild         a LOD's MeshData rebuilt from the core's result (attributes, sharp
                    edges and seams carried back)
    measure         surface deviation and the LOD report numbers (the closest-point tree
                    is handed in: addon/bvh.py)
    deviation_targets  the search for LODs by deviation, over any measuring function
    deviation_search   LOD levels by measured deviation: the core's tracked bound (the
                    controls, lean, the planes' placement), then the ladder of rungs
    skin_fit        LOD skin weights fitted to the rig's sample poses; coarse levels checked
                    against a run without the poses
    key_deviation   each shape key's deviation on a LOD, and the keys' offsets
    level_deviation where a LOD differs: per vertex (the heat map), per material and painted
                    region (the report), the posed numbers' summary
    limits          painted limits: how far each LOD may move, per vertex; the runs that hold
                    a chain to them
    switch_distances  the engines' switch distances from a chain's measured error
"""
