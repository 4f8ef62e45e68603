"""docs/parameters.md's defaults and ranges against the settings table, without Blender.

Each setting is defined once, as a row of ``SETTINGS`` (addon/pure/settings.py); the page that
documents every parameter is written by hand. The table is the truth: these tests fail when
a setting is missing from the page, or the page gives it another default or range, so a
change to the table cannot leave the page quietly stale (issue 32 §4).
"""
from __future__ import annotations

import math
import re
from pathlib import Path
from typing import NamedTuple, Optional

import pytest

from addon.pure.settings import BY_NAME, LodSettings

PAGE = Path(__file__).resolve().parent.parent / "docs" / "parameters.md"

# Range cells that are not numbers or an enum's items, so nothing to check them against.
PROSE_RANGES = {
    "importance_group": "a vertex group of the object: a name, not a numeric range",
    "limit_group": "a vertex group of the object: a name, not a numeric range",
}

NUMBER = r"-?\d+(?:\.\d+)?(?:e-?\d+)?"


class Entry(NamedTuple):
    """One setting as a row of the page gives it: its share of the default and range cells
    (range None for a switch, which has none)."""
    name: str
    default: str
    range: Optional[str]


class Range(NamedTuple):
    low: Optional[float]
    high: Optional[float]
    low_open: bool
    high_open: bool


def cells(line: str) -> list:
    """A table line's cells; ``\\|`` is a pipe inside a cell (`--mode soft\\|strong`), not a border."""
    return [c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]]


def tables(text: str) -> list:
    """Each block of consecutive lines starting with '|' as (header, rows). A block whose
    second line is not the |---| delimiter renders as a paragraph of pipes, not a table, so
    it comes back with header None (all its lines as rows)."""
    blocks, block = [], []
    for line in text.splitlines() + [""]:
        if line.startswith("|"):
            block.append(line)
        elif block:
            blocks.append(block)
            block = []
    result = []
    for block in blocks:
        if len(block) >= 2 and re.fullmatch(r"\|(\s*:?-+:?\s*\|)+", block[1].strip()):
            result.append((cells(block[0]), [cells(line) for line in block[2:]]))
        else:
            result.append((None, [cells(line) for line in block]))
    return result


def split_values(cell: str, count: int) -> Optional[list]:
    """A cell's ``count`` comma-separated values (one per setting of the row), or None when it
    holds another number of them. Commas inside an interval, "(0, 180)", or before
    "soft max" do not separate; a cell for one setting is not split at all (an enum's list)."""
    if count == 1:
        return [cell]
    parts = [p.strip() for p in re.split(r",(?![^(\[]*[)\]])(?!\s*soft max)", cell)] if cell else []
    return parts if len(parts) == count else None


def read_page(text: str) -> tuple:
    """The settings a page documents (a list of Entry) and what is wrong with its tables.

    A settings table is one whose first header cell is "property" (the core API's table,
    about core.Options, starts with "option"). A row may name several settings
    (`pixel_error`, `screen_height`): its default cell then holds one comma-separated value
    per setting and its range cell one per setting that is not a switch, in the same order.
    A row with more or fewer cells than its header loses cells when rendered, and a setting
    row without a header above it is no table at all: both are problems."""
    entries, problems = [], []
    for header, rows in tables(text):
        for row in rows:
            names = re.findall(r"`(\w+)`", row[0]) if row else []
            if header is None:
                if any(n in BY_NAME for n in names):
                    problems.append(f"{row[0]}: a row outside a table (no header and |---| line above it)")
                continue
            if header[0] != "property":
                continue
            if len(row) != len(header) or "range" not in header:
                problems.append(f"{row[0]}: {len(row)} cells under the header {header} (which needs a range)")
                continue
            if not names or any(n not in BY_NAME for n in names):
                problems.append(f"{row[0]}: names no setting of SETTINGS")
                continue
            cell = dict(zip(header, row))
            ranged = [n for n in names if BY_NAME[n].kind is not bool]
            defaults, ranges = split_values(cell["default"], len(names)), split_values(cell["range"], len(ranged))
            if defaults is None or ranges is None:
                problems.append(f"{row[0]}: needs {len(names)} defaults and {len(ranged)} ranges, "
                                f"got {cell['default']!r} and {cell['range']!r}")
                continue
            by_name = dict(zip(ranged, ranges))
            entries += [Entry(n, d, by_name.get(n)) for n, d in zip(names, defaults)]
    return entries, problems


def read_default(setting, text: str):
    """The value a default cell means, in the setting's terms; ValueError if it names none.

    Prose after the value is dropped ("0 (off)", `""` (off)); numbers compare as numbers
    (0.001 or 1e-3); a switch is on or off, as the page writes its checkbox; an enum is given
    by an item's label (Triangles) or identifier ('NONE'), and read as the identifier; a
    string is written in quotes ("")."""
    value = re.sub(r"\s*\(.*\)$", "", text).strip().strip("`")
    if setting.kind is bool:
        if value.lower() not in ("on", "off"):
            raise ValueError(f"a switch's default is on or off, not {value!r}")
        return value.lower() == "on"
    if setting.items:
        for identifier, label, _ in setting.items:
            if value.strip("'\"") in (identifier, label):
                return identifier
        raise ValueError(f"{value!r} is none of the items")
    if setting.kind is str:
        if len(value) < 2 or value[0] not in "'\"" or value[-1] != value[0]:
            raise ValueError(f"a string's default is written in quotes, not {value!r}")
        return value[1:-1]
    return float(value)


def default_problem(entry: Entry) -> Optional[str]:
    """Why the page's default for a setting is not the table's, or None when it is."""
    setting = BY_NAME[entry.name]
    try:
        value = read_default(setting, entry.default)
    except ValueError as error:
        return f"{entry.name}: cannot read the default {entry.default!r} ({error})"
    same = (math.isclose(value, setting.default, rel_tol=1e-12, abs_tol=0.0)
            if isinstance(value, float) else value == setting.default)
    return None if same else f"{entry.name}: the page says {entry.default!r}, the table {setting.default!r}"


def read_range(text: str) -> tuple:
    """A numeric range cell as (Range, soft max or None), or None for anything else (prose,
    an enum's list). The page writes "0.0001 – 1" (closed), "≥ 0", "> 0", interval notation
    "(0, 180)", a unit after it ("8 – 16384 px", "0 – 179 degrees") and ", soft max X"
    (where the slider stops; typing more is allowed)."""
    soft = re.search(rf",\s*soft max ({NUMBER})$", text)
    text = re.sub(r"\s+(degrees|px)$", "", text[:soft.start()] if soft else text)
    soft_max = float(soft[1]) if soft else None
    if m := re.fullmatch(rf"({NUMBER}) – ({NUMBER})", text):
        return Range(float(m[1]), float(m[2]), False, False), soft_max
    if m := re.fullmatch(rf"(≥|>) ({NUMBER})", text):
        return Range(float(m[2]), None, m[1] == ">", False), soft_max
    if m := re.fullmatch(rf"([(\[])({NUMBER}), ({NUMBER})([)\]])", text):
        return Range(float(m[2]), float(m[3]), m[1] == "(", m[4] == ")"), soft_max
    return None


def table_ranges(setting) -> tuple:
    """The two ranges a setting has, either of which the page may give: the one validation
    and the command line enforce (low/high, open or closed), and the one the panel's
    property enforces (Blender's min/max, always closed, where ``blender`` narrows it:
    Ratio's 0.0001 for the open 0, Factor's 0.01 – 0.99)."""
    checked = Range(setting.low, setting.high, setting.low_open, setting.high_open)
    panel = Range(setting.blender.get("min", setting.low), setting.blender.get("max", setting.high), False, False)
    return checked, panel


def range_problem(entry: Entry) -> Optional[str]:
    """Why the page's range for a number setting is not one of the table's, or for an enum
    its list not the items (labels or identifiers, in order); None when it matches."""
    setting = BY_NAME[entry.name]
    if setting.items:
        listed = [item.strip("`'\" ") for item in entry.range.split(",")]
        items = [[i for i, _, _ in setting.items], [label for _, label, _ in setting.items]]
        return None if listed in items else f"{entry.name}: the page lists {listed}, the table {items[0]}"
    documented = read_range(entry.range)
    if documented is None:
        return f"{entry.name}: cannot read the range {entry.range!r}"
    bounds, soft_max = documented
    if bounds not in table_ranges(setting):
        return f"{entry.name}: the page says {entry.range!r}, the table {' or '.join(map(str, table_ranges(setting)))}"
    if soft_max is not None and soft_max != setting.blender.get("soft_max"):
        return f"{entry.name}: the page's soft max {soft_max:g} is not the table's {setting.blender.get('soft_max')}"
    return None


ENTRIES, PAGE_PROBLEMS = read_page(PAGE.read_text(encoding="utf-8"))
RANGED = [e for e in ENTRIES if e.range is not None]


def test_the_settings_tables_render_as_tables():
    assert not PAGE_PROBLEMS, "\n".join(PAGE_PROBLEMS)


def test_every_setting_is_documented_once():
    documented = [e.name for e in ENTRIES]
    assert sorted(documented) == sorted(LodSettings.names())


@pytest.mark.parametrize("entry", ENTRIES, ids=lambda e: e.name)
def test_documented_default_is_the_tables(entry):
    assert default_problem(entry) is None, default_problem(entry)


@pytest.mark.parametrize("entry", RANGED, ids=lambda e: e.name)
def test_documented_range_is_the_tables(entry):
    if entry.name in PROSE_RANGES:
        assert read_range(entry.range) is None, f"{entry.name}'s range is a number now: check it"
        pytest.skip(f"{entry.name}: {PROSE_RANGES[entry.name]}")
    assert range_problem(entry) is None, range_problem(entry)


def changed_page(row: str, old: str, new: str) -> str:
    """The real page with ``old`` replaced by ``new`` in the first line starting with ``row``
    (the settings tables come before the core API's, which has rows named alike)."""
    lines = PAGE.read_text(encoding="utf-8").splitlines()
    index = next(i for i, line in enumerate(lines) if line.startswith(row))
    assert old in lines[index]
    lines[index] = lines[index].replace(old, new, 1)
    return "\n".join(lines)


@pytest.mark.parametrize("name,row,old,new,check", [
    pytest.param("ratio", "| `ratio` |", "| 0.5 |", "| 0.25 |", default_problem, id="number"),
    pytest.param("screen_height", "| `pixel_error`, `screen_height` |", "| 1, 1080 |", "| 1, 720 |",
                 default_problem, id="second-of-a-row"),
    pytest.param("preserve_seams", "| `preserve_seams` |", "| on |", "| off |", default_problem, id="switch"),
    pytest.param("importance_source", "| `importance_source` |", "| `'NONE'` |", "| `'ARMATURE'` |",
                 default_problem, id="enum"),
    pytest.param("ratio", "| `ratio` |", "| 0.0001 – 1 |", "| 0 – 1 |", range_problem, id="range"),
    pytest.param("vertical_fov", "| `vertical_fov` |", "| (0, 180) |", "| (0, 180] |", range_problem,
                 id="open-bound"),
    pytest.param("line_weight", "| `line_weight` |", "soft max 0.1", "soft max 1", range_problem, id="soft-max"),
])
def test_the_checker_catches_a_wrong_value(name, row, old, new, check):
    """So the tests above cannot pass by reading nothing: one value of the real page
    changed, and its check reports it (the page's shape untouched)."""
    entries, problems = read_page(changed_page(row, old, new))
    (entry,) = [e for e in entries if e.name == name]
    assert problems == PAGE_PROBLEMS and check(entry) is not None


def test_the_checker_catches_a_row_outside_a_table():
    """A paragraph between two rows splits the table: the rows after it render as text."""
    entries, problems = read_page(changed_page("| `levels` |", "| `levels` |", "\nSome words.\n\n| `levels` |"))
    assert "levels" not in [e.name for e in entries]
    assert any(p.startswith("`levels`: a row outside a table") for p in problems)
