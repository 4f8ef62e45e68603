"""Markdown tables, the one way every bench and figure script prints them.

Scripts print the header first and then each row as it is measured (with flush=True where
rows take long), so a table is built line by line rather than from a finished list.
"""
from __future__ import annotations


def row(*cells) -> str:
    """One table row: ``| a | b |``."""
    return "| " + " | ".join(str(cell) for cell in cells) + " |"


def header(*columns) -> str:
    """The column names and the rule under them (two lines)."""
    return row(*columns) + "\n" + "|" + "---|" * len(columns)
