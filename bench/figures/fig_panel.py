"""The panel walkthrough's pictures (docs/panel.md): the panel drawn from its own draw()
code, and renders of what its steps do to the built-in sample's Monkey.

    .venv/bin/python bench/figures/fig_panel.py [--size 400] [--samples 16]
      -> docs/images/panel_defaults.png, panel_importance.png, panel_last_run.png,
         panel_weights.png, panel_lod_chain.png

Why drawn and not a screenshot: the bpy module has no window, so Blender cannot draw its
interface. Instead this process registers the add-on (addon.register(), as Blender does
on enabling it), builds the sample scene of addon/sample.py, and runs the real
``VIEW3D_PT_line_quadric_lod.draw()`` of addon/panel.py against bench/figures/ui_recorder.py's
stand-in for UILayout. The recording holds every box, row and column with its ``active``
flag, each property's UI name and current value from RNA, and each button's ``bl_label``;
it is drawn here with matplotlib in the colours of Blender's default theme as bpy reports
them (Preferences > Themes), at Blender's 20 px unit, with DejaVu Sans instead of
Blender's Inter and without icons.

Panel states: the defaults with the Monkey active; after the real Paint Importance
operator (it selects the Monkey's painted group "LOD_Importance" as the source; strength
0.5 is the default); after the real Generate LODs operator, called with exactly
the properties the panel's button carries, with the default settings (the Last Run
report filled in).
Renders (bench/figures/render.py: Cycles on the CPU, shaded with wireframe, one camera): the
Monkey's "LOD_Importance" weights in Blender's weight-paint colours (blue 0, green 0.5,
red 1) beside the last LOD made without and with that importance (each LOD carries the
group, interpolated); the LOD chain made with the panel's defaults, LOD0 (the source) to
LOD3, with triangle counts and mean triangle quality (core.quality_summary).
Each line printed on stdout says what one picture shows and the numbers behind it;
bench/figures/fig_all.py copies them into docs/panel.md.
"""
from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

import fig_common as fc
import bpy
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.font_manager import FontProperties
from matplotlib.patches import PathPatch, Polygon
from matplotlib.path import Path as MplPath
from matplotlib.textpath import TextToPath

import addon
import core
import render as rd
from addon import panel, sample, vertex_groups
from addon.pure.settings import LodSettings
from blender_reference import mesh_arrays, stdout_to_stderr
from ui_recorder import record_panel, walk

GROUP = sample.IMPORTANCE_GROUP
GENERATE = "object.line_quadric_lod"
PAINTED = 0.5  # a triangle counts as painted when its vertices' mean weight is above this
BY_COUNT = 20000  # a Triangles value for the chain preview's other form
# Nearly frontal (Suzanne faces -Y), so the painted eyes and brow are in view.
VIEW = dict(direction=(0.35, -1.0, 0.3), up=(0, 0, 1))

# ----------------------------------------------------------------------------- the panel, drawn

U = 20  # Blender's UI unit: widget height in px at UI scale 1
PANEL_W = 300  # a sidebar of 15 units
OUTER = 6  # region margin around the panel
HEADER = 26
MARGIN = 8  # panel body margin
BOX_PAD = 5
GAP = 3  # between widgets that are not aligned
FONT_PX = 10.5
SCALE = 1.5  # output px per UI px
INACTIVE_ALPHA = 0.5
FONT = FontProperties(family="DejaVu Sans", size=FONT_PX)  # for measuring, in UI px
DRAW_FONT = FontProperties(family="DejaVu Sans", size=FONT_PX * SCALE * 72 / 100)  # points at 100 dpi
_TEXT = TextToPath()
ALL, NONE = (True, True, True, True), (False, False, False, False)  # corners tl, tr, br, bl


def theme_colors() -> dict:
    """The default theme's colours that the panel's widgets use, read from bpy."""
    theme = bpy.context.preferences.themes[0]
    ui, space = theme.user_interface, theme.view_3d.space

    def wcol(name):
        w = getattr(ui, name)
        return {"inner": tuple(w.inner), "inner_sel": tuple(w.inner_sel), "item": tuple(w.item),
                "outline": tuple(w.outline), "text": tuple(w.text), "text_sel": tuple(w.text_sel)}

    return {
        "region": tuple(space.button[:3]), "panel": tuple(space.panelcolors.back),
        "title": tuple(space.button_title), "label": tuple(space.button_text),
        **{name: wcol("wcol_" + name) for name in ("num", "numslider", "option", "menu", "text", "tool", "radio",
                                                   "box")},
    }


def text_width(s: str) -> float:
    return _TEXT.get_text_width_height_descent(s, FONT, ismath=False)[0]


def fit(s: str, width: float) -> str:
    """``s`` clipped with an ellipsis to ``width``, as Blender clips a label that does not fit."""
    if text_width(s) <= width:
        return s
    while s and text_width(s + "…") > width:
        s = s[:-1]
    return s + "…"


def rgba(color, alpha: float = 1.0) -> tuple:
    """A theme colour (RGB or RGBA) with its own alpha times ``alpha`` (greyed-out widgets)."""
    return (*color[:3], (color[3] if len(color) > 3 else 1.0) * alpha)


def rounded(x, y, w, h, r, corners=ALL) -> MplPath:
    """A rectangle (y down) with the corners (tl, tr, br, bl) that are True rounded by r."""
    r = min(r, w / 2, h / 2)
    tl, tr, br, bl = corners
    verts, codes = [(x + r, y) if tl else (x, y)], [MplPath.MOVETO]
    for before, corner, after, on in (((x + w - r, y), (x + w, y), (x + w, y + r), tr),
                                      ((x + w, y + h - r), (x + w, y + h), (x + w - r, y + h), br),
                                      ((x + r, y + h), (x, y + h), (x, y + h - r), bl),
                                      ((x, y + r), (x, y), (x + r, y), tl)):
        if on:
            verts += [before, corner, after]
            codes += [MplPath.LINETO, MplPath.CURVE3, MplPath.CURVE3]
        else:
            verts.append(corner)
            codes.append(MplPath.LINETO)
    return MplPath(verts + [verts[0]], codes + [MplPath.CLOSEPOLY])


class Canvas:
    """Drawing operations in UI px (y down), collected while laying out, painted at the end."""

    def __init__(self, theme):
        self.theme = theme
        self.ops = []

    def field(self, x, y, w, h, wcol, corners, alpha, fill=None, selected=False):
        inner = wcol["inner_sel"] if selected else wcol["inner"]
        self.ops.append(("field", x, y, w, h, inner, wcol["outline"], corners, alpha, fill))

    def text(self, x, y, s, color, alpha, ha="left"):
        self.ops.append(("text", x, y, s, color, alpha, ha))

    def paint(self, ax):
        for op in self.ops:
            kind = op[0]
            if kind == "field":
                _, x, y, w, h, inner, outline, corners, alpha, fill = op
                path = rounded(x + 0.5, y + 0.5, w - 1, h - 1, 4, corners)
                patch = PathPatch(path, facecolor=rgba(inner, alpha), edgecolor=rgba(outline, alpha),
                                  linewidth=SCALE * 0.75)
                ax.add_patch(patch)
                if fill is not None:  # a slider's filled part, clipped to the field's shape
                    frac, color = fill
                    bar = PathPatch(rounded(x, y, w * frac, h, 0, NONE), facecolor=rgba(color, alpha),
                                    edgecolor="none")
                    ax.add_patch(bar)
                    bar.set_clip_path(patch)
            elif kind == "text":
                _, x, y, s, color, alpha, ha = op
                ax.text(x, y, s, color=rgba(color, alpha), ha=ha, va="center_baseline", fontproperties=DRAW_FONT)
            elif kind == "check":
                _, x, y, size, wcol, on, alpha = op
                ax.add_patch(PathPatch(rounded(x, y, size, size, 3), linewidth=SCALE * 0.75,
                                       facecolor=rgba(wcol["inner_sel"] if on else wcol["inner"], alpha),
                                       edgecolor=rgba(wcol["outline"], alpha)))
                if on:
                    ax.plot([x + 0.22 * size, x + 0.42 * size, x + 0.8 * size],
                            [y + 0.52 * size, y + 0.72 * size, y + 0.28 * size],
                            color=rgba(wcol["item"], alpha), linewidth=1.6 * SCALE, solid_capstyle="round")
            elif kind == "poly":
                _, points, color, alpha = op
                ax.add_patch(Polygon(points, closed=True, facecolor=rgba(color, alpha), edgecolor="none"))


def natural_width(node) -> float:
    """The width Blender would ask for: text plus padding (and a check box or arrow)."""
    if "children" in node:
        kids = node["children"]
        if node["kind"] == "row":
            return sum(natural_width(k) for k in kids) + GAP * max(len(kids) - 1, 0)
        return max((natural_width(k) for k in kids), default=0.0)
    kind = node["kind"]
    if kind == "label":
        return text_width(node["text"]) + 8
    if kind == "operator":
        return text_width(node["text"]) + 16
    if node.get("type") == "BOOLEAN":
        return 14 + 6 + text_width(node["text"]) + 6
    if node.get("type") == "ENUM" and node.get("expand"):
        return sum(text_width(name) + 16 for _, name in node["items"])
    label = text_width(node["text"]) + 12 if node["text"] else 0.0
    return max(label + text_width(node["display"]) + 12, 5 * U)


def corner_mask(corners, first, last, vertical):
    """The corners a member of an aligned group keeps: only the group's outer ones."""
    tl, tr, br, bl = corners
    if vertical:
        return (tl and first, tr and first, br and last, bl and last)
    return (tl and first, tr and last, br and last, bl and first)


def split_widths(widths, total, gap):
    """Share ``total`` among items in proportion to the widths they ask for."""
    widths = np.asarray(widths, dtype=float)
    room = total - gap * (len(widths) - 1)
    return widths * room / max(widths.sum(), 1e-9)


def place(canvas, node, x, y, w, active=True, corners=ALL) -> float:
    """Lay out ``node`` at (x, y) in width w, adding its drawing to the canvas; returns its height."""
    if "children" not in node:
        place_item(canvas, node, x, y, w, active, corners)
        return U
    active = active and node.get("active", True)
    kind, kids = node["kind"], node["children"]
    align = node.get("align", False)
    gap = 0 if align else GAP
    if kind == "row":
        widths = split_widths([natural_width(k) for k in kids], w, gap)
        height, cx = 0.0, x
        for i, (kid, kw) in enumerate(zip(kids, widths)):
            kc = corner_mask(corners, i == 0, i == len(kids) - 1, False) if align else corners
            height = max(height, place(canvas, kid, cx, y, kw, active, kc))
            cx += kw + gap
        return height
    if kind == "grid_flow":
        ncol = node.get("columns") or 1
        rows = [kids[i:i + ncol] for i in range(0, len(kids), ncol)]
        col_w = [max(natural_width(r[c]) for r in rows if c < len(r)) for c in range(ncol)]
        widths = split_widths(col_w, w, gap)
        for r, row in enumerate(rows):
            cx = x
            for kid, kw in zip(row, widths):
                place(canvas, kid, cx, y + r * (U + gap), kw, active, NONE if align else corners)
                cx += kw + gap
        return len(rows) * U + gap * max(len(rows) - 1, 0)
    # layout, column, box, split: a vertical stack
    pad = BOX_PAD if kind == "box" else 0
    start = len(canvas.ops)
    cy = y + pad
    for i, kid in enumerate(kids):
        kc = corner_mask(corners, i == 0, i == len(kids) - 1, True) if align else corners
        cy += place(canvas, kid, x + pad, cy, w - 2 * pad, active, kc) + gap
    height = cy - y - (gap if kids else 0) + pad
    if kind == "box":  # drawn under its content
        box = canvas.theme["box"]
        canvas.ops.insert(start, ("field", x, y, w, height, box["inner"], box["outline"], ALL, 1.0, None))
    return height


def place_item(canvas, item, x, y, w, active, corners) -> None:
    t = canvas.theme
    alpha = 1.0 if active else INACTIVE_ALPHA
    mid = y + U / 2
    kind, typ = item["kind"], item.get("type")
    if kind == "label":
        canvas.text(x + 4, mid, fit(item["text"], w - 6), t["label"], alpha)
    elif kind == "operator":
        canvas.field(x, y, w, U, t["tool"], corners, alpha)
        canvas.text(x + w / 2, mid, fit(item["text"], w - 8), t["tool"]["text"], alpha, ha="center")
    elif typ == "BOOLEAN":
        canvas.ops.append(("check", x + 2, y + 3, 14, t["option"], item["value"], alpha))
        canvas.text(x + 22, mid, fit(item["text"], w - 24), t["option"]["text"], alpha)
    elif typ == "ENUM" and item["expand"]:
        names = [name for _, name in item["items"]]
        widths = split_widths([text_width(n) + 16 for n in names], w, 0)
        cx = x
        for i, ((ident, name), kw) in enumerate(zip(item["items"], widths)):
            on = ident == item["value"]
            canvas.field(cx, y, kw, U, t["radio"], corner_mask(corners, i == 0, i == len(names) - 1, False),
                         alpha, selected=on)
            canvas.text(cx + kw / 2, mid, fit(name, kw - 8), t["radio"]["text_sel" if on else "text"], alpha,
                        ha="center")
            cx += kw
    elif typ in ("ENUM", "STRING") or kind == "prop_search":
        if item["text"]:  # a label, then the field (Blender's non-split layout)
            lw = min(text_width(item["text"]) + 12, 0.4 * w)
            canvas.text(x + 4, mid, fit(item["text"], lw - 6), t["label"], alpha)
            x, w = x + lw, w - lw
        wcol = t["menu"] if typ == "ENUM" else t["text"]
        canvas.field(x, y, w, U, wcol, corners, alpha)
        canvas.text(x + 6, mid, fit(item["display"], w - 24), wcol["text"], alpha)
        if typ == "ENUM":  # the menu's down arrow
            ax_, ay = x + w - 11, y + U / 2
            canvas.ops.append(("poly", [(ax_ - 3.5, ay - 2), (ax_ + 3.5, ay - 2), (ax_, ay + 2.5)],
                               wcol["text"], alpha))
    else:  # INT, FLOAT: a number field, a slider for factors
        slider = "fraction" in item
        wcol = t["numslider" if slider else "num"]
        fill = (item["fraction"], wcol["item"]) if slider else None
        canvas.field(x, y, w, U, wcol, corners, alpha, fill=fill)
        if item["text"]:
            value_w = text_width(item["display"])
            canvas.text(x + 6, mid, fit(item["text"], w - value_w - 18), wcol["text"], alpha)
            canvas.text(x + w - 6, mid, item["display"], wcol["text"], alpha, ha="right")
        else:
            canvas.text(x + w / 2, mid, item["display"], wcol["text"], alpha, ha="center")


def draw_panel(recording: dict, title: str, theme: dict, out_name: str) -> Path:
    """The recorded panel in the sidebar's colours, header and body, into docs/images."""
    canvas = Canvas(theme)
    body_h = place(canvas, recording, OUTER + MARGIN, OUTER + HEADER + 4, PANEL_W - 2 * MARGIN)
    panel_h = HEADER + 4 + body_h + MARGIN
    width, height = PANEL_W + 2 * OUTER, panel_h + 2 * OUTER
    fig = plt.figure(figsize=(width * SCALE / 100, height * SCALE / 100), dpi=100)
    ax = fig.add_axes([0, 0, 1, 1])
    ax.set_xlim(0, width)
    ax.set_ylim(height, 0)
    ax.set_axis_off()
    fig.patch.set_facecolor(theme["region"])
    ax.add_patch(PathPatch(rounded(OUTER, OUTER, PANEL_W, panel_h, 5), facecolor=theme["panel"], edgecolor="none"))
    tx, ty = OUTER + 12, OUTER + HEADER / 2
    ax.add_patch(Polygon([(tx - 4, ty - 2.5), (tx + 4, ty - 2.5), (tx, ty + 3)], closed=True,
                         facecolor=theme["title"], edgecolor="none"))  # the open panel's disclosure arrow
    canvas.text(OUTER + 22, ty, title, theme["title"], 1.0)
    canvas.paint(ax)
    path = fc.IMAGES / out_name
    fc.IMAGES.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100, facecolor=fig.get_facecolor())
    plt.close(fig)
    fc.log(f"wrote {path.relative_to(fc.REPO_ROOT)}")
    return path


# ----------------------------------------------------------------------------- the scene and runs

def select_only(ob) -> None:
    for other in bpy.context.view_layer.objects:
        other.select_set(False)
    ob.select_set(True)
    bpy.context.view_layer.objects.active = ob


def generate_from_button(recording: dict, monkey) -> tuple:
    """Press the panel's Generate LODs button: the real operator with the properties the
    button carries. Returns (report of the Monkey, wall seconds of the operator call)."""
    button = next(item for item, _a, _e in walk(recording) if item.get("idname") == GENERATE)
    select_only(monkey)
    t0 = time.perf_counter()
    with stdout_to_stderr():
        result = bpy.ops.object.line_quadric_lod(**button["props"])
    seconds = time.perf_counter() - t0
    if result != {"FINISHED"}:
        raise SystemExit(f"Generate LODs returned {result}")
    return json.loads(bpy.context.scene.line_quadric_lod.last_report)[0], seconds


def mesh_weights(ob) -> tuple:
    V, F, _uv, _poly = mesh_arrays(ob.data)
    return V, F, vertex_groups.read_weights(ob.data, [GROUP])[:, 0]


def preview(recording: dict) -> str:
    """The Target box's chain preview line."""
    return next(item["text"] for item, _a, _e in walk(recording)
                if item["kind"] == "label" and item["text"].startswith("LOD1.."))


def greyed(recording: dict) -> list:
    """The greyed-out widgets, by their text, or for a property drawn without one (text=""),
    its label in the settings table."""
    from addon.pure.settings import SETTINGS

    labels = {setting.name: setting.label for setting in SETTINGS}
    return [item["text"] or labels.get(item.get("prop"), item.get("prop"))
            for item, active, _e in walk(recording) if not active]


def painted_share(F, w) -> float:
    """% of the triangles whose vertices' mean importance weight is above PAINTED."""
    return 100.0 * float(np.mean(w[F].mean(axis=1) > PAINTED))


def build_and_record() -> dict:
    """Register the add-on, build the sample, record the panel in its states and run the
    operator twice; everything the pictures need, as plain data."""
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    out = {"theme": theme_colors()}
    addon.register()
    try:
        scene = bpy.context.scene
        settings = scene.line_quadric_lod
        with stdout_to_stderr():
            monkey = sample.build(bpy.context)["Monkey"]
        select_only(monkey)
        panel_cls = panel.VIEW3D_PT_line_quadric_lod
        out["title"] = panel_cls.bl_label
        out["defaults"] = record_panel(panel_cls, bpy.context).to_dict()
        settings.target_triangles = BY_COUNT  # recorded only, for the docs' example
        out["by_count"] = record_panel(panel_cls, bpy.context).to_dict()
        settings.property_unset("target_triangles")
        out["source"] = mesh_weights(monkey)

        with stdout_to_stderr():
            bpy.ops.object.line_quadric_lod_paint()  # selects the painted group as the source
            bpy.ops.object.mode_set(mode='OBJECT')
        out["importance"] = record_panel(panel_cls, bpy.context).to_dict()
        out["soft_report"], _seconds = generate_from_button(out["importance"], monkey)
        out["soft_last"] = mesh_weights(bpy.data.objects[out["soft_report"]["levels"][-1]["name"]])

        for name in LodSettings.names():  # back to the defaults
            settings.property_unset(name)
        out["run_settings"] = {name: getattr(settings, name) for name in LodSettings.names()}
        out["report"], out["seconds"] = generate_from_button(record_panel(panel_cls, bpy.context).to_dict(), monkey)
        out["last_run"] = record_panel(panel_cls, bpy.context).to_dict()
        out["chain"] = [mesh_weights(bpy.data.objects[lv["name"]]) for lv in out["report"]["levels"]]
    finally:
        addon.unregister()
    return out


# ----------------------------------------------------------------------------- renders

def weight_rgb(w: np.ndarray) -> np.ndarray:
    """Blender's weight-paint colours (BKE_defvert_weight_to_rgb): blue 0, cyan 0.25, green
    0.5, yellow 0.75, red 1, brighter towards 1; sRGB as shown on screen."""
    w = np.clip(np.asarray(w, dtype=np.float64), 0.0, 1.0)
    blend = w / 2 + 0.5
    t = np.select([w <= 0.25, w <= 0.5, w <= 0.75], [w * 4, (w - 0.25) * 4, (w - 0.5) * 4], (w - 0.75) * 4)
    zero, one = np.zeros_like(w), np.ones_like(w)
    r = np.select([w <= 0.5, w <= 0.75], [zero, t], one)
    g = np.select([w <= 0.25, w <= 0.75], [t, one], 1 - t)
    b = np.select([w <= 0.25, w <= 0.5], [one, 1 - t], zero)
    return np.stack([r, g, b], axis=1) * blend[:, None]


def srgb_to_linear(c: np.ndarray) -> np.ndarray:
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def crop_together(images, pad: int = 6) -> list:
    """Cut the empty (transparent) margin shared by all images, so they keep one scale."""
    alpha = np.max([img[..., 3] for img in images], axis=0) > 0.02
    rows, cols = np.flatnonzero(alpha.any(axis=1)), np.flatnonzero(alpha.any(axis=0))
    r0, r1 = max(rows[0] - pad, 0), rows[-1] + pad + 1
    c0, c1 = max(cols[0] - pad, 0), cols[-1] + pad + 1
    return [img[r0:r1, c0:c1] for img in images]


def render_set(entries, titles, out_name, args, view_mesh, colors=False) -> float:
    """Render each (V, F, weights) from one camera framing ``view_mesh``; returns seconds."""
    t0 = time.perf_counter()
    scene, sun, cam = rd.setup_scene("CYCLES", args.size, args.samples)
    rd.aim(cam, sun, view_mesh, VIEW)
    mat = rd.wire_material("CYCLES", vertex_colors=colors)
    if colors:  # more ambient light: weight colours read as in Weight Paint mode, not in shadow
        scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    images = []
    with tempfile.TemporaryDirectory(prefix="lqlod_panel_") as tmp:
        for i, (V, F, w) in enumerate(entries):
            fc.log(f"rendering {out_name} {i + 1}/{len(entries)} ({len(F):,} triangles)")
            png = Path(tmp) / f"{i}.png"
            rd.render(scene, V, F, mat, png, colors=srgb_to_linear(weight_rgb(w)) if colors else None)
            images.append(plt.imread(png))
    rd.compose(crop_together(images), titles, out_name)
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=400, help="pixels per render (square)")
    ap.add_argument("--samples", type=int, default=16, help="Cycles samples per pixel")
    args = ap.parse_args()
    t_start = time.perf_counter()
    d = build_and_record()
    theme, title = d["theme"], d["title"]
    rep = d["report"]
    V0, F0, w0 = d["source"]

    draw_panel(d["defaults"], title, theme, "panel_defaults.png")
    print("`panel_defaults.png`: the panel with its default settings and the sample's Monkey active, drawn by "
          "bench/figures/fig_panel.py from addon/panel.py's own draw() (not a screenshot: the bpy module has no window); "
          f"its chain preview reads `{preview(d['defaults'])}`, greyed out: "
          f"{', '.join(greyed(d['defaults'])) or 'nothing'}. With Triangles = {BY_COUNT:,} the same draw() reads "
          f"`{preview(d['by_count'])}`, greyed out: {', '.join(greyed(d['by_count'])) or 'nothing'}.")
    draw_panel(d["importance"], title, theme, "panel_importance.png")
    print(f'`panel_importance.png`: the same after **Paint Importance**, which selected the Monkey\'s painted group '
          f'"{GROUP}" as the source (Vertex Group; strength 0.5, the default).')
    draw_panel(d["last_run"], title, theme, "panel_last_run.png")
    levels = rep["levels"]
    print(f"`panel_last_run.png`: the panel after **Generate LODs** with the default settings on the Monkey "
          f"({rep['source_triangles']:,} triangles): LOD1 to LOD{len(levels)} with "
          + ", ".join(f"{lv['triangles']:,}" for lv in levels)
          + f" triangles, made in {rep['seconds']:.2f} s (the report's time; the operator call took "
          f"{d['seconds']:.2f} s in all).")

    base_last = d["chain"][-1]
    soft_last = d["soft_last"]
    k = len(levels)
    shares = [painted_share(F, w) for _V, F, w in (d["source"], base_last, soft_last)]
    titles = [f"Monkey, {GROUP}\n{len(F0):,} triangles, {shares[0]:.1f} % painted",
              f"LOD{k}, importance None\n{len(base_last[1]):,} triangles, {shares[1]:.1f} % painted",
              f"LOD{k}, Vertex Group (strength 0.5)\n{len(soft_last[1]):,} triangles, {shares[2]:.1f} % painted"]
    secs = render_set([d["source"], base_last, soft_last], titles, "panel_weights.png", args, V0, colors=True)
    painted_vertices = int(np.count_nonzero(w0 > 0))
    print(f'`panel_weights.png`: the Monkey\'s painted "{GROUP}" weights in Blender\'s weight-paint colours '
          f"(blue 0, green 0.5, red 1; {painted_vertices:,} of {len(w0):,} vertices above 0), and LOD{k} made "
          f"without ({len(base_last[1]):,} triangles) and with that importance ({len(soft_last[1]):,}), each "
          f"showing the group it carries: {shares[0]:.1f} % of the source's triangles are painted (mean weight "
          f"above {PAINTED}), {shares[1]:.1f} % of LOD{k}'s without importance and {shares[2]:.1f} % with it "
          f"(Cycles, {args.size} px, {args.samples} samples, rendered in {secs:.0f} s).")

    chain = [d["source"], *d["chain"]]
    quality = [core.quality_summary(V, F)["mean_quality"] for V, F, _w in chain]
    titles = [f"LOD0 (source)\n{len(F0):,} triangles, mean q {quality[0]:.2f}"]
    titles += [f"LOD{lv['level']}\n{lv['triangles']:,} triangles, mean q {q:.2f}"
               for lv, q in zip(levels, quality[1:])]
    secs = render_set(chain, titles, "panel_lod_chain.png", args, V0)
    print(f"`panel_lod_chain.png`: the chain Generate LODs made with the defaults (ratio "
          f"{d['run_settings']['ratio']:g}, {d['run_settings']['levels']} levels, factor "
          f"{d['run_settings']['level_factor']:g}, uniformity {d['run_settings']['line_weight']:g}): "
          f"LOD0 {len(F0):,} triangles (mean quality {quality[0]:.2f}), "
          + ", ".join(f"LOD{lv['level']} {lv['triangles']:,} ({q:.2f}; deviation max "
                      f"{lv['hausdorff_percent']:.3f} %, mean {lv['mean_percent']:.4f} % of the diagonal)"
                      for lv, q in zip(levels, quality[1:]))
          + f" (Cycles, {args.size} px, {args.samples} samples, rendered in {secs:.0f} s).")
    fc.log(f"bench/figures/fig_panel.py: {time.perf_counter() - t_start:.0f} s")


if __name__ == "__main__":
    main()
