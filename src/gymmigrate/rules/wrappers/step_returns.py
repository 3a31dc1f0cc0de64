"""GM602: the five values a wrapper's ``step`` override returns, built on the LibCST side.

``return obs, reward, done, info`` becomes ``return obs, reward, <terminated>, <truncated>,
info``: the inner step's flags, the override's own end cut against ``terminated``
(``done and not terminated``, agent by agent for per-agent lists), the flags each passed
through the call that reshaped ``done``, or reduced with ``all``/``any``. ``step.py``
decides which.
"""

from __future__ import annotations

from gymmigrate.edits.lazy import cst
from gymmigrate.rules.wrappers.common import _parenthesized, _tuple


def _code(node: cst.BaseExpression) -> str:
    return cst.Module(body=[]).code_for_node(node)


def _five(node: cst.Tuple, flags: list[cst.BaseExpression]) -> cst.Tuple:
    """``obs, reward, done, info`` -> ``obs, reward, <flags>, info``."""
    obs, reward, _, info = (element.value for element in node.elements)
    return _tuple([obs, reward, *flags, info], node if node.lpar else None)


def _reshaped_flags(node: cst.Tuple, terminated: str, truncated: str) -> list[cst.BaseExpression]:
    call = node.elements[2].value
    assert isinstance(call, cst.Call)  # ``_reshapes`` checked the ast side
    first = call.args[0]
    return [
        call.with_changes(args=[first.with_changes(value=cst.Name(flag)), *call.args[1:]])
        for flag in (terminated, truncated)
    ]


def _reduced_flags(reduced: str, done: str, terminated: str) -> list[cst.BaseExpression]:
    """``all(terminated), all(done) and not all(terminated)`` (an agent may end by termination,
    another by truncation, on the same step); the same with ``any``. ``truncated`` is not
    reduced itself: a per-agent env migrated by this run returns one ``False`` there."""
    return [cst.parse_expression(f"{reduced}({terminated})"), cst.parse_expression(f"{reduced}({done}) and not {reduced}({terminated})")]


def _cut(node: cst.Tuple, terminated: str, per_agent: bool | str = False) -> list[cst.BaseExpression]:
    """The override's own ``done`` becomes truncation: ``terminated, done and not terminated``
    (per-agent lists: that of each agent; ``per_agent`` is the code's own type test when it
    handles one flag too, ``isinstance(done, Iterable)``)."""
    done = node.elements[2].value
    if per_agent:
        each = f"[end and not term for end, term in zip({_code(done)}, {terminated})]"
        if isinstance(per_agent, str):
            each = f"({each} if isinstance({terminated}, {per_agent}) else {_code(_parenthesized(done))} and not {terminated})"
        return [cst.Name(terminated), cst.parse_expression(each)]
    cut = cst.BooleanOperation(
        left=_parenthesized(done),
        operator=cst.And(),
        right=cst.UnaryOperation(operator=cst.Not(), expression=cst.Name(terminated)),
    )
    return [cst.Name(terminated), cut]


def _own_cut(node: cst.Tuple, terminated: str) -> list[cst.BaseExpression]:
    """The override's own ``done`` standing in for the inner end: ``done and terminated,
    done and not terminated``, so that ``terminated or truncated`` is ``done`` itself."""
    done = _parenthesized(node.elements[2].value)
    flag = cst.Name(terminated)
    return [
        cst.BooleanOperation(left=done, operator=cst.And(), right=flag),
        cst.BooleanOperation(left=done, operator=cst.And(), right=cst.UnaryOperation(operator=cst.Not(), expression=flag)),
    ]
