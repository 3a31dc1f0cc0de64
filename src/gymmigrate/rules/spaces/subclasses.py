"""Space subclasses whose ``__init__`` skips the space's own (GM911). Part of ``drift.SpaceDrift``.

``class ByteActions(Discrete)`` setting ``self.n`` itself and calling
``super(Discrete, self).__init__((), dtype)`` ran gym 0.21's ``Space.__init__`` only, to
keep a dtype gym's ``Discrete`` overrode. Gymnasium 1.4's ``Discrete`` also reads
``start``, which only its ``__init__`` sets: ``sample()``, ``contains()``, ``repr()``,
``==`` and ``flatten`` raise AttributeError. Each Gymnasium space reads attributes of its
own (``_READS``); a subclass whose ``__init__`` runs no ``__init__`` of its space class
(only ``Space.__init__``, or none) and never sets one of them is reported at the class.

Where the skip only kept a dtype (a ``Discrete`` subclass that sets ``self.n`` to a
parameter and calls ``Space.__init__`` with the shape ``()`` and a dtype), the item names
the two calls a person chooses between, and neither is written: Gymnasium's ``Discrete``
takes ``dtype=``, but with it ``contains`` refuses actions of an integer type that cannot
be cast to that dtype (an ``np.int64`` from ``argmax`` in a ``uint8`` space), which gym
0.21's ``Discrete.contains`` accepted, and PettingZoo's and Gymnasium's checkers assert
``contains``; ``Discrete.__init__(self, n)`` keeps gym's membership, but the space's dtype
becomes ``int64``. Which one the project's actions need is its own knowledge.
"""

from __future__ import annotations

import ast
from typing import cast

from gymmigrate.facts.module import FUNCTIONS, is_super_call, walk
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import RuleFamily
from gymmigrate.rules.spaces.values import space_class_of

# What Gymnasium 1.4's spaces read that ``__init__`` sets, and what raises AttributeError
# without each: found by deleting each attribute of a built space and calling sample,
# contains, repr, ==, seed, shape, to_jsonable, flatdim and flatten (the script is in
# docs/rules/GM911.md). ``Space.__init__`` sets ``_shape``, ``dtype`` and ``_np_random``.
_SAMPLE, _CONTAINS, _REPR, _EQ, _SHAPE, _FLATTEN = "sample()", "contains()", "repr()", "==", ".shape", "flatten"
_JSON, _SEED, _FLATDIM = "to_jsonable()", "seed()", "flatdim"
_ALL = (_SAMPLE, _CONTAINS, _REPR, _EQ, _SEED, _JSON, _FLATDIM, _FLATTEN)
_SPACE_SETS = frozenset({"_shape", "dtype", "_np_random"})
_READS: dict[str, dict[str, tuple[str, ...]]] = {
    "Discrete": {
        "n": (_SAMPLE, _CONTAINS, _REPR, _EQ, _FLATDIM, _FLATTEN),
        "start": (_SAMPLE, _CONTAINS, _REPR, _EQ, _FLATTEN),
        "dtype": (_SAMPLE, _CONTAINS, _REPR, _EQ, _FLATTEN),
        "_shape": (_SHAPE,),
        "_np_random": (_SAMPLE,),
    },
    "Box": {
        "low": (_SAMPLE, _CONTAINS, _REPR, _EQ),
        "high": (_SAMPLE, _CONTAINS, _REPR, _EQ),
        "bounded_below": (_SAMPLE,),
        "bounded_above": (_SAMPLE,),
        "low_repr": (_REPR,),
        "high_repr": (_REPR,),
        "dtype": (_SAMPLE, _CONTAINS, _REPR, _EQ, _FLATTEN),
        "_shape": (_SAMPLE, _CONTAINS, _REPR, _EQ, _SHAPE, _FLATDIM),
        "_np_random": (_SAMPLE,),
    },
    "MultiBinary": {
        "n": (_SAMPLE, _REPR, _EQ),
        "dtype": (_SAMPLE, _FLATTEN),
        "_shape": (_CONTAINS, _SHAPE, _FLATDIM),
        "_np_random": (_SAMPLE,),
    },
    "MultiDiscrete": {
        "nvec": _ALL,
        "start": (_SAMPLE, _CONTAINS, _REPR, _EQ, _FLATTEN),
        "dtype": (_SAMPLE, _CONTAINS, _EQ, _FLATTEN),
        "_shape": (_CONTAINS, _EQ, _SHAPE),
        "_np_random": (_SAMPLE,),
    },
    "Tuple": {"spaces": _ALL, "_shape": (_SHAPE,)},
    "Dict": {"spaces": _ALL, "_shape": (_SHAPE,)},
    "OneOf": {"spaces": _ALL, "_shape": (_SHAPE,), "_np_random": (_SAMPLE,)},
    "Sequence": {
        "feature_space": _ALL,
        "stack": (_SAMPLE, _CONTAINS, _REPR, _EQ, _JSON, _FLATDIM, _FLATTEN),
        "_shape": (_SHAPE,),
        "_np_random": (_SAMPLE,),
    },
    "Text": {
        "min_length": (_SAMPLE, _CONTAINS, _REPR, _EQ),
        "max_length": (_SAMPLE, _CONTAINS, _REPR, _EQ, _FLATDIM, _FLATTEN),
        "_char_set": (_SAMPLE, _CONTAINS, _EQ, _FLATTEN),
        "_char_list": (_SAMPLE,),
        "_char_index": (_FLATTEN,),
        "_char_str": (_REPR,),
        "_shape": (_SHAPE,),
        "_np_random": (_SAMPLE,),
    },
    "Graph": {
        "node_space": (_SAMPLE, _CONTAINS, _REPR, _EQ, _SEED, _FLATTEN),
        "edge_space": (_SAMPLE, _CONTAINS, _REPR, _EQ, _SEED, _FLATTEN),
        "batch_node_space": (_CONTAINS, _JSON, _FLATTEN),
        "batch_edge_space": (_CONTAINS, _JSON, _FLATTEN),
        "_shape": (_SHAPE,),
        "_np_random": (_SAMPLE,),
    },
}
# What failed alike on gym 0.21 without the same attribute: its ``Space.shape`` property
# returned ``self._shape``, which only ``Space.__init__`` set, so a subclass skipping it
# raised AttributeError on ``.shape`` there too. Nothing changed there: not reported.
_LEGACY_RAISED: dict[str, tuple[str, ...]] = {"_shape": (_SHAPE,)}
_ORDER = (_SAMPLE, _CONTAINS, _REPR, _EQ, _SHAPE, _SEED, _JSON, _FLATDIM, _FLATTEN)

# what a subclass's ``__init__`` runs of its space class's initialisation
_FULL, _SPACE_ONLY, _NOTHING = "full", "Space.__init__", "nothing"


def decide_subclass(family: RuleFamily, classdef: ast.ClassDef) -> None:
    """GM911 for one class of the module."""
    facts = family.facts
    if len(classdef.bases) != 1 or classdef.keywords:
        return  # another base's __init__ may set what the space needs (or ``super()`` reaches it)
    base = classdef.bases[0]
    space = space_class_of(facts.qualified_names(base))
    reads = _READS.get(space or "")
    if space is None or reads is None:
        return
    init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
    if init is None or not init.args.args:
        return  # the space's own __init__ runs
    runs, calls = _what_runs(family, classdef, init, base)
    if runs is None or runs == _FULL:
        return
    stored = _stored_names(classdef)
    if stored is None:
        return  # ``setattr``/``__dict__``/``__getattr__``: what the class has is not known
    available = stored | (_SPACE_SETS if runs == _SPACE_ONLY else frozenset())
    legacy_missing = _SPACE_SETS if runs == _NOTHING else frozenset()
    new = {
        attribute: tuple(
            operation
            for operation in reads[attribute]
            if not (attribute in legacy_missing and operation in _LEGACY_RAISED.get(attribute, ()))
        )
        for attribute in reads
        if attribute not in available
    }
    missing = [attribute for attribute, operations in new.items() if operations]
    if not missing:
        return
    raising = [operation for operation in _ORDER if any(operation in new[a] for a in missing)]
    if runs == _NOTHING:
        skipped = f"its `__init__` calls no `__init__` of `{space}`"
    elif isinstance(calls[0].func, ast.Attribute) and isinstance(calls[0].func.value, ast.Call):
        skipped = f"`{facts.segment(calls[0].func)}` runs `Space.__init__` only"
    else:
        skipped = "its `__init__` calls `Space.__init__` only"
    names = ", ".join(f"`{a}`" for a in missing)
    why = (
        f"`{classdef.name}` skips `{space}.__init__` ({skipped}) and never sets {names}, which Gymnasium 1.4's `{space}` "
        f"reads: {', '.join(raising)} raise AttributeError"
    )
    if space == "Discrete" and missing == ["start"] and len(calls) == 1:
        choices = _discrete_calls(family, init, calls[0], base)
        if choices is not None:
            with_dtype, without = choices
            family.report(
                calls[0],
                "GM911",
                f"{why}. Gymnasium's `{space}` takes `dtype=`: `{with_dtype}` keeps the dtype, but its `contains` then "
                "refuses actions of an integer type that cannot be cast to it (an `np.int64` from `argmax`), which gym's "
                f"accepted and the env checkers assert; `{without}` keeps gym's membership, but the dtype becomes int64. "
                "Choose by the actions the project passes",
                FixKind.FLAG,
            )
            return
    family.report(
        classdef,
        "GM911",
        f"{why}; call `{space}.__init__` (Gymnasium's takes the arguments it needs) or set them in `__init__`",
        FixKind.FLAG,
    )


def _what_runs(family: RuleFamily, classdef: ast.ClassDef, init: ast.FunctionDef | ast.AsyncFunctionDef, base: ast.expr) -> tuple[str | None, list[ast.Call]]:
    """What ``init`` runs of the space's initialisation (``_FULL``, ``_SPACE_ONLY`` or
    ``_NOTHING``) and the calls that skip to ``Space.__init__``; None when an ``__init__``
    call reaches what the module does not show."""
    facts = family.facts
    this = init.args.args[0].arg
    runs, skipping = _NOTHING, []
    for node in walk(init):
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "__init__"):
            continue
        owner = node.func.value
        if is_super_call(owner) and not facts.bindings_of(cast(ast.Name, owner.func)):  # is_super_call saw the name
            if not owner.args or (isinstance(owner.args[0], ast.Name) and owner.args[0].id == classdef.name):
                return _FULL, []  # ``super().__init__``: the one base's
            named = owner.args[0]
        elif node.args and isinstance(node.args[0], ast.Name) and node.args[0].id == this:
            named = owner  # ``Base.__init__(self, ...)``
            if facts.segment(named) == facts.segment(base):
                return _FULL, []
        else:
            return None, []  # ``self.other.__init__(...)``, a base of a base: not known
        if facts.segment(named) == facts.segment(base):
            runs = _SPACE_ONLY  # ``super(Discrete, self)``: the class after Discrete, which is Space
            skipping.append(node)
        elif space_class_of(facts.qualified_names(named)) == "Space":
            runs = _SPACE_ONLY
            skipping.append(node)
        else:
            return None, []
    return runs, skipping


def _stored_names(classdef: ast.ClassDef) -> frozenset[str] | None:
    """Every attribute the class sets: ``self.x = ...`` in its methods, names its body binds
    (class attributes, methods, properties); None when it sets attributes in ways not shown."""
    names: set[str] = set()
    for statement in classdef.body:
        if isinstance(statement, (*FUNCTIONS, ast.ClassDef)):
            if statement.name in ("__getattr__", "__getattribute__", "__setstate__"):
                return None
            names.add(statement.name)
        elif isinstance(statement, (ast.Assign, ast.AnnAssign)):
            targets = statement.targets if isinstance(statement, ast.Assign) else [statement.target]
            names.update(t.id for t in targets if isinstance(t, ast.Name))
    for method in classdef.body:
        if not isinstance(method, FUNCTIONS) or not method.args.args:
            continue
        this = method.args.args[0].arg
        for node in walk(method):
            if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == this:
                if not isinstance(node.ctx, ast.Load):
                    names.add(node.attr)
                elif node.attr == "__dict__":
                    return None
            elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "setattr":
                return None
    return frozenset(names)


def _discrete_calls(
    family: RuleFamily, init: ast.FunctionDef | ast.AsyncFunctionDef, call: ast.Call, base: ast.expr
) -> tuple[str, str] | None:
    """``Discrete.__init__(self, n, dtype=dtype)`` and ``Discrete.__init__(self, n)`` (a
    seed kept in both) for a skip that kept a dtype: the call is a statement of its own with
    the shape ``()`` and a dtype (a seed too, maybe), and ``self.n`` is set once, in
    ``__init__``'s own body, to a parameter it never rebinds."""
    facts = family.facts
    statement = facts.statement_of(call)
    if not isinstance(statement, ast.Expr) or statement.value is not call:
        return None
    if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
        return None
    skips_super = isinstance(call.func, ast.Attribute) and isinstance(call.func.value, ast.Call)
    args = call.args if skips_super else call.args[1:]  # ``Space.__init__(self, ...)`` passes self
    allowed = ("shape", "dtype", "seed")
    if len(args) > len(allowed) or any(k.arg not in allowed for k in call.keywords):
        return None
    passed = {name: value for name, value in zip(allowed, args)}
    passed.update({k.arg: k.value for k in call.keywords if k.arg is not None})
    shape, dtype = passed.get("shape"), passed.get("dtype")
    if not (isinstance(shape, ast.Tuple) and not shape.elts) or dtype is None or _maybe_none(init, dtype):
        return None
    size = _sole_store(init, "n")
    params = {a.arg for a in (*init.args.posonlyargs, *init.args.args, *init.args.kwonlyargs)}
    if not (isinstance(size, ast.Name) and size.id in params) or _rebinds(init, size.id):
        return None
    this = init.args.args[0].arg
    seed = passed.get("seed")
    seeded = f", seed={facts.segment(seed)}" if seed is not None else ""
    head = f"{facts.segment(base)}.__init__({this}, {size.id}"
    return f"{head}, dtype={facts.segment(dtype)}{seeded})", f"{head}{seeded})"


def _sole_store(init: ast.FunctionDef | ast.AsyncFunctionDef, attribute: str) -> ast.expr | None:
    """The value of the one ``self.<attribute> = value`` statement of ``init``'s own body."""
    this = init.args.args[0].arg
    values = []
    for node in walk(init):
        if isinstance(node, ast.Attribute) and node.attr == attribute and isinstance(node.value, ast.Name) and node.value.id == this:
            if isinstance(node.ctx, ast.Load):
                continue
            values.append(node)
    if len(values) != 1:
        return None
    for statement in init.body:
        if isinstance(statement, ast.Assign) and statement.targets == [values[0]]:
            return statement.value
    return None


def _rebinds(init: ast.FunctionDef | ast.AsyncFunctionDef, name: str) -> bool:
    return any(isinstance(n, ast.Name) and n.id == name and not isinstance(n.ctx, ast.Load) for n in walk(init))


def _maybe_none(init: ast.FunctionDef | ast.AsyncFunctionDef, dtype: ast.expr) -> bool:
    """``dtype`` may be None: Gymnasium's ``Discrete`` raises TypeError for it."""
    if isinstance(dtype, ast.Constant):
        return dtype.value is None
    if not isinstance(dtype, ast.Name):
        return False
    args = init.args
    positional = [*args.posonlyargs, *args.args]
    defaults = dict(zip([a.arg for a in positional][len(positional) - len(args.defaults) :], args.defaults))
    defaults.update({a.arg: d for a, d in zip(args.kwonlyargs, args.kw_defaults) if d is not None})
    default = defaults.get(dtype.id)
    return (isinstance(default, ast.Constant) and default.value is None) or _rebinds(init, dtype.id)
