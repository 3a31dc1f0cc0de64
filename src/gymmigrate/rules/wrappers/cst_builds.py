"""LibCST transformers the wrapper builds run (the apply layer: loaded by the first build
that needs one, never while the family decides)."""

from __future__ import annotations

import libcst as cst


def _is_inner_reset(node: cst.BaseExpression, bases: frozenset[str] = frozenset()) -> bool:
    """``self.env.reset(...)``, ``super().reset(...)``, or ``Base.reset(self, ...)`` naming one
    of ``bases`` (the wrapper's bases, as the class statement spells them)."""
    if not (isinstance(node, cst.Call) and isinstance(node.func, cst.Attribute) and node.func.attr.value == "reset"):
        return False
    owner = node.func.value
    if bases and node.args and isinstance(node.args[0].value, cst.Name) and node.args[0].value.value == "self":
        if cst.Module(body=[]).code_for_node(owner) in bases:
            return True
    if isinstance(owner, cst.Attribute):
        return isinstance(owner.value, cst.Name) and owner.value.value == "self" and owner.attr.value == "env"
    return isinstance(owner, cst.Call) and isinstance(owner.func, cst.Name) and owner.func.value == "super"


class ObservationOf(cst.CSTTransformer):
    """The inner reset (or the ``[0]`` of it the reset family wrote) becomes the observation name."""

    def __init__(self, obs_name: str, bases: frozenset[str] = frozenset()) -> None:
        super().__init__()
        self.obs_name = obs_name
        self.bases = bases

    def visit_Lambda(self, node: cst.Lambda) -> bool:
        return False

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.BaseExpression:
        return cst.Name(self.obs_name) if _is_inner_reset(original_node, self.bases) else updated_node

    def leave_Subscript(self, original_node: cst.Subscript, updated_node: cst.Subscript) -> cst.BaseExpression:
        if _is_inner_reset(original_node.value, self.bases) and len(original_node.slice) == 1:
            index = original_node.slice[0].slice
            if isinstance(index, cst.Index) and isinstance(index.value, cst.Integer) and index.value.value == "0":
                return cst.Name(self.obs_name)
        return updated_node
