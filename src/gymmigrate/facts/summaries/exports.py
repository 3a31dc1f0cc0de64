"""What the top-level names of a module give to the modules that import them: every
name's ``Kind`` when called (``ModuleSummary.exports``), and the names bound to a Gym
callable (``ModuleSummary.aliases``)."""

from __future__ import annotations

import ast
from collections.abc import Iterator

from gymmigrate.facts import names as N
from gymmigrate.facts.creator_tables import (
    Field,
    entries,
    module_table,
    record_fields,
    record_positions,
)
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, own_returns
from gymmigrate.facts.module_summary import OWN, REF, Kind
from gymmigrate.facts.receiver_classes import duck_wrapper_param
from gymmigrate.facts.receivers import Receivers
from gymmigrate.facts.summaries.defs import made_value


class Exports:
    """The exports and aliases of one module."""

    def __init__(self, facts: ModuleFacts, receivers: Receivers) -> None:
        self.facts = facts
        self.receivers = receivers

    def exports(self, env_classes: set[str]) -> dict[str, Kind]:
        """Every top-level name the module binds with what calling it gives (see
        ``ModuleSummary.exports``)."""
        exports: dict[str, Kind] = {}
        for name, bindings in self.facts.module_scope.bindings.items():
            kinds = {self._export(name, binding, env_classes) for binding in bindings}
            kinds.discard(None)
            if len(kinds) == 1:
                exports[name] = kinds.pop()  # type: ignore[assignment]
            elif kinds:
                exports[name] = EnvKind.UNKNOWN
        return exports

    def tables(self, env_classes: set[str]) -> dict[tuple[str, Field], tuple[Kind, ...]]:
        """The module's closed tables of creators (``ModuleSummary.tables``): per table and
        field, what calling each of its callables gives."""
        return {(name, field): tuple(self._called(value, env_classes) for value in values) for name, field, values in self._creator_tables()}

    def made_tables(self, made_defs: frozenset[str]) -> dict[tuple[str, Field], tuple[str, ...]]:
        """Per closed table of creators and field (as ``tables``), whether each callable
        returns a ``make(...)`` result (``ModuleSummary.made_tables``): ``@`` when this
        module shows it (a lambda around ``make``, maybe in Gym wrappers; a def of
        ``made_defs``), ``ref:<qualified>`` for a call of a name of another module of the
        run (made when the run says so), "" otherwise."""
        return {(name, field): tuple(self._made(value, made_defs) for value in values) for name, field, values in self._creator_tables()}

    def _creator_tables(self) -> Iterator[tuple[str, Field, list[ast.expr]]]:
        """Every closed table of callables the module binds once at top level, per field
        ("" for the table's own values): its name, the field and the callables, so that
        ``tables`` and ``made_tables`` always describe the same tables."""
        for name, bindings in self.facts.module_scope.bindings.items():
            if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
                continue
            display = module_table(self.facts, bindings[0])
            if display is None:
                continue
            fields: list[Field | None] = [None, *sorted(record_fields(display)), *record_positions(display)]
            for field in fields:
                values = entries(display, field)
                # only callables: a table of numbers or strings is no table of creators
                if values is not None and all(isinstance(v, (ast.Lambda, ast.Name, ast.Attribute)) for v in values):
                    yield name, "" if field is None else field, values

    def _made(self, value: ast.expr, made_defs: frozenset[str]) -> str:
        if isinstance(value, ast.Lambda):
            if made_value(self.facts, value.body, value, self.receivers):
                return OWN
            if not (isinstance(value.body, ast.Call) and isinstance(value.body.func, (ast.Name, ast.Attribute))):
                return ""
            value = value.body.func
        if isinstance(value, ast.Name) and value.id in made_defs and self.facts.module_scope.bindings.get(value.id) == self.facts.bindings_of(value):
            return OWN
        qualified = self.facts.qualified_names(value)
        if len(qualified) == 1 and not N.is_library(name := next(iter(qualified))):
            return REF + name
        return ""

    def _called(self, value: ast.expr, env_classes: set[str]) -> Kind:
        """What calling a table's value gives, for another module: a lambda's body (a call
        of a name of the run: what calling that name gives), a top-level name as its export."""
        if isinstance(value, ast.Lambda):
            kind = self.receivers.kind_of(value.body)
            if kind is EnvKind.UNKNOWN and isinstance(value.body, ast.Call) and isinstance(value.body.func, (ast.Name, ast.Attribute)):
                return self._called(value.body.func, env_classes)
            return kind
        if isinstance(value, ast.Name):
            bindings = self.facts.bindings_of(value)
            if len(bindings) == 1 and self.facts.module_scope.bindings.get(value.id) == bindings:
                export = self._export(value.id, bindings[0], env_classes)
                return EnvKind.UNKNOWN if export is None else export
        elif isinstance(value, ast.Attribute):
            qualified = self.facts.qualified_names(value)
            if len(qualified) == 1:
                return self._reference(qualified.pop())
        return self.receivers.returned_kind(value)

    def _export(self, name: str, binding: ast.AST, env_classes: set[str]) -> Kind | None:
        if isinstance(binding, ast.alias):
            return self._reference(self.facts.imports[binding])
        if isinstance(binding, ast.ClassDef):
            kind = self.receivers.class_kind(binding)
            if name in env_classes and kind is not EnvKind.OWN_API:
                kind = EnvKind.GYM_ENV
            if kind is EnvKind.NOT_ENV and duck_wrapper_param(binding) is not None and not self.receivers.derives_own_api(binding):
                # A duck wrapper its own module cannot prove (other modules build it): what
                # its instances are is decided where they are made, never "no env".
                return EnvKind.UNKNOWN
            if kind is EnvKind.UNKNOWN:
                return self._run_base(binding) or kind
            return kind
        if isinstance(binding, FUNCTIONS):
            kind = self.receivers.returns_kind(binding)
            if kind is EnvKind.UNKNOWN:
                # ``def make_benchmark(...): return NASimEnv(scenario, **kwargs)`` with the class
                # imported from another module of the run: what calling that name gives
                made = self._returned_run_call(binding)
                if made is not None:
                    return REF + made
            return kind
        if isinstance(binding, ast.Name):
            parent = self.facts.parent(binding)
            if isinstance(parent, ast.Assign) and len(parent.targets) == 1 and parent.targets[0] is binding:
                value = parent.value
                if isinstance(value, (ast.Name, ast.Attribute)):
                    qualified = self.facts.qualified_names(value)
                    if len(qualified) == 1:
                        return self._reference(qualified.pop())  # ``make = gym.make``
                    return self.receivers.returned_kind(value)
                if isinstance(value, ast.Call):
                    # ``parallel_env = parallel_wrapper_fn(env)``: a factory made by a factory.
                    if any(q.endswith(".parallel_wrapper_fn") for q in self.facts.qualified_names(value.func)):
                        return EnvKind.PZ_PARALLEL
                    return self.receivers.returned_kind(value)
        return EnvKind.UNKNOWN

    def _run_base(self, classdef: ast.ClassDef) -> str | None:
        """``ref:`` the class of another module of the run that ``classdef`` derives from
        (``class Hunter(HuntEnv)`` with ``HuntEnv`` imported), through the bases of this
        module it derives from (``class Task(Mid)`` with ``class Mid(HuntEnv)`` here: its
        module cannot tell what ``Mid`` is either). With several such bases (``class
        Flock(BaseAviary, MultiAgentEnv)``), the first one's, as ``class_kind`` takes the
        first base that says anything. None where no base is one."""
        return self.facts.memo(("run-base", id(classdef)), lambda: self._compute_run_base(classdef), while_computing=None)

    def _compute_run_base(self, classdef: ast.ClassDef) -> str | None:
        for base in classdef.bases:
            run_bases = [q for q in self.facts.qualified_names(base) if not N.is_library(q)]
            if len(run_bases) == 1:
                return REF + run_bases[0]
            if run_bases:
                return None
            local = self.receivers.local_class(base)
            if local is not None and local is not classdef and self.receivers.class_kind(local) is EnvKind.UNKNOWN:
                found = self._run_base(local)
                if found is not None:
                    return found
        return None

    def _returned_run_call(self, function: ast.FunctionDef | ast.AsyncFunctionDef) -> str | None:
        """The one imported name every return of ``function`` calls (``return Env(...)``),
        when it is no library's, through the defs of this module the returns call
        (``return _dress(env)`` with ``_dress`` returning ``wrappers.Logged(env)``); else None.
        A def met again while its own answer is computed (recursion) adds nothing."""
        return self.facts.memo(("returned-run-call", id(function)), lambda: self._compute_returned_run_call(function), while_computing=None)

    def _compute_returned_run_call(self, function: ast.FunctionDef | ast.AsyncFunctionDef) -> str | None:
        found: set[str] = set()
        for ret in own_returns(function):
            value = ret.value
            if isinstance(value, ast.Name):
                # ``env = make(...); env.seed(s); env = dress(env); return env``: the call the
                # returned name holds on every path (``dress`` of another module of the run)
                reaching = self.receivers.values_reaching(value)
                value = reaching[0] if reaching is not None and len(reaching) == 1 else None
            if not (isinstance(value, ast.Call) and isinstance(value.func, (ast.Name, ast.Attribute))):
                return None
            declared = self._declared_class_parameter(function, value.func)
            if declared is not None:
                found.add(declared)
                continue
            local = self.receivers.local_function(value.func)
            if local is not None:
                # A def of this module whose returns ``returns_kind`` could not judge either:
                # one that hands on what a name of another module makes (``_dress`` putting
                # wrappers of the run around the env it is given) makes what that name makes.
                called = self._returned_run_call(local)
                if called is None:
                    return None
                found.add(called)
                continue
            qualified = self.facts.qualified_names(value.func)
            if len(qualified) != 1:
                return None
            name = next(iter(qualified))
            if N.is_library(name) or "." not in name:
                return None  # a library's, or a name of this module (``returns_kind`` judged it)
            found.add(name)
        return found.pop() if len(found) == 1 else None

    def _declared_class_parameter(self, function: ast.FunctionDef | ast.AsyncFunctionDef, func: ast.expr) -> str | None:
        """``def make(spec, env_class=GridEnv) -> GridEnv: return env_class(spec)``: a call of a
        parameter of ``function`` whose default and the def's return annotation name the same
        class of another module of the run. Whatever class a caller hands in, the def declares
        its result an instance of that class (a subclass at most), so its callers get what
        calling the class gives. A default alone is no proof (a caller may pass another
        class); an annotation alone over an unknown callable is not read either."""
        if not isinstance(func, ast.Name) or function.returns is None:
            return None
        arguments = function.args
        positional = [*arguments.posonlyargs, *arguments.args]
        defaults: dict[str, ast.expr] = dict(zip((a.arg for a in positional[len(positional) - len(arguments.defaults) :]), arguments.defaults))
        defaults.update((a.arg, d) for a, d in zip(arguments.kwonlyargs, arguments.kw_defaults) if d is not None)
        default = defaults.get(func.id)
        if default is None or self.facts.bindings_of(func) != [p for p in (*positional, *arguments.kwonlyargs) if p.arg == func.id]:
            return None  # no parameter of this def, or one rebound before the call
        named = self.facts.qualified_names(default)
        if len(named) != 1 or named != self.facts.qualified_names(function.returns):
            return None
        name = next(iter(named))
        return None if N.is_library(name) or "." not in name else name

    def aliases(self) -> dict[str, str]:
        """Top-level names bound to a Gym callable: ``make = gym.make``, ``from gym import make``."""
        found: dict[str, str] = {}
        for name, bindings in self.facts.module_scope.bindings.items():
            if len(bindings) != 1:
                continue
            binding = bindings[0]
            if isinstance(binding, ast.alias):
                qualified = {self.facts.imports[binding]}
            elif isinstance(binding, ast.Name) and isinstance(assign := self.facts.parent(binding), ast.Assign) and isinstance(assign.value, (ast.Name, ast.Attribute)):
                qualified = self.facts.qualified_names(assign.value)
            else:
                continue
            if len(qualified) == 1 and N.strip_gym_prefix(next(iter(qualified))) is not None:
                found[name] = qualified.pop()
        return found

    def _reference(self, qualified: str) -> Kind:
        if not N.is_library(qualified):
            return REF + qualified
        kind = self.receivers.kind_from_qualified(qualified, ast.Call(func=ast.Name(id="_"), args=[], keywords=[]))
        return kind if kind is not None else EnvKind.UNKNOWN


def star_bases(facts: ModuleFacts) -> frozenset[str]:
    """The plain names the module's top-level classes derive that it never binds itself:
    where it has star imports, one of them may bind the name (``class Child(Base)`` after
    ``from .base import *``)."""
    if not facts.star_imports:
        return frozenset()
    bound = facts.module_scope.bindings
    # a name the run's star bindings bound stays one (every join of the run finds it again)
    return frozenset(
        base.id
        for classdef in facts.classes.values()
        for base in classdef.bases
        if isinstance(base, ast.Name) and (base.id not in bound or base.id in facts.star_bindings)
    )


def declared_all(facts: ModuleFacts) -> tuple[str, ...] | None:
    """The module's ``__all__``: None without one; () where its text does not show the
    names (built, extended or assigned more than once), so a star import of it binds no
    name the run can be sure of."""
    if "__all__" not in facts.text:
        return None  # most modules: no walk
    found: list[ast.expr] = []
    for statement in ast.walk(facts.tree):
        if isinstance(statement, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "__all__" for t in statement.targets):
            found.append(statement.value)
        elif isinstance(statement, (ast.AugAssign, ast.AnnAssign)) and isinstance(statement.target, ast.Name) and statement.target.id == "__all__":
            found.append(statement.value or ast.Constant(None))
        elif isinstance(statement, ast.Attribute) and isinstance(statement.value, ast.Name) and statement.value.id == "__all__":
            found.append(ast.Constant(None))  # ``__all__.append(...)``, ``__all__.extend(...)``
    if not found:
        return None
    value = found[0]
    if len(found) > 1 or not isinstance(value, (ast.List, ast.Tuple)):
        return ()
    names = [item.value for item in value.elts if isinstance(item, ast.Constant) and isinstance(item.value, str)]
    return tuple(names) if len(names) == len(value.elts) else ()
