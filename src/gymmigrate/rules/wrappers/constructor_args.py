"""GM617: wrapper classes record their constructor arguments.

Gymnasium 1.x recreates an env from its spec: ``env.spec`` of a wrapped env lists every
wrapper with the keyword arguments it was built with, and ``make(env.spec)``,
``env.spec.make()`` and ``check_env`` (which recreates the env to test ``close``) build
it again from them. A wrapper that does not derive from
``gymnasium.utils.RecordConstructorArgs`` has no arguments on record, and the recreation
raises ``ValueError: <Name> wrapper does not inherit from
`gymnasium.utils.RecordConstructorArgs`, therefore, the wrapper cannot be recreated``;
gym had no such recreation.

A wrapper class whose own ``__init__(self, env, ...)`` takes arguments besides the env records them the way
Gymnasium's own wrappers do (the env is the parameter named ``env`` wherever it stands,
``__init__(self, shape, env=None)`` included, since the recreation passes it as
``env=``; without one, the first parameter after ``self``): its first statement becomes
``gym.utils.RecordConstructorArgs.__init__(self, weight=weight, ...)`` (before anything
can rebind a parameter), and a class that derives directly from ``Wrapper``,
``ObservationWrapper``, ``ActionWrapper`` or ``RewardWrapper`` gains
``RecordConstructorArgs`` as a base. A subclass of a Gymnasium wrapper that records its
own arguments (``RecordEpisodeStatistics``) or of a wrapper of the run gets the call only:
the first call wins, so the subclass's arguments, not its base's, are on record. A
wrapper that forwards attributes itself (``__getattr__``) records them right after its base
``__init__``: the mixin's ``hasattr`` would run that ``__getattr__`` before ``self.env``
exists and recurse. Where that is not safe (a parameter rebound first, no base call found,
a base that records first) it is reported.

``RecordConstructorArgs`` deep-copies what it records; a parameter that may hold
anything (no annotation, or not a plain value type, and no literal default) could be an
object ``deepcopy`` cannot copy (a lock, a file, another env with a window), so where
one does the call passes ``_disable_deepcopy=True``. ``*args`` cannot be recorded by
name: such a wrapper is reported, as a question where the run recreates envs from their
spec (``check_env``, ``make(x.spec)``), as a note elsewhere (gym recreated none). A wrapper without ``__init__``, or whose ``__init__``
takes only the env, is left as it is (its recreation still raises, as gym-era wrappers'
did under any recreation; Gymnasium's own env-only wrappers record nothing either).

Only modules that import gym (the code this run moves) are changed: a module already on
Gymnasium decided how its wrappers record themselves.

Source: Gymnasium 1.4 ``core.py`` (``Wrapper.spec``), ``envs/registration.py``
(``_create_from_env_id``'s recreation of ``additional_wrappers``),
``utils/record_constructor.py`` and ``wrappers/common.py`` (``TimeLimit.__init__``).
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.env_specs import recreates_from_spec
from gymmigrate.facts.module import FUNCTIONS, is_super_call, walk
from gymmigrate.facts.project_imports import imports_env_checker
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.env_ids.syntax import gym_alias

RULES = (
    Rule(
        "GM617",
        "wrapper constructor arguments",
        FixKind.AUTO,
        "A wrapper's `__init__` records its arguments with `RecordConstructorArgs`, so `make(env.spec)` and `check_env` can recreate it.",
    ),
)

_RECORD = "RecordConstructorArgs"
# Names an annotation may be made of for a value ``deepcopy`` always copies.
_PLAIN_ANNOTATIONS = frozenset(
    {
        "int", "float", "str", "bool", "complex", "bytes", "None", "Optional", "Union",
        "list", "List", "tuple", "Tuple", "dict", "Dict", "Sequence", "Mapping", "set", "Set",
        "np", "numpy", "ndarray", "NDArray", "typing", "npt",
        "float16", "float32", "float64", "int8", "int16", "int32", "int64", "uint8", "bool_",
    }
)


class WrapperConstructorArgs(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        # Code being moved off gym: a module already on Gymnasium chose how its wrappers record.
        return context.profile.imports_gym and ("Wrapper" in facts.text or "wrappers" in facts.text)

    def decide(self) -> None:
        for classdef in self.facts.all_classes:
            if not self.receivers.is_gym_wrapper_class(classdef) or self._records_already(classdef):
                continue
            if self.receivers.wraps_pz_parallel(classdef) or self.receivers.wraps_vec_env(classdef):
                continue  # no Gymnasium wrapper: reported (GM602)
            if self._derives_from_a_helper(classdef):
                continue
            init = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "__init__"), None)
            if init is not None:
                self._record(classdef, init)

    def _recreates_envs(self) -> bool:
        """The run (or this file, alone) calls ``check_env`` or ``make(x.spec)`` /
        ``x.spec.make()``: Gymnasium rebuilds wrapped envs from their spec there."""
        project = self.receivers.project
        if project is not None:
            return project.recreates_envs()
        return any(imports_env_checker(q) for q in self.facts.imports.values()) or recreates_from_spec(self.facts)

    def _derives_from_a_helper(self, classdef: ast.ClassDef) -> bool:
        """A base under ``gym.wrappers`` that is no wrapper: the monitoring recorders, the
        video encoder, the normalize statistics."""
        for base in classdef.bases:
            for q in self.facts.qualified_names(base):
                rest = N.strip_gym_prefix(q)
                if rest is None:
                    continue
                parts = rest.split(".")
                if parts[-1] in N.GYM_NOT_ENV_CLASSES or any(part in N.GYM_NOT_ENV_MODULES for part in parts[:-1]):
                    return True
        return False

    def _forwards_attributes(self, classdef: ast.ClassDef, seen: frozenset[str] = frozenset()) -> bool:
        """The class, or a base of it defined in this module, defines ``__getattr__`` or
        ``__getattribute__``: an attribute it lacks is looked up by its own code."""
        if any(isinstance(s, FUNCTIONS) and s.name in ("__getattr__", "__getattribute__") for s in classdef.body):
            return True
        by_name = {c.name: c for c in self.facts.all_classes}
        for base in classdef.bases:
            if isinstance(base, ast.Name) and base.id in by_name and base.id not in seen and by_name[base.id] is not classdef:
                if self._forwards_attributes(by_name[base.id], seen | {classdef.name}):
                    return True
        return False

    def _records_already(self, classdef: ast.ClassDef) -> bool:
        """A base or a call names ``RecordConstructorArgs`` (or ``EzPickle``, its gym-era cousin
        some wrappers used for pickling): the class decided how it records itself."""
        for node in walk(classdef):
            name = node.attr if isinstance(node, ast.Attribute) else node.id if isinstance(node, ast.Name) else None
            if name in (_RECORD, "EzPickle"):
                return True
        return False

    def _record(self, classdef: ast.ClassDef, init: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        args = init.args
        positional = [*args.posonlyargs, *args.args]
        if args.posonlyargs:
            return  # positional-only parameters cannot be recorded by name
        env = _env_param(init)
        if env is None:
            return  # no env parameter: not a wrapper constructor we can read
        if args.vararg is not None:
            # Gym could not recreate a wrapper at all: only a run that rebuilds envs from
            # their spec (``check_env``, ``make(env.spec)``) meets the ValueError.
            recreates = self._recreates_envs()
            self.report(
                init,
                "GM617",
                f"`{classdef.name}.__init__` takes `*{args.vararg.arg}`, which `RecordConstructorArgs` cannot record by "
                "name: `make(env.spec)` and `check_env` cannot recreate this wrapper until its arguments are recorded "
                f"(`gymnasium.utils.RecordConstructorArgs.__init__(self, name=value, ...)`)"
                + ("" if recreates else "; the run calls neither, so nothing recreates it now"),
                FixKind.FLAG,
                tier=None if recreates else Tier.NOTE,
            )
            return
        recorded = [a for a in (*positional[1:], *args.kwonlyargs) if a is not env]
        if not recorded and args.kwarg is None:
            return  # only the env: left as it is (nothing of its own to record)
        defaults = dict(zip([a.arg for a in positional][len(positional) - len(args.defaults) :], args.defaults))
        defaults.update((a.arg, d) for a, d in zip(args.kwonlyargs, args.kw_defaults) if d is not None)
        unsure = [a.arg for a in recorded if not _plain(a, defaults.get(a.arg))]
        if args.kwarg is not None:
            unsure.append(f"**{args.kwarg.arg}")
        alias = gym_alias(self.facts)
        direct = any(
            N.strip_gym_prefix(q) in N.GYM_WRAPPER_BASE_CLASSES for base in classdef.bases for q in self.facts.qualified_names(base)
        )
        record = f"{alias}.utils.{_RECORD}" if alias is not None else self.plan.ensure_import("gymnasium.utils", _RECORD)
        keywords = [f"{a.arg}={a.arg}" for a in recorded]
        if args.kwarg is not None:
            keywords.append(f"**{args.kwarg.arg}")
        if unsure:
            keywords.append("_disable_deepcopy=True")
        call = f"{record}.__init__({', '.join(['self', *keywords])})"
        body = init.body
        if self._forwards_attributes(classdef):
            # ``RecordConstructorArgs.__init__`` asks ``hasattr(self, "_saved_kwargs")``; a class
            # whose ``__getattr__`` forwards to ``self.env`` reads ``self.env`` there, before the
            # base ``__init__`` set it, and recurses (RecursionError, which hasattr does not
            # swallow): the arguments are recorded right after the base ``__init__``, as long as
            # no parameter recorded is rebound before it, and the base is Gymnasium's plain
            # wrapper (a base that records its own arguments would win: the first call does).
            base_call = _base_init_call(body)
            rebound = base_call is not None and _rebinds(body[: body.index(base_call)], {a.arg for a in recorded})
            if base_call is None or rebound or not direct:
                why = (
                    "its base records its own arguments first, and the first call wins"
                    if not direct
                    else "a parameter to record is rebound before that call"
                    if rebound
                    else "no base `__init__` call was found"
                )
                self.report(
                    classdef,
                    "GM617",
                    f"`{classdef.name}` forwards attributes (`__getattr__`), so `RecordConstructorArgs.__init__` (which reads "
                    f"an attribute) can only run once the base `__init__` has set `self.env`, and {why}"
                    + f": record the constructor arguments by hand after it (`{call}`) if `make(env.spec)` or `check_env` "
                    "must recreate this wrapper",
                    FixKind.FLAG,
                    tier=None if self._recreates_envs() else Tier.NOTE,
                )
                return
            self.plan.insert_after(base_call, call)
        elif _is_docstring(body[0]) and len(body) == 1:
            self.plan.insert_after(body[0], call)
        else:
            self.plan.insert_before(body[1] if _is_docstring(body[0]) else body[0], call)
        if direct:
            self.plan.replace(classdef, lambda node, record=record: _with_base(node, record))
        copy = (
            f"; `{'`, `'.join(unsure)}` may hold objects deepcopy cannot copy: recorded as they are, not copied"
            if unsure
            else ""
        )
        self.report(
            classdef,
            "GM617",
            f"`{classdef.name}` records its constructor arguments ({', '.join(keywords) or 'none besides env'})"
            + (f" and derives from `{_RECORD}`" if direct else "")
            + ": Gymnasium 1.x recreates wrappers from `env.spec` (`make(env.spec)`, `check_env`) and raises ValueError "
            f"for one that does not{copy}",
        )


def _env_param(init: ast.FunctionDef | ast.AsyncFunctionDef) -> ast.arg | None:
    """The parameter that takes the wrapped env: the one named ``env`` wherever it stands
    (``__init__(self, shape, env=None)``), as Gymnasium's recreation passes it
    (``wrapper(env=env, **kwargs)``); without one, the first after ``self``."""
    args = init.args
    named = next((a for a in (*args.args[1:], *args.kwonlyargs) if a.arg == "env"), None)
    if named is not None:
        return named
    return args.args[1] if len(args.args) >= 2 else None


def _plain(arg: ast.arg, default: ast.expr | None) -> bool:
    """The parameter holds a value ``deepcopy`` copies: its annotation names only plain
    types, or it has none and its default is a literal other than None."""
    if arg.annotation is not None:
        annotation: ast.AST = arg.annotation
        if isinstance(annotation, ast.Constant) and isinstance(annotation.value, str):
            try:
                annotation = ast.parse(annotation.value, mode="eval").body
            except SyntaxError:
                return False
        names = {n.id for n in walk(annotation) if isinstance(n, ast.Name)}
        names |= {n.attr for n in walk(annotation) if isinstance(n, ast.Attribute)}
        return bool(names) and names <= _PLAIN_ANNOTATIONS
    if default is None:
        return False
    literal = default.operand if isinstance(default, ast.UnaryOp) else default
    if isinstance(literal, (ast.Tuple, ast.List)):
        return all(isinstance(e, ast.Constant) for e in literal.elts) and bool(literal.elts)
    return isinstance(literal, ast.Constant) and literal.value is not None


def _base_init_call(body: list[ast.stmt]) -> ast.stmt | None:
    """The statement of ``body`` that calls the base ``__init__`` (``super().__init__(...)``,
    ``Base.__init__(self, ...)``), at the top level of the body."""
    for statement in body:
        if not (isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Call)):
            continue
        func = statement.value.func
        if isinstance(func, ast.Attribute) and func.attr == "__init__":
            owner = func.value
            if is_super_call(owner):
                return statement
            first = statement.value.args[:1]
            if isinstance(owner, (ast.Name, ast.Attribute)) and first and isinstance(first[0], ast.Name) and first[0].id == "self":
                return statement
    return None


def _rebinds(statements: list[ast.stmt], names: set[str]) -> bool:
    """A statement among ``statements`` binds one of ``names`` (an assignment, a loop
    target, a ``with ... as``, ``del``)."""
    for statement in statements:
        for node in walk(statement):
            if isinstance(node, ast.Name) and isinstance(node.ctx, (ast.Store, ast.Del)) and node.id in names:
                return True
    return False


def _is_docstring(statement: ast.stmt) -> bool:
    return isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant) and isinstance(statement.value.value, str)


def _with_base(node: cst.ClassDef, record: str) -> cst.ClassDef:
    bases = list(node.bases)
    last = bases[-1]
    bases[-1] = last.with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
    bases.append(cst.Arg(value=cst.parse_expression(record)))
    return node.with_changes(bases=bases)
