"""GM602: what a wrapper's ``step`` override does with its inner step's result.

Which attributes hold the wrapped env itself (``self._env`` stored from the parameter
handed to the base's ``__init__``, so ``self._env.step`` is the inner step), whether the
inner ``done`` is a collection of per-agent flags (``all(done)``, ``done[i]``), whether a
line is the ``done = terminated or truncated`` the step family inserts, and whether the
override changes ``done`` anywhere but by its unpacks.

``InnerStep`` gathers what the inner step unpacks give the override (their flags, the
line that keeps ``done``), as the step family rewrote them (``notes.step_unpacks``).

Separate from ``step.py`` because these read the override's lines alone (the ``ast`` and
the notes, no plan and no rewrite); ``step.py`` holds the decision and the edits built
from them.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass

from gymmigrate.facts.collection_reads import (
    CollectionRead,
    Shape,
    collection_read,
    named_in,
)
from gymmigrate.facts.module import FUNCTIONS, is_super_call, walk
from gymmigrate.facts.receiver_classes import duck_wrapper_attribute
from gymmigrate.rules.step_done.common import StepUnpack
from gymmigrate.rules.wrappers.common import (
    _assigned_names,
    _inner_call,
    _single_assign,
    _statements,
)
from gymmigrate.rules.wrappers.step_ends import _is_initializer

# The builtins a wrapper's step reduces (or lists) its inner per-agent flags with. Each
# raises on one flag (``all(True)``), so a single env's done is never taken for agents'.
_AGENT_BUILTINS = frozenset({"all", "any", "list", "sum", "len"})
# A dict of agents' flags read through its views (``done.values()``): a bool has none.
# facts/per_agent_flags.py takes any attribute as a sign against (an array's ``done.any()``);
# here a view is a sign for, and other methods, NumPy's calls and type tests, which one
# flag may pass too (``np.any(True)``, ``isinstance(done, bool)``), are no sign.
_DICT_VIEWS = frozenset({"values", "items", "keys"})


def _reads_per_agent(expr: ast.expr, names: set[str]) -> bool:
    """``all(done)``, ``any(dones)``, ``done.values()``, ``done[i]`` or a comprehension over
    ``done``: the inner step's done (or flags) is a collection of per-agent flags."""
    is_flag = named_in(names)
    return any(_per_agent_read(collection_read(node, is_flag)) for node in walk(expr))


def _per_agent_read(read: CollectionRead | None) -> bool:
    """A read one flag raises on: indexed, iterated, a reducing builtin's, a dict's view."""
    if read is None:
        return False
    if read.shape is Shape.PASSED:
        return read.callee in _AGENT_BUILTINS
    if read.shape is Shape.METHOD:
        return read.callee in _DICT_VIEWS
    # ``expr`` is an expression, so ITERATED is a comprehension's ``for`` (no loop statement)
    return read.shape in (Shape.INDEXED, Shape.KEYED, Shape.ITERATED)


def _reduces_per_agent(function: ast.AST, name: str, flags: set[str]) -> bool:
    """``done = all(done)`` (or ``any``, ``.values()``, a comprehension) somewhere in
    ``function``: ``name`` holds a reduction of the inner step's per-agent flags."""
    for node in walk(function):
        if (
            isinstance(node, ast.Assign)
            and len(node.targets) == 1
            and isinstance(node.targets[0], ast.Name)
            and node.targets[0].id == name
            and _reads_per_agent(node.value, flags)
        ):
            return True
    return False


def _is_done_line(statement: ast.stmt, flags: tuple[str, str]) -> bool:
    """``done = terminated or truncated`` right after a five-target step unpack."""
    assign = _single_assign(statement)
    if assign is None or not isinstance(assign.targets[0], ast.Name):
        return False
    value = assign.value
    return (
        isinstance(value, ast.BoolOp)
        and isinstance(value.op, ast.Or)
        and len(value.values) == 2
        and all(isinstance(v, ast.Name) for v in value.values)
        and tuple(v.id for v in value.values if isinstance(v, ast.Name)) == flags  # all Names (above)
    )


def _other_assignments(
    lines: list[ast.stmt],
    name: str,
    done_line: ast.stmt | None,
    unpacks: dict[ast.stmt, StepUnpack | None],
    inserted: tuple[ast.Assign, StepUnpack] | None,
    flags: tuple[str, str] | None = None,
) -> tuple[ast.stmt, ...]:
    """The statements that change ``name`` other than the unpack, its ``done = ...`` line or an initializer."""
    changes: list[ast.stmt] = []
    seen_unpack = False
    for line in lines:
        if line in unpacks:
            seen_unpack = True
            noted = unpacks[line]
            # another unpack after which the step family keeps ``done`` too assigns it again,
            # unless it is a later inner step (``obs, _, done, _ = self.env.step(1)`` after a
            # lost life) binding ``name`` as its done together with the same two flags: then
            # ``name`` is still ``terminated or truncated`` of the step that ran last
            if noted is not None and noted.done_line is not None and (inserted is None or line is not inserted[0]):
                if name in _assigned_names(line) and not _rebinds_flags_with_done(line, noted, name, flags):
                    changes.append(line)
            continue
        if line is done_line:
            continue
        if name not in _assigned_names(line):
            if isinstance(line, ast.AugAssign) and isinstance(line.target, ast.Name) and line.target.id == name:
                changes.append(line)
            continue
        if not seen_unpack and _is_initializer(line, name):
            continue
        changes.append(line)
    return tuple(changes)


def _rebinds_flags_with_done(line: ast.stmt, noted: StepUnpack, name: str, flags: tuple[str, str] | None) -> bool:
    """``line`` is a legacy inner-step unpack whose done target is ``name`` and which the step
    family split into the same two flags (``flags``) as the override's other unpacks."""
    assign = _single_assign(line)
    if assign is None or flags is None or noted.discarded:
        return False
    target = assign.targets[0]
    return (
        isinstance(target, (ast.Tuple, ast.List))
        and len(target.elts) == 4
        and isinstance(target.elts[2], ast.Name)
        and target.elts[2].id == name
        and name not in _assigned_names_except(target, 2)
        and (noted.names.terminated, noted.names.truncated) == flags
    )


def _assigned_names_except(target: ast.Tuple | ast.List, index: int) -> set[str]:
    return {e.id for i, e in enumerate(target.elts) if i != index and isinstance(e, ast.Name)}


def _inner_aliases(classdef: ast.ClassDef) -> frozenset[str]:
    """Attributes that hold the wrapped env itself: ``__init__`` hands its parameter to the
    base's ``__init__`` (``super().__init__(env)``, ``gym.Wrapper.__init__(self, env)``) and
    stores the same parameter (``self._env = env``), so ``self._env`` is ``self.env``."""
    init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
    if init is None:
        return frozenset()
    handed: set[str] = set()
    stored: dict[str, str] = {}
    rebound: set[str] = set()
    for node in walk(init):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "__init__":
            base = node.func.value
            args = node.args
            if is_super_call(base):
                handed |= {a.id for a in args[:1] if isinstance(a, ast.Name)}
            elif args and isinstance(args[0], ast.Name) and args[0].id == "self":
                handed |= {a.id for a in args[1:2] if isinstance(a, ast.Name)}
        elif isinstance(node, ast.Assign):
            for target in node.targets:
                if isinstance(target, ast.Name):
                    rebound.add(target.id)
                elif (
                    isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"
                    and isinstance(node.value, ast.Name)
                ):
                    stored[target.attr] = node.value.id
    written_elsewhere = {
        t.attr
        for method in classdef.body
        if isinstance(method, FUNCTIONS) and method is not init
        for n in walk(method)
        if isinstance(n, ast.Assign)
        for t in n.targets
        if isinstance(t, ast.Attribute) and isinstance(t.value, ast.Name) and t.value.id == "self"
    }
    held = duck_wrapper_attribute(classdef)  # a plain class's ``self.environment``: what it wraps
    return frozenset(
        attr for attr, param in stored.items() if param in handed and param not in rebound and attr not in written_elsewhere
    ) | ({held} if held is not None else set())


def _alias_step(node: ast.AST | None, aliases: frozenset[str]) -> bool:
    """``self.<alias>.step(...)`` for an attribute ``_inner_aliases`` found."""
    return (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == "step"
        and isinstance(node.func.value, ast.Attribute)
        and isinstance(node.func.value.value, ast.Name)
        and node.func.value.value.id == "self"
        and node.func.value.attr in aliases
    )


@dataclass(frozen=True)
class InnerStep:
    """What a step override's inner step unpacks give it, read from its lines and from how
    the step family rewrote them (``notes.step_unpacks``)."""

    lines: list[ast.stmt]  # the override's simple statements, in order, inside its blocks too
    unpacks: dict[ast.stmt, StepUnpack | None]  # each inner step unpack; its note, if the step family rewrote it
    flags: tuple[str, str] | None  # the names of terminated and truncated
    consistent: bool  # every unpack gives the same flags, each by a name
    done_name: str | None  # the name of the old done, kept by a ``done = ...`` line
    done_line: ast.stmt | None  # an existing ``done = ...`` line, or the unpack it is inserted after
    inserted: tuple[ast.Assign, StepUnpack] | None  # the unpack whose ``done = ...`` line the step family inserts
    inner_done: str | None  # the legacy unpack's done name, with or without a done line
    bound: set[str]  # the names the override binds, as they stand after the step family's rewrite
    # ``..., self.done, info = self.env.step(a)`` at the top level of the body: the
    # attribute and that unpack (the step family keeps it as ``terminated or truncated``)
    done_attribute: tuple[str, ast.stmt] | None
    per_agent: bool | str  # per-agent flags; the code's own type test when it handles one flag too
    done_modified: bool  # the override changes the old done other than by its unpacks
    done_changes: tuple[ast.stmt, ...]  # ...the statements that do


def _read_inner_step(
    function: ast.FunctionDef | ast.AsyncFunctionDef, classdef: ast.AST | None, noted_unpacks: dict[ast.Assign, StepUnpack]
) -> InnerStep:
    """The inner step unpacks of ``function``, a step override of ``classdef``."""
    lines = list(_statements(function.body))
    flags: tuple[str, str] | None = None
    done_name: str | None = None
    done_line: ast.stmt | None = None  # an existing ``done = ...`` line, or the unpack it is inserted after
    inserted: tuple[ast.Assign, StepUnpack] | None = None
    consistent = True
    unpacks: dict[ast.stmt, StepUnpack | None] = {}
    bound: set[str] = set()
    inner_done: str | None = None  # the legacy unpack's done name, with or without a done line
    # ``..., self.done, info = self.env.step(a)`` at the top level of the body: the
    # attribute and that unpack (the step family keeps it as ``terminated or truncated``)
    done_attribute: tuple[str, ast.stmt] | None = None
    aliases = _inner_aliases(classdef) if isinstance(classdef, ast.ClassDef) else frozenset()
    bases = classdef.bases if isinstance(classdef, ast.ClassDef) else []  # ``gym.Wrapper.step(self, a)``
    for index, line in enumerate(lines):
        assign = _single_assign(line)
        if assign is None or (_inner_call(assign.value, "step", bases=bases) is None and not _alias_step(assign.value, aliases)):
            bound |= _assigned_names(line)
            continue
        target = assign.targets[0]
        if (
            not isinstance(target, (ast.Tuple, ast.List))
            or len(target.elts) not in (4, 5)
            or any(isinstance(element, ast.Starred) for element in target.elts)
        ):
            bound |= _assigned_names(line)
            continue
        # Targets may be attributes or subscripts (``obs, reward, self.done, info = ...``):
        # only the plain names among them are bound names of the override.
        targets = [element.id if isinstance(element, ast.Name) else None for element in target.elts]
        named = {name for name in targets if name is not None}
        noted = noted_unpacks.get(assign) if len(targets) == 4 else None
        found: tuple[str, str] | None
        if len(targets) == 4:
            if noted is None:  # a legacy step the step family left: nothing to return
                found, consistent = None, False
                bound.update(named)
            else:
                names = noted.names
                found = ("_", "_") if noted.discarded else (names.terminated, names.truncated)
                bound.update(named - {targets[2]})
                bound.update(found)
                inner_done = inner_done or targets[2]
                held = target.elts[2]
                if isinstance(held, ast.Attribute) and _is_self(held.value) and line in function.body and done_attribute is None:
                    done_attribute = (held.attr, line)
                if noted.done_line is not None and targets[2] is not None:
                    bound.add(targets[2])
                    if done_name is None:
                        done_name, done_line, inserted = targets[2], assign, (assign, noted)
        elif targets[2] is None or targets[3] is None:
            # ``obs, reward, self.terminated, self.truncated, info``: no names to return
            found, consistent = None, False
            bound.update(named)
        else:
            found = (targets[2], targets[3])
            bound.update(named)
            following = lines[index + 1] if index + 1 < len(lines) else None
            if following is not None and _is_done_line(following, found):
                done_line, done_name = following, following.targets[0].id  # type: ignore[attr-defined]
        unpacks[line] = noted
        if found is not None:
            if flags is not None and flags != found:
                consistent = False
            flags = flags or found
    # The inner done is a list of per-agent flags (facts/per_agent_flags.py): its own end is
    # cut against ``terminated`` agent by agent, ``done and not terminated`` is always false.
    agents = [noted.names for noted in unpacks.values() if noted is not None and noted.names.per_agent and not noted.names.by_name]
    per_agent: bool | str = bool(agents) and (agents[0].guard or True)
    done_changes = (
        _other_assignments(lines, done_name, done_line, unpacks, inserted, flags if consistent else None)
        if done_name is not None
        else ()
    )
    done_modified = bool(done_changes)
    return InnerStep(
        lines=lines,
        unpacks=unpacks,
        flags=flags,
        consistent=consistent,
        done_name=done_name,
        done_line=done_line,
        inserted=inserted,
        inner_done=inner_done,
        bound=bound,
        done_attribute=done_attribute,
        per_agent=per_agent,
        done_modified=done_modified,
        done_changes=done_changes,
    )


# Calls that only convert or reshape a flag (elementwise): ``f(terminated) or f(truncated)``
# is ``f(terminated or truncated)``.
_RESHAPING = frozenset({"bool", "asarray", "array", "expand_dims", "atleast_1d", "reshape", "bool_"})


def _reshapes(done: ast.expr, name: str, terminated: str) -> bool:
    """``np.expand_dims(done, 0)``, ``bool(done)``: a reshaping call whose first argument is
    the inner ``done`` (which the step family may have made ``terminated``) and whose other
    arguments do not read it."""
    if not (isinstance(done, ast.Call) and done.args and not any(isinstance(a, ast.Starred) for a in done.args)):
        return False
    func = done.func
    called = func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else None
    first = done.args[0]
    rest = [*done.args[1:], *(k.value for k in done.keywords)]
    return (
        called in _RESHAPING
        and isinstance(first, ast.Name)
        and first.id == name
        and name != terminated
        and not any(isinstance(n, ast.Name) and n.id == name for r in rest for n in walk(r))
    )


def _reduction_of(done: ast.expr, done_name: str | None) -> str | None:
    """``all(done)`` / ``any(done)`` of the inner step's done: the builtin's name."""
    if (
        isinstance(done, ast.Call)
        and isinstance(done.func, ast.Name)
        and done.func.id in ("all", "any")
        and len(done.args) == 1
        and not done.keywords
        and isinstance(done.args[0], ast.Name)
        and done.args[0].id == done_name
    ):
        return done.func.id
    return None


def _is_self(node: ast.AST) -> bool:
    return isinstance(node, ast.Name) and node.id == "self"


def _only_inner_done(classdef: ast.AST | None, function: ast.AST, done: ast.expr, held: tuple[str, ast.stmt], ret: ast.Return) -> bool:
    """``return ..., self.done, ...`` after ``..., self.done, ... = self.env.step(a)`` at
    the top level of the body, with no other store of ``self.done`` in the class but in
    ``__init__`` and ``reset`` (nor ``del``): what it returns is the inner step's done,
    nothing the override decided."""
    attribute, unpack = held
    if not (isinstance(done, ast.Attribute) and done.attr == attribute and _is_self(done.value)):
        return False
    if ret.lineno <= (unpack.end_lineno or unpack.lineno) or not isinstance(classdef, ast.ClassDef):
        return False  # a return before the unpack reads the previous step's value
    others = [s for s in classdef.body if isinstance(s, FUNCTIONS) and s is not function and s.name not in ("__init__", "reset")]
    for node in (n for scope in (function, *others) for n in walk(scope)):
        if isinstance(node, ast.Attribute) and node.attr == attribute and _is_self(node.value) and not isinstance(node.ctx, ast.Load):
            if not any(node is t for t in walk(unpack)):
                return False
    return True
