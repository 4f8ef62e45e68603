"""A stand-in for Blender's UILayout that records what a panel's ``draw()`` asks for.

Blender draws panels only in a window, and the ``bpy`` module has none. Running a
panel's own ``draw(context)`` with a :class:`LayoutRecorder` as ``self.layout`` gives the
panel's content as data instead: the layouts (box, column, row, grid_flow, ...) with
their ``active`` flags, and for every item what Blender would show, taken from RNA:
a property's UI name (or the ``text=`` override) and current value formatted as
Blender formats it, an enum's item names, an operator button's ``bl_label``.

Used by bench/figures/fig_panel.py, which draws the recording as a picture of the panel, and
by tests/test_addon_monkey.py, which checks that the panel names only real properties
and operators and greys out what it should. Needs a running ``bpy`` only when
recording (properties are read from the objects passed to ``prop``); :func:`walk` and
:func:`to_dict` output are plain data.

Every call is also appended to ``log`` as a tuple, in draw order:
``("prop", name)``, ``("prop_search", name)``, ``("operator", idname)``,
``("label", text)`` and ``("set", idname, property, value)`` for an operator
button's properties.
"""
from __future__ import annotations

import inspect
import types

# Blender shows at most this many decimals (UI_PRECISION_FLOAT_MAX).
_MAX_PRECISION = 6


def format_float(value: float, precision: int) -> str:
    """A float as a Blender field shows it: ``precision`` decimals, more (up to 6) when
    the value is too small to show otherwise (0.0001 at precision 2 is not "0.00")."""
    value = float(value)
    while 0.0 < abs(value) < 10.0 ** -precision and precision < _MAX_PRECISION:
        precision += 1
    return f"{value:.{precision}f}"


def describe_property(data, name: str) -> dict:
    """What a field for ``data.<name>`` shows: UI name, type and the current value."""
    props = data.bl_rna.properties
    if name not in props:
        raise AttributeError(f"panel draws unknown property {name!r} of {data}")
    rna = props[name]
    value = getattr(data, name)
    item = {"prop": name, "name": rna.name, "type": rna.type, "subtype": rna.subtype}
    if rna.type == 'FLOAT':
        item["value"] = float(value)
        item["display"] = format_float(value, rna.precision)
        if rna.subtype == 'FACTOR':  # drawn as a slider, filled over the soft range
            lo, hi = rna.soft_min, rna.soft_max
            item["fraction"] = min(max((value - lo) / (hi - lo), 0.0), 1.0) if hi > lo else 0.0
    elif rna.type == 'INT':
        item["value"] = int(value)
        item["display"] = str(int(value))
    elif rna.type == 'BOOLEAN':
        item["value"] = bool(value)
        item["display"] = ""
    elif rna.type == 'ENUM':
        names = {i.identifier: i.name for i in rna.enum_items}
        item["value"] = value
        item["display"] = names.get(value, str(value))
        item["items"] = [[i.identifier, i.name] for i in rna.enum_items]
    else:
        item["value"] = str(value)
        item["display"] = str(value)
    return item


class OperatorButton:
    """What ``layout.operator()`` returns: setting a property it lacks raises, as in Blender."""

    def __init__(self, rna, item: dict, log: list):
        object.__setattr__(self, "_rna", rna)
        object.__setattr__(self, "_item", item)
        object.__setattr__(self, "_log", log)

    def __setattr__(self, name, value):
        if name not in self._rna.properties:
            raise AttributeError(f"{self._item['idname']} has no property {name!r}")
        self._item["props"][name] = value
        self._log.append(("set", self._item["idname"], name, value))


class LayoutRecorder:
    """Records the UILayout calls a panel's draw() makes (the subset panels here use)."""

    def __init__(self, kind: str = "layout", log=None, **options):
        self.kind = kind
        self.options = options  # align, columns, ... as passed
        self.log = [] if log is None else log
        self.children = []  # LayoutRecorder or item dicts, in draw order
        self.active = True
        self.enabled = True
        self.alert = False
        self.use_property_split = False
        self.use_property_decorate = True
        self.scale_x = self.scale_y = 1.0

    # --- sub-layouts
    def _sub(self, kind, **options):
        child = LayoutRecorder(kind, self.log, **options)
        self.children.append(child)
        return child

    def row(self, align=False, **kw):
        return self._sub("row", align=align)

    def column(self, align=False, **kw):
        return self._sub("column", align=align)

    def box(self):
        return self._sub("box")

    def split(self, factor=0.0, align=False):
        return self._sub("split", factor=factor, align=align)

    def grid_flow(self, row_major=False, columns=0, even_columns=False, even_rows=False, align=False):
        return self._sub("grid_flow", row_major=row_major, columns=columns, even_columns=even_columns,
                         align=align)

    def column_flow(self, columns=0, align=False):
        return self._sub("column_flow", columns=columns, align=align)

    # --- items
    def _item(self, item: dict) -> dict:
        self.children.append(item)
        return item

    def prop(self, data, property, text=None, icon='NONE', expand=False, **kw):
        item = describe_property(data, property)
        self.log.append(("prop", property))
        return self._item({"kind": "prop", **item, "text": item["name"] if text is None else text,
                           "expand": bool(expand), "icon": icon})

    def prop_search(self, data, property, search_data, search_property, text=None, icon='NONE', **kw):
        if search_property not in search_data.bl_rna.properties:
            raise AttributeError(f"panel searches unknown property {search_property!r} of {search_data}")
        item = describe_property(data, property)
        self.log.append(("prop_search", property))
        return self._item({"kind": "prop_search", **item, "text": item["name"] if text is None else text,
                           "search": search_property, "icon": icon})

    def operator(self, operator, text=None, icon='NONE', **kw):
        import bpy

        module, name = operator.split(".")
        rna = getattr(getattr(bpy.ops, module), name).get_rna_type()  # KeyError if not registered
        cls = getattr(bpy.types, rna.identifier, None)
        label = getattr(cls, "bl_label", None) or rna.name
        self.log.append(("operator", operator))
        item = self._item({"kind": "operator", "idname": operator, "text": label if text is None else text,
                           "icon": icon, "props": {}})
        return OperatorButton(rna, item, self.log)

    def label(self, text="", icon='NONE', **kw):
        self.log.append(("label", text))
        self._item({"kind": "label", "text": text, "icon": icon})

    def separator(self, factor=1.0, **kw):
        self._item({"kind": "separator", "factor": factor})

    def to_dict(self) -> dict:
        """The recording as plain data (JSON-serialisable)."""
        return {"kind": self.kind, **self.options, "active": self.active, "enabled": self.enabled,
                "children": [c.to_dict() if isinstance(c, LayoutRecorder) else dict(c) for c in self.children]}


class _PanelSelf:
    """``self`` for a panel's draw(): the recorder as ``layout``, the rest from the class
    (plain methods bound to this stand-in, static and class methods as they are)."""

    def __init__(self, panel_cls, layout):
        self._cls = panel_cls
        self.layout = layout

    def __getattr__(self, name):
        raw = inspect.getattr_static(self._cls, name)
        value = getattr(self._cls, name)
        if inspect.isfunction(raw):
            return types.MethodType(value, self)
        return value


def record_panel(panel_cls, context) -> LayoutRecorder:
    """Run ``panel_cls.draw(context)`` against a recorder; returns the root layout."""
    root = LayoutRecorder()
    panel_cls.draw(_PanelSelf(panel_cls, root), context)
    return root


def walk(node: dict, active: bool = True, enabled: bool = True):
    """Yield (item, active, enabled) for every item of a recording (``to_dict()`` form), in
    draw order; a layout greyed out or disabled greys out or disables all it contains."""
    active = active and node.get("active", True)
    enabled = enabled and node.get("enabled", True)
    for child in node["children"]:
        if "children" in child:
            yield from walk(child, active, enabled)
        else:
            yield child, active, enabled
