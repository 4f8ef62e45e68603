# SPDX-License-Identifier: GPL-3.0-or-later
"""A LOD run over several objects whose expensive part can go to a worker thread.

A blocking operator never sees the Esc key (Blender handles events between operator
calls), so cancelling needs a modal operator that keeps the UI loop running while the
work happens elsewhere. Only the core is thread-safe, not bpy, hence the split from
lod.py: Blender data is read here on the main thread (constructor), the simplification
and measuring run in a thread (start) or inline (run), and Blender data is written only
by commit(), on the main thread, after everything is done. A cancelled or failed job
never reaches commit(), so the scene stays exactly as it was.

The panel and the command line both drive their runs through LodJob: the panel with
one settings for every selected object and a fraction for its progress bar, the command
line with settings per object (importance differs between the assets of a batch) and an
:class:`ObjectObserver` for its per-object progress lines.

Objects whose LODs would be identical are made once: a mesh datablock used by several
objects (instances, linked duplicates, a CAD assembly's repeated parts) with equal
settings and nothing of the object's own shaping the input (lod.shared_mesh_key: no
evaluated geometry modifiers, no armature, no bake) is read, simplified and measured once
per level, as one group; commit gives every object of the group LOD objects of its own
(names, transform, parent, collection, object-linked materials) that share the group's
LOD meshes. ``inputs`` and ``outputs`` are per group (what is computed, what the observer
and the progress count); ``objects``, ``object_inputs`` and ``object_outputs`` per object,
and commit() returns one report per object, in the order the objects were given.

Several objects with ``asset_budget`` on (the default) are one asset (addon/asset.py):
a chain by triangles is the asset's, split over the groups by error before they are
simplified (the first share of run()'s progress); deviations and switch numbers are the
asset's; ``asset_report`` holds its entry after commit().
"""
from __future__ import annotations

import threading
from typing import Callable, Optional, Sequence, Union

import numpy as np

from . import asset as asset_set
from .pure import deviation_search
from .pure import level_deviation
from .pure import measure
from . import lod
from . import mesh_io
from . import object_importance
from .pure._core import core
from .pure.phases import LodInput, LodOutput
from .pure.settings import LodCancelled, LodError, LodSettings


# Source Shape Keys over an asset: one reference for the keys' motion over all parts, in
# scene units (asset.key_importance), rather than each mesh's own.
ASSET_KEY_REFERENCE = True


# An asset's chain by triangles is one core run over all its parts (core.assembly) where
# the parts allow it (LodJob.together); False splits the budget by error curves and runs
# each part alone (asset_set.split_budget), as before.
ONE_RUN = True


def _unchanged(before, after) -> bool:
    """Whether a part's level is its level before, untouched by the asset's run since."""
    return (len(before.faces) == len(after.faces) and np.array_equal(before.face_origin, after.face_origin)
            and np.array_equal(before.faces, after.faces) and np.array_equal(before.vertices, after.vertices))


def _set_part_samples(inputs: list, matrices: list) -> None:
    """How densely each part of an asset is measured (LodInput.part_samples): its share of
    the area the asset draws (in scene units through the largest scale it is drawn at,
    once per object drawing it) of what the asset would get as one surface."""
    drawn = np.array([measure.mesh_area(i.data.vertices, i.data.faces) * asset_set.matrix_scale_max(placed) ** 2
                      * len(placed) for i, placed in zip(inputs, matrices)])
    total = float(drawn.sum())
    triangles = sum(len(i.data.faces) * len(placed) for i, placed in zip(inputs, matrices))
    for lod_input, area in zip(inputs, drawn):
        share = float(area / total) if total > 0 else 1.0 / len(inputs)
        lod_input.part_samples = deviation_search.part_samples(share, triangles, len(lod_input.data.faces))


class ObjectObserver:
    """What :meth:`LodJob.run` tells about each object, on the thread that runs it.
    The hooks here do nothing; override the ones you need."""

    def splitting(self, parts: int, targets: list) -> None:
        """An asset's budget, ``targets`` per level, is being split over ``parts`` groups."""

    def started(self, lod_input: LodInput) -> None:
        pass

    def progress(self, fraction: float) -> None:
        """How far the current object is, 0 to 1 (lod.compute's fraction)."""

    def finished(self, lod_output: LodOutput) -> None:
        pass


def _prepare(context, obj, settings: LodSettings, chain_labels: tuple, asset=None,
             importance_optional: bool = False) -> LodInput:
    try:
        return lod.prepare(context, obj, settings, chain_labels, asset, importance_optional)
    except LodError as ex:
        # With several objects, a message such as "the first LOD's target ... is not
        # smaller than the mesh" must say which one it is about.
        name = getattr(obj, "name", None)
        if name is None or f'"{name}"' in str(ex):
            raise
        raise LodError(f'"{name}": {ex}') from ex


class LodJob:
    def __init__(self, context, objects,
                 settings: Union[LodSettings, Sequence[LodSettings]], chain_labels: tuple = (),
                 asset_name: Optional[str] = None, named: bool = False):
        """``settings``: one for every object, or a sequence with one per object;
        ``chain_labels``: how messages name an explicit chain (lod.prepare); ``asset_name``:
        what an asset's glTF level nodes are named after (default: asset_set.default_name);
        ``named``: the objects were named one by one (the command line's --objects), so a
        helper among them (lod.helper_role) is a part as asked.
        Reads Blender data: main thread only. Raises LodError for bad input, naming the object."""
        objects = list(objects)
        per_object = list(settings) if isinstance(settings, (list, tuple)) else [settings] * len(objects)
        if len(per_object) != len(objects):
            raise ValueError(f"{len(per_object)} settings for {len(objects)} objects")
        self.objects = []  # the objects' names, in the order given
        self.groups = []  # per group: the names of its objects (the first is its input's source)
        self._group_of = []  # per object: the index of its group
        self.inputs = []  # per group: what compute() gets
        shared = {}  # lod.shared_mesh_key -> [(settings, group index)]
        for ob in objects:
            lod.check_source(ob)
        # A helper of the asset (a Boolean cutter, an object disabled in renders, a
        # collision mesh) and a part with nothing to simplify (no faces, or none its
        # modifiers leave) are left out of an asset with a note, as the command line skips
        # them: they draw nothing of it. Alone, an object is simplified as asked, or
        # prepare() says why it cannot be.
        self.skipped = []  # notes: '"name" skipped: why'
        if len(objects) > 1:
            scene, depsgraph = mesh_io.scene_and_depsgraph(context)
            helpers = None if named else lod.scene_helpers(scene.objects)
            why = [lod.left_out(ob, depsgraph, s.use_modifiers, helpers) for ob, s in zip(objects, per_object)]
            if all(why):
                raise LodError(f"none of the {len(objects)} objects is a part to simplify: "
                               + "; ".join(f'"{ob.name}": {w}' for ob, w in zip(objects, why)))
            self.skipped = [f'"{ob.name}" skipped: {w}' for ob, w in zip(objects, why) if w]
            objects = [ob for ob, w in zip(objects, why) if not w]
            per_object = [s for s, w in zip(per_object, why) if not w]
        self.asset = None
        if asset_set.is_asset(objects, per_object):
            self.asset = asset_set.asset_of(objects, asset_name or asset_set.default_name(objects))
        self.asset_report: Optional[dict] = None  # after commit(), for an asset
        self.asset_notes: list = []  # what the report says of the asset as a whole (its "warnings")
        self._matrices = []  # per group: its objects' world matrices (asset_set.split_budget)
        for ob, s in zip(objects, per_object):
            key = lod.shared_mesh_key(ob, s)
            group = None
            if key is not None:
                group = next((g for other, g in shared.get(key, ()) if other == s), None)
            if group is None:
                self.inputs.append(_prepare(context, ob, s, chain_labels, self.asset,
                                            importance_optional=len(objects) > 1))
                self._matrices.append([])
                group = len(self.groups)
                self.groups.append([])
                if key is not None:
                    shared.setdefault(key, []).append((s, group))
            else:
                lod.check_source(ob)  # its mesh was read for the group's first object
            self.groups[group].append(ob.name)
            self._matrices[group].append(asset_set.world_matrix(ob))
            self.objects.append(ob.name)
            self._group_of.append(group)
        self._check_importance(objects, per_object)
        if self.asset is not None:
            _set_part_samples(self.inputs, self._matrices)
        if self.asset is not None:
            asset_set.key_importance(self.inputs, self._matrices, shared_reference=ASSET_KEY_REFERENCE)
        # The asset's triangle count per level (a chain by triangles), split in run().
        self._asset_targets = None
        if self.asset is not None and per_object[0].deviation_chain() is None:
            # What the asset draws: a mesh counts once per object using it.
            total = sum(len(i.data.faces) * len(m) for i, m in zip(self.inputs, self._matrices))
            labels = tuple(chain_labels) or ("ratios", "triangle counts")
            try:
                self._asset_targets = per_object[0].targets(total, *labels[:2], source="the asset")
            except LodError as ex:
                raise LodError(f"the asset of {len(objects)} objects ({len(self.inputs)} meshes): {ex}") from ex
        self.outputs = []  # per group, after run()
        self.fraction = 0.0
        self.error: Optional[BaseException] = None
        self._cancel = threading.Event()
        self._thread: Optional[threading.Thread] = None

    def _check_importance(self, objects: list, per_object: list) -> None:
        """An importance source on several objects: those without it were made without
        importance (lod.prepare, with a note); LodError when none of them has it."""
        asked = [(ob.name, s, g) for ob, s, g in zip(objects, per_object, self._group_of)
                 if s.importance_source != 'NONE']
        if len(objects) > 1 and asked and all(self.inputs[g].settings.importance_source == 'NONE'
                                              for _, _, g in asked):
            raise LodError(object_importance.none_has_source(asked[0][1], [name for name, _, _ in asked]))

    @property
    def object_inputs(self) -> list:
        """Per object, its group's LodInput (the same one for the objects of a group)."""
        return [self.inputs[g] for g in self._group_of]

    @property
    def object_outputs(self) -> list:
        """Per object, its group's LodOutput (after run())."""
        return [self.outputs[g] for g in self._group_of]

    def run(self, progress: Optional[Callable[[float], object]] = None,
            observer: Optional[ObjectObserver] = None) -> None:
        """Compute every group's LODs in the calling thread; raises LodCancelled/LodError.
        ``progress`` gets the fraction of the whole job, ``observer`` each group's (started
        with the group's input, whose source is its first object)."""
        observer = observer or ObjectObserver()
        count = len(self.inputs)
        first = 0.0  # the share of the progress the asset's split takes
        if self._asset_targets is not None:
            if count > 1:
                observer.splitting(count, self._asset_targets)
                first = self._run_together(progress) if self.together() else self._split_budget(progress)
            else:
                # One mesh drawn by every object of the asset: each copy gets its share of
                # what the asset draws (two objects sharing a monkey got the asset's whole
                # budget per copy, one level late; three, a target above the mesh's own).
                copies = len(self._matrices[0])
                self.inputs[0].targets = [max(1, t // copies) for t in self._asset_targets]
        elif self.asset is not None and self._one_run_allowed():
            first = self._search_together(progress)
        for index, lod_input in enumerate(self.inputs):
            def step(fraction, index=index):
                self.fraction = first + (1.0 - first) * (index + fraction) / count
                if progress is not None:
                    progress(self.fraction)
                observer.progress(fraction)
                return not self._cancel.is_set()

            observer.started(lod_input)
            output = lod.compute(lod_input, step)
            observer.finished(output)
            self.outputs.append(output)
        self.fraction = 1.0

    def _first_share(self, share: float, progress):
        """The progress callback of the asset's first step (its one run or search, or the
        split), which takes ``share`` of the job's progress: it reports the job's fraction
        and says whether to go on."""
        def step(fraction):
            self.fraction = share * fraction
            if progress is not None:
                progress(self.fraction)
            return not self._cancel.is_set()
        return step

    # The asset's one core run (_run_together), against the parts' measuring afterwards.
    TOGETHER_SHARE = 0.5

    def together(self) -> bool:
        """Whether the asset's parts are simplified in one core run (core.assembly): a chain
        by triangles, with nothing that needs a run per part (painted limits, whose
        distances are to the part's own surface; Source Armature, whose levels are
        refitted and remade per part) and with the options one run has one of alike."""
        if self._asset_targets is None or any(i.deviations is not None for i in self.inputs):
            return False
        return self._one_run_allowed()

    def _one_run_allowed(self) -> bool:
        """Whether the parts may share one core run: two or more, nothing that needs a run
        per part, the options one run has one of alike."""
        if not ONE_RUN or len(self.inputs) < 2:
            return False
        if any(i.limit is not None or i.poses is not None for i in self.inputs):
            return False
        try:
            core.assembly.shared_options([i.core_options for i in self.inputs])
        except ValueError:
            return False
        return True

    def _run_together(self, progress) -> float:
        """Simplify every part in one core run to the asset's targets (core.assembly: each
        part in scene units through the largest scale it is drawn at, counted once per
        object drawing it) and give each part its levels (LodInput.chain); returns the
        share of the progress it took."""
        assembly = core.assembly

        step = self._first_share(self.TOGETHER_SHARE, progress)
        parts = [assembly.Part(i.data.vertices, i.data.faces, i.core_options,
                               asset_set.matrix_scale_max(placed), len(placed))
                 for i, placed in zip(self.inputs, self._matrices)]
        try:
            vertices, faces, options, layout = assembly.combine(parts)
            results = core.simplify_chain(vertices, faces, self._asset_targets, options, progress=step)
        except core.SimplifyCancelled as ex:
            raise LodCancelled("cancelled") from ex
        except ValueError as ex:
            raise LodError(f"simplifying the asset's {len(parts)} meshes together: {ex}") from ex
        per_level = [assembly.split(r, layout) for r in results]
        for p, lod_input in enumerate(self.inputs):
            chain = []
            for level in per_level:
                part = level[p]
                if part is None:
                    break
                if chain and _unchanged(chain[-1], part):
                    part = chain[-1]  # (one mesh, measured once: lod.compute repeats it)
                chain.append(part)
            counts = np.array([0 if level[p] is None else len(level[p].faces) for level in per_level])
            lod_input.targets, note = asset_set.part_targets(counts, len(lod_input.data.faces))
            lod_input.chain = chain
            if note:
                lod_input.warnings.append(note)
        for k, r in enumerate(results, start=1):
            if r.stats.stop_reason != core.STOP_TARGET:
                why = core.STOP_REASON_TEXT.get(r.stats.stop_reason, r.stats.stop_reason)
                self.asset_notes.append(
                    f"the asset's LOD{k} stopped above its budget of {self._asset_targets[k - 1]} triangles: {why}")
        return self.TOGETHER_SHARE

    def _search_together(self, progress) -> float:
        """An asset's chain by deviation (or screen size): searched in one core run over
        every part (deviation_search.by_deviation_together), each part given its levels,
        their requested deviations and measurements (LodInput.chain); where the run does
        not meet a level, the parts are searched one by one (lod.compute) as before.
        Returns the share of the progress it took."""
        step = self._first_share(self.TOGETHER_SHARE, progress)
        settings = self.inputs[0].settings
        try:
            found = deviation_search.by_deviation_together(
                self.inputs, [asset_set.matrix_scale_max(placed) for placed in self._matrices],
                [len(placed) for placed in self._matrices], settings.deviations(self.asset.diagonal),
                self.asset_notes, progress=step, cancelled=self._cancel.is_set)
        except core.SimplifyCancelled as ex:
            raise LodCancelled("cancelled") from ex
        except ValueError as ex:
            raise LodError(f"searching the asset's {len(self.inputs)} meshes together: {ex}") from ex
        if found is None:
            return 0.0
        for lod_input, (chain, measured) in zip(self.inputs, found):
            for k in range(len(chain)):
                before = chain[k - 1] if k else None
                if before is not None and len(before.faces) <= len(chain[k].faces):
                    # No coarser than the level before, which is within a smaller bound (the
                    # asset's levels may come from different runs: deviation_targets): that
                    # one mesh, measured once (lod.compute repeats it).
                    chain[k] = before
                if chain[k] is before or (k == 0 and len(chain[0].faces) == len(lod_input.data.faces)):
                    lod_input.warnings.append(deviation_search.repeat_note(k + 1, lod_input.deviations[k]))
            lod_input.chain = chain
            lod_input.chain_requested = list(lod_input.deviations[:len(chain)])
            lod_input.chain_measured = measured
            lod_input.targets = [len(level.faces) for level in chain]
        return self.TOGETHER_SHARE

    # The split runs the core once per part down its error curve: about as long as
    # simplifying the parts to their shares afterwards, which also measures.
    SPLIT_SHARE = 0.4

    def _split_budget(self, progress) -> float:
        """Give every group its share of the asset's targets (asset_set.split_budget);
        returns the share of the progress it took."""
        step = self._first_share(self.SPLIT_SHARE, progress)
        try:
            counts = asset_set.split_budget(self.inputs, self._matrices, self._asset_targets, progress=step)
        except core.SimplifyCancelled as ex:
            raise LodCancelled("cancelled") from ex
        except ValueError as ex:
            raise LodError(f"splitting the asset's budget over its parts: {ex}") from ex
        for column, lod_input in zip(counts.T, self.inputs):
            lod_input.targets, note = asset_set.part_targets(column, len(lod_input.data.faces))
            if note:
                lod_input.warnings.append(note)
        return self.SPLIT_SHARE

    def _run_in_thread(self) -> None:
        try:
            self.run()
        except BaseException as ex:  # handed to the main thread, which reports it
            self.error = ex

    def start(self) -> None:
        """Run :meth:`run` in a daemon thread; poll :attr:`done`."""
        self._thread = threading.Thread(target=self._run_in_thread, name="line_quadric_lod", daemon=True)
        self._thread.start()

    def cancel(self) -> None:
        """Ask the run to stop at its next progress report (core.heartbeat: a quarter second
        apart inside long passes)."""
        self._cancel.set()

    @property
    def cancelled(self) -> bool:
        return self._cancel.is_set()

    @property
    def done(self) -> bool:
        return self._thread is None or not self._thread.is_alive()

    def wait(self, timeout: Optional[float] = None) -> bool:
        if self._thread is not None:
            self._thread.join(timeout)
        return self.done

    def commit(self, context) -> list:
        """Write and link the LODs (main thread); one report per object, in the order the
        objects were given (lod.commit: the objects of a group share its LOD meshes).
        Raises the worker's error, or LodCancelled if the job was cancelled, before
        touching any data."""
        if not self.done:
            raise RuntimeError("the LOD job is still running")
        if self.error is not None:
            raise self.error
        if self._cancel.is_set():
            raise LodCancelled("cancelled")
        if len(self.outputs) != len(self.inputs):
            raise RuntimeError("the LOD job has not run")
        if self.asset is None:
            return lod.commit(context, self.object_outputs, self.objects)
        import bpy

        chains = [(out, asset_set.world_scale(bpy.data.objects[name]))
                  for out, name in zip(self.object_outputs, self.objects) if name in bpy.data.objects]
        # The heat maps of a level in one scale for all the parts (Deviation Colors).
        first = {}  # each output once, with its first object's scale (its meshes are shared)
        for out, unit in chains:
            first.setdefault(id(out), (out, unit))
        level_deviation.share_scales(list(first.values()))
        eps = asset_set.level_deviations(chains)
        switch = None if eps is None else asset_set.switch_data(
            self.asset, asset_set.level_deviations(chains, for_switch=True), self.inputs[0].settings)
        reports = lod.commit(context, self.object_outputs, self.objects, switch=switch)
        asset_set.mark(self.asset, reports)
        self.asset_report = asset_set.report(self.asset, reports, switch, eps, self.asset_notes)
        return reports
