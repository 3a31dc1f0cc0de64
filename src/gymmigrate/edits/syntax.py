"""LibCST syntax helpers for build callbacks: the nodes rules construct while an edit is
applied (decisions use ``gymmigrate.facts`` instead). LibCST loads when a build first
runs."""

from __future__ import annotations

from gymmigrate.edits.lazy import cst


def dotted_node(path: str) -> cst.Name | cst.Attribute:
    """``a.b.c`` as a Name/Attribute chain."""
    parts = path.split(".")
    node: cst.Name | cst.Attribute = cst.Name(parts[0])
    for part in parts[1:]:
        node = cst.Attribute(value=node, attr=cst.Name(part))
    return node
