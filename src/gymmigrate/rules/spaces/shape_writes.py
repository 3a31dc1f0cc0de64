"""Writes to a space's ``shape`` (GM913): a read-only property in Gymnasium.

``self.observation_space.shape = shape`` raises ``AttributeError: property 'shape' of 'Box'
object has no setter`` on Gymnasium 1.x. Code that writes it usually rebuilds the space right
after (``self.observation_space = spaces.Box(..., shape, ...)``): the write then does nothing
the rebuild does not, and it is removed, where nothing reads the shape it set before the
rebuild replaces the space. Any other write (nothing rebuilds the space next, or the rebuild
reads the shape written) is reported: a space's shape changes by building another space.
Part of ``drift.SpaceDrift``.
"""

from __future__ import annotations

import ast

from gymmigrate.facts.flow import Flow
from gymmigrate.facts.module import dotted_name, walk
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import RuleFamily
from gymmigrate.rules.spaces.values import SpaceValues


def decide_shape_write(family: RuleFamily, spaces: SpaceValues, attribute: ast.Attribute) -> None:
    """``<space>.shape = ...`` where ``<space>`` is known to be a space."""
    if not isinstance(attribute.ctx, ast.Store) or spaces.space_class(attribute.value) is None:
        return
    statement = family.facts.parent(attribute)
    space = dotted_name(attribute.value)
    if (
        isinstance(statement, ast.Assign)
        and statement.targets == [attribute]
        and space is not None
        and _rebuilt_next(family, statement, space)
    ):
        family.report(
            attribute,
            "GM913",
            f"`{space}.shape` is read-only in Gymnasium (AttributeError on the write); the next statement rebuilds "
            f"`{space}`, so the write is removed",
        )
        family.plan.remove(statement, keep_comments=True)
        return
    family.report(
        attribute,
        "GM913",
        f"`{dotted_name(attribute) or 'shape'}` is read-only in Gymnasium (AttributeError on the write): build a new "
        "space with that shape instead",
        FixKind.FLAG,
    )


def _rebuilt_next(family: RuleFamily, statement: ast.Assign, space: str) -> bool:
    """The statement after ``statement`` in its block assigns ``space`` again, and it does not
    read ``space.shape`` (which the write would have changed) while building the new value."""
    found = Flow.of(family.facts).block_of(statement)
    if found is None:
        return False
    block, index = found
    if index + 1 >= len(block):
        return False
    following = block[index + 1]
    if not isinstance(following, ast.Assign) or len(following.targets) != 1 or dotted_name(following.targets[0]) != space:
        return False
    return not any(
        isinstance(node, ast.Attribute) and node.attr == "shape" and dotted_name(node.value) == space
        for node in walk(following.value)
    )
