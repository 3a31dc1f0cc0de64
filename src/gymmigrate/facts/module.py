"""What one module says about its names, computed once from CPython's ``ast``.

Every rule asks the same questions: where does this name come from, which import
does ``gym`` stand for, what encloses this node, which calls name this function.
``ModuleFacts`` answers them from a single walk over the tree (``ast`` is several
times cheaper to build and walk than a LibCST tree), and memoizes everything else.

The walk is iterative, so deep expressions and long chains cannot overflow the
interpreter's stack, and every lookup is linear or better in the size of the file.
"""

from __future__ import annotations

import ast
import io
import weakref
from collections import defaultdict
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from itertools import chain
from typing import NamedTuple, TypeGuard, cast

FUNCTIONS = (ast.FunctionDef, ast.AsyncFunctionDef)
COMPREHENSIONS = (ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp)
SCOPES = (ast.Module, *FUNCTIONS, ast.ClassDef, ast.Lambda, *COMPREHENSIONS)
LOOPS = (ast.For, ast.AsyncFor, ast.While)
_UNSET = object()
# Statements that hold blocks; ``try/except*`` and ``match`` where this Python has them.
COMPOUND_STATEMENTS = (
    *FUNCTIONS,
    ast.ClassDef,
    ast.If,
    *LOOPS,
    ast.With,
    ast.AsyncWith,
    ast.Try,
    *((ast.TryStar,) if hasattr(ast, "TryStar") else ()),
    *((ast.Match,) if hasattr(ast, "Match") else ()),
)


@dataclass(eq=False)
class Scope:
    """A module, class, function, lambda or comprehension scope."""

    node: ast.AST
    parent: Scope | None
    bindings: dict[str, list[ast.AST]] = field(default_factory=lambda: defaultdict(list))
    reads: dict[str, list[ast.Name]] = field(default_factory=lambda: defaultdict(list))
    declared_global: set[str] = field(default_factory=set)
    declared_nonlocal: set[str] = field(default_factory=set)

    @property
    def is_class(self) -> bool:
        return isinstance(self.node, ast.ClassDef)

    @property
    def is_function(self) -> bool:
        return isinstance(self.node, (*FUNCTIONS, ast.Lambda))


# Fields that can hold child nodes, per node class. ``ctx`` (Load/Store) and operators
# (``op``, ``ops``) are shared singletons in a parsed tree: no fact is about them, and
# skipping them saves about a third of the walk.
_SKIPPED_FIELDS = frozenset({"ctx", "op", "ops"})
_CHILD_FIELDS: dict[type, tuple[str, ...]] = {}


def statements_in(node: ast.AST) -> list[ast.AST]:
    """The statements (and except/case clauses) directly inside ``node``: enough to find
    what only statements do (return, assign) without walking every expression."""
    return [child for child in child_nodes(node) if isinstance(child, _STATEMENT_LIKE)]


_STATEMENT_LIKE = (ast.stmt, ast.excepthandler, ast.match_case)


def child_nodes(node: ast.AST) -> list[ast.AST]:
    """``ast.iter_child_nodes`` in the same order, without contexts and operators."""
    fields = _CHILD_FIELDS.get(type(node))
    if fields is None:
        fields = _CHILD_FIELDS[type(node)] = tuple(f for f in node._fields if f not in _SKIPPED_FIELDS)
    children: list[ast.AST] = []
    for name in fields:
        value = getattr(node, name, None)
        if isinstance(value, list):
            children.extend(item for item in value if isinstance(item, ast.AST))
        elif isinstance(value, ast.AST):
            children.append(value)
    return children


class ModuleFacts:
    """Parents, scopes, bindings, imports and definitions of one module.

    A *binding* is the node that binds a name: an ``ast.Name`` in store context, an
    ``ast.arg``, an ``ast.alias`` (imports), or a ``FunctionDef``/``ClassDef``.
    """

    def __init__(self, tree: ast.Module, text: str, star_bindings: Mapping[str, str] | None = None) -> None:
        self.tree = tree
        self.text = text
        # Names this module reads that only its star imports of the run's modules bind, with
        # the qualified name each stands for (``{"Base": ".base.Base"}``; the run's join,
        # ``ProjectFacts.star_bindings``): bound as if imported by name, so that a class
        # deriving one is known the way ``from .base import Base`` would make it known.
        self.star_bindings: Mapping[str, str] = star_bindings or {}
        # Split where the tokenizer does (\n, \r\n, \r), not at form feeds or \u2028 as
        # str.splitlines would, so line numbers agree with ast's.
        self.lines = io.StringIO(text, newline="").readlines()
        self._line_starts: list[int] | None = None
        self.parents: dict[ast.AST, ast.AST] = {}
        self.scopes: dict[ast.AST, Scope] = {}  # scope-creating node -> its Scope
        self._scope_of: dict[ast.AST, Scope] = {}  # Name / arg / alias / def -> scope it lives in
        self.imports: dict[ast.alias, str] = {}  # import binding -> qualified name it binds
        self.star_imports: tuple[str, ...] = ()  # modules of ``from M import *`` at module level
        self.calls_by_name: dict[str, list[ast.Call]] = defaultdict(list)
        self.attribute_calls: dict[str, list[ast.Call]] = defaultdict(list)  # x.<attr>(...)
        self.lookup_calls: list[ast.Call] = []  # x[k](...): a call through a table of creators, maybe
        self.attributes: dict[str, list[ast.Attribute]] = defaultdict(list)  # every x.<attr>, by attr
        self.classes: dict[str, ast.ClassDef] = {}  # module-level classes
        self.functions: dict[str, ast.FunctionDef | ast.AsyncFunctionDef] = {}  # module-level functions
        self.all_classes: list[ast.ClassDef] = []
        self.strings: list[ast.Constant] = []
        self.import_statements: list[ast.Import | ast.ImportFrom] = []
        self._memo: dict[tuple[str, int], object] = {}
        # Every store into ``_memo`` counts: a receiver answer cut short by a cycle may be
        # reused only while no fact it could have read has changed (``Receivers.kind_of``).
        self.memo_writes = 0
        # Whether a qualified name is a record class of another module of the run (set by the
        # engine from the run's facts; ``done_uses.builds_record``). None of them outside a run.
        self.is_run_record: Callable[[str], bool] = _no_record
        self.module_scope = Scope(tree, None)
        self.scopes[tree] = self.module_scope
        self._walk()

    # -- the one walk ------------------------------------------------------------------

    def _walk(self) -> None:
        parents = self.parents
        stack: list[tuple[ast.AST, Scope]] = [(self.tree, self.module_scope)]
        while stack:
            node, scope = stack.pop()
            inner = self._enter(node, scope)
            if inner is not None:
                pushed = self._scoped_children(node, scope, inner)
            elif isinstance(node, ast.arguments):  # defaults are evaluated where the def is
                outside = scope.parent or scope
                pushed = [(c, scope if isinstance(c, ast.arg) else outside) for c in child_nodes(node)]
            else:
                pushed = [(child, scope) for child in child_nodes(node)]
            # Reversed so the stack pops children in source order.
            for child, child_scope in reversed(pushed):
                parents[child] = node
                stack.append((child, child_scope))

    def _enter(self, node: ast.AST, scope: Scope) -> Scope | None:
        """Record what ``node`` binds or reads; return the scope it opens, if any."""
        if isinstance(node, ast.Name):
            self._scope_of[node] = scope
            if isinstance(node.ctx, ast.Load):
                scope.reads[node.id].append(node)
            else:
                self._bind(scope, node.id, node)
            return None
        if isinstance(node, ast.Call):
            func = node.func
            if isinstance(func, ast.Name):
                self.calls_by_name[func.id].append(node)
            elif isinstance(func, ast.Attribute):
                self.attribute_calls[func.attr].append(node)
            elif isinstance(func, ast.Subscript):
                self.lookup_calls.append(node)
            return None
        if isinstance(node, ast.Attribute):
            self.attributes[node.attr].append(node)
            return None
        if isinstance(node, ast.Constant):
            if isinstance(node.value, str):
                self.strings.append(node)
            return None
        if isinstance(node, (*FUNCTIONS, ast.ClassDef)):
            self._scope_of[node] = scope
            self._bind(scope, node.name, node)
            if scope is self.module_scope:
                if isinstance(node, ast.ClassDef):
                    self.classes[node.name] = node
                else:
                    self.functions[node.name] = node
            if isinstance(node, ast.ClassDef):
                self.all_classes.append(node)
            inner = Scope(node, scope)
            self.scopes[node] = inner
            return inner
        if isinstance(node, (ast.Lambda, *COMPREHENSIONS)):
            inner = Scope(node, scope)
            self.scopes[node] = inner
            return inner
        if isinstance(node, ast.arguments):
            return None
        if isinstance(node, ast.arg):
            self._scope_of[node] = scope
            self._bind(scope, node.arg, node)
            return None
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            self.import_statements.append(node)
            self._record_import(node, scope)
            return None
        if isinstance(node, ast.Global):
            scope.declared_global.update(node.names)
            return None
        if isinstance(node, ast.Nonlocal):
            scope.declared_nonlocal.update(node.names)
            return None
        if isinstance(node, ast.ExceptHandler) and node.name:
            self._scope_of[node] = scope
            self._bind(scope, node.name, node)
        return None

    @staticmethod
    def _scoped_children(node: ast.AST, outer: Scope, inner: Scope) -> list[tuple[ast.AST, Scope]]:
        """Children of a scope-opening node, each with the scope it is evaluated in.

        Decorators, bases, defaults and annotations run in the enclosing scope; parameter
        names and the body bind in the new one.
        """
        pushed: list[tuple[ast.AST, Scope]] = []
        if isinstance(node, (*FUNCTIONS, ast.Lambda)):
            for decorator in getattr(node, "decorator_list", ()):
                pushed.append((decorator, outer))
            arguments = node.args
            pushed.append((arguments, inner))
            if isinstance(node, ast.Lambda):
                pushed.append((node.body, inner))
            else:
                pushed.extend((statement, inner) for statement in node.body)
                if node.returns is not None:
                    pushed.append((node.returns, outer))
            return pushed
        if isinstance(node, ast.ClassDef):
            pushed.extend((decorator, outer) for decorator in node.decorator_list)
            pushed.extend((base, outer) for base in node.bases)
            pushed.extend((kw, outer) for kw in node.keywords)
            pushed.extend((statement, inner) for statement in node.body)
            return pushed
        return [(child, inner) for child in child_nodes(node)]  # comprehensions

    def _bind(self, scope: Scope, name: str, node: ast.AST) -> None:
        target = self.module_scope if name in scope.declared_global else scope
        target.bindings[name].append(node)

    def _record_import(self, node: ast.Import | ast.ImportFrom, scope: Scope) -> None:
        for alias in node.names:
            if isinstance(node, ast.Import):
                bound = alias.asname or alias.name.split(".", 1)[0]
                qualified = alias.name if alias.asname else bound
            else:
                if alias.name == "*":
                    if scope is self.module_scope:  # ``from utils.wrappers import *``
                        self.star_imports += ("." * node.level + (node.module or ""),)
                        self._bind_star_names(node, alias)
                    continue
                base = "." * node.level + (node.module or "")
                bound = alias.asname or alias.name
                qualified = f"{base}.{alias.name}" if base and not base.endswith(".") else base + alias.name
            self._scope_of[alias] = scope
            self.imports[alias] = qualified
            self._bind(scope, bound, alias)

    def _bind_star_names(self, node: ast.ImportFrom, star: ast.alias) -> None:
        """Bind the names ``star_bindings`` gives this star import, each to an alias of its
        own (not in the tree: no rule edits it) placed where the star import is."""
        base = "." * node.level + (node.module or "")
        for name, qualified in self.star_bindings.items():
            if qualified != (f"{base}.{name}" if base and not base.endswith(".") else base + name):
                continue
            bound = ast.alias(name=name, asname=None)
            ast.copy_location(bound, star)
            self.parents[bound] = node
            self._scope_of[bound] = self.module_scope
            self.imports[bound] = qualified
            self._bind(self.module_scope, name, bound)

    # -- structure ----------------------------------------------------------------------

    def parent(self, node: ast.AST | None) -> ast.AST | None:
        """The node's parent; ``None`` for the module, for a node outside the tree and for
        ``None`` itself (so ``parent(parent(param))`` walks arg -> arguments -> def)."""
        return None if node is None else self.parents.get(node)

    def ancestors(self, node: ast.AST) -> Iterator[ast.AST]:
        current = self.parents.get(node)
        while current is not None:
            yield current
            current = self.parents.get(current)

    def enclosing(self, node: ast.AST, kind: type | tuple[type, ...]) -> ast.AST | None:
        for ancestor in self.ancestors(node):
            if isinstance(ancestor, kind):
                return ancestor
        return None

    def statement_of(self, node: ast.AST) -> ast.stmt:
        """The innermost statement that contains ``node`` (``node`` itself if it is one)."""
        current: ast.AST | None = node
        while current is not None and not isinstance(current, ast.stmt):
            current = self.parents.get(current)
        assert current is not None, "every node of a module sits in a statement"
        return current

    def enclosing_function(self, node: ast.AST) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        return self.enclosing(node, FUNCTIONS)  # type: ignore[return-value]

    def enclosing_class(self, node: ast.AST) -> ast.ClassDef | None:
        return self.enclosing(node, ast.ClassDef)  # type: ignore[return-value]

    def is_method(self, function: ast.AST) -> bool:
        parent = self.parents.get(function)
        return isinstance(parent, ast.ClassDef) and function in parent.body

    def parameter_slot(self, param: ast.arg) -> ParameterSlot | None:
        """Where the calls of its def pass ``param``; None for ``self`` (a method's first
        parameter), a lambda's parameter, and one passed only by keyword or in ``*args``."""
        function = self.parent(self.parent(param))  # arg -> arguments -> def
        if not isinstance(function, FUNCTIONS):
            return None
        params = [*function.args.posonlyargs, *function.args.args]
        position = next((i for i, p in enumerate(params) if p is param), None)
        if position is None:
            return None
        classdef = self.parent(function)
        if isinstance(classdef, ast.ClassDef) and self.is_method(function):
            return ParameterSlot(function, classdef, position - 1) if position > 0 else None  # calls do not pass self
        return ParameterSlot(function, None, position)

    # -- names ----------------------------------------------------------------------------

    def scope_of(self, node: ast.AST) -> Scope:
        """The scope a Name/arg/alias/def lives in (for other nodes, the enclosing one)."""
        scope = self._scope_of.get(node)
        if scope is not None:
            return scope
        child = node
        for ancestor in self.ancestors(node):
            # A class body is a scope; its decorators and bases run in the enclosing one.
            if ancestor in self.scopes and not (isinstance(ancestor, ast.ClassDef) and child not in ancestor.body):
                return self.scopes[ancestor]
            child = ancestor
        return self.module_scope

    def resolve(self, name: str, scope: Scope) -> tuple[Scope | None, list[ast.AST]]:
        """The scope that binds ``name`` as seen from ``scope``, and its bindings."""
        current: Scope | None = scope
        first = True
        while current is not None:
            if name in current.declared_global:
                current = self.module_scope
            if current.is_class and not first:
                current = current.parent  # class bodies are not enclosing scopes for functions
                continue
            found = current.bindings.get(name)
            if found:
                return current, found
            first = False
            current = current.parent
        return None, []

    def bindings_of(self, name: ast.Name) -> list[ast.AST]:
        return self.resolve(name.id, self.scope_of(name))[1]

    def reaching_bindings(self, name: ast.Name) -> list[ast.AST]:
        """The bindings of ``name`` that may still hold when it is read: ``bindings_of``
        without the module-level ones a later unconditional module-level binding replaces
        (``from gym.wrappers import Monitor`` then ``from wrappers import Monitor``: only
        the second reaches a read after it, or in a function, which runs once the module
        has run). Bindings under ``if``/``try`` or in a loop replace nothing: which one
        holds is not known, so all of them stay."""
        scope, bindings = self.resolve(name.id, self.scope_of(name))
        if scope is not self.module_scope or len(bindings) < 2:
            return bindings
        at = self._import_time_index(name)
        by_position = cast("dict[int, list[ast.AST]]", self._memo.setdefault(("reaching-bindings", id(bindings)), {}))
        found = by_position.get(-1 if at is None else at)
        if found is None:
            ordered = [(binding, self._import_time_index(binding)) for binding in bindings]
            if at is not None:  # read while the module runs: only what ran before it
                ordered = [(b, i) for b, i in ordered if i is None or i <= at]
            replaced = max(
                (i for b, i in ordered if i is not None and (at is None or i < at) and self._binds_unconditionally(b)),
                default=None,
            )
            kept = [b for b, i in ordered if replaced is None or i is None or i >= replaced]
            found = by_position[-1 if at is None else at] = kept or bindings
        return found

    def _import_time_index(self, node: ast.AST) -> int | None:
        """The index in the module body of the statement ``node`` runs in when it runs as
        the module is imported; None when it runs in a function or lambda (called later)."""
        scope: Scope | None = self._scope_of.get(node) or self.scope_of(node)
        while scope is not None:
            if scope.is_function:
                return None
            scope = scope.parent
        top: ast.AST = node
        for ancestor in self.ancestors(node):
            if ancestor is self.tree:
                break
            top = ancestor
        return self._top_index().get(top)

    def _top_index(self) -> dict[ast.AST, int]:
        found = self._memo.get(("top-index", 0))
        if found is None:
            found = self._memo[("top-index", 0)] = {statement: i for i, statement in enumerate(self.tree.body)}
        return cast("dict[ast.AST, int]", found)

    def _binds_unconditionally(self, binding: ast.AST) -> bool:
        """A binding made by a statement of the module body itself (an import, assignment,
        def or class outside any ``if``, ``try``, ``with`` or loop): it always runs."""
        statement = binding if isinstance(binding, ast.stmt) else self.statement_of(binding)
        if isinstance(statement, ast.AnnAssign) and statement.value is None:
            return False  # ``name: T`` binds nothing when it runs
        return self.parent(statement) is self.tree and isinstance(
            statement, (ast.Import, ast.ImportFrom, ast.Assign, ast.AnnAssign, *FUNCTIONS, ast.ClassDef)
        )

    def reads_of(self, name: str, binding: ast.AST | None = None) -> list[ast.Name]:
        """Every read of ``name`` in the module, in every scope (from the index the walk
        built, no second walk); with ``binding``, only the reads it may reach."""
        reads = [read for scope in self.scopes.values() for read in scope.reads.get(name, ())]
        if binding is None:
            return reads
        return [read for read in reads if binding in self.reaching_bindings(read)]

    def assigned_values(self, name: ast.Name, *, sole_target: bool = False) -> list[ast.expr] | None:
        """The values of every ``name = ...`` binding of ``name``; None when one binds it
        otherwise (a parameter, a loop or tuple target, an import...).

        ``sole_target``: ``a = b = value`` counts as bound otherwise too. The parameter
        analysis (``receiver_params.py`` with ``receiver_callers.py`` and
        ``receiver_thunks.py``) has only ever followed single-target assignments, and taking
        chained ones there would change what it concludes of a callee.
        """
        values: list[ast.expr] = []
        for binding in self.bindings_of(name):
            parent = self.parent(binding) if isinstance(binding, ast.Name) else None
            if not isinstance(parent, ast.Assign):
                return None
            if (parent.targets != [binding]) if sole_target else (binding not in parent.targets):
                return None
            values.append(parent.value)
        return values

    def qualified_names(self, expr: ast.AST) -> set[str]:
        """Library names ``expr`` stands for through imports: ``gym.make`` -> {"gym.make"}."""
        if isinstance(expr, ast.Name):
            bindings = self.reaching_bindings(expr)
            if not bindings:
                return set()
            # One answer per set of bindings, not per read: a name rebound n times is read
            # about n times, and each read would otherwise scan all n bindings.
            key = ("qualified-names", id(bindings))
            found = self._memo.get(key)
            if found is None:
                found = self._memo[key] = frozenset(
                    self.imports[binding] for binding in bindings if isinstance(binding, ast.alias)
                )
            return set(cast("frozenset[str]", found))  # only this code stores under the key
        if isinstance(expr, ast.Attribute):
            return {f"{q}.{expr.attr}" for q in self.qualified_names(expr.value)}
        return set()

    def imported_as(self, qualified: str) -> str | None:
        """A module-level name bound to ``qualified`` (``numpy`` -> ``np``), if any."""
        for alias, name in self.imports.items():
            if name == qualified and self._scope_of.get(alias) is self.module_scope:
                return alias.asname or alias.name.split(".", 1)[0]
        return None

    # -- source -------------------------------------------------------------------------

    def segment(self, node: ast.AST) -> str:
        """The exact source text of ``node`` (without its parentheses), except that an
        expression which is only valid in parentheses (a walrus, a ``yield``) gets them,
        so that the text can stand in any expression position it is moved to."""
        if getattr(node, "end_lineno", None) is None:
            return ""
        start = self.offset(node.lineno, node.col_offset)  # type: ignore[attr-defined]
        end = self.offset(node.end_lineno, node.end_col_offset)  # type: ignore[attr-defined]
        return parenthesized_if_needed(node, self.text[start:end])

    def line_start(self, line: int) -> int:
        """Character offset in the text where ``line`` (1-based) starts; one past the last
        line gives the length of the text."""
        if self._line_starts is None:
            starts, total = [], 0
            for text_line in self.lines:
                starts.append(total)
                total += len(text_line)
            starts.append(total)
            self._line_starts = starts
        return self._line_starts[min(line - 1, len(self._line_starts) - 1)]

    def offset(self, line: int, byte_column: int) -> int:
        """Character offset in the text of an ast position (1-based line, UTF-8 byte column)."""
        text_line = self.lines[line - 1] if 0 < line <= len(self.lines) else ""
        column = byte_column if text_line.isascii() else len(text_line.encode("utf-8")[:byte_column].decode("utf-8", "replace"))
        return self.line_start(line) + column

    def column(self, node: ast.AST) -> int:
        """``ast`` columns count UTF-8 bytes; findings count characters."""
        return self._characters(node.lineno, node.col_offset)  # type: ignore[attr-defined]

    def end(self, node: ast.AST) -> tuple[int | None, int | None]:
        """Where ``node`` ends (1-based line, 0-based character column), when ``ast`` knows."""
        line = getattr(node, "end_lineno", None)
        offset = getattr(node, "end_col_offset", None)
        if line is None or offset is None:
            return None, None
        return line, self._characters(line, offset)

    def _characters(self, lineno: int, offset: int) -> int:
        line = self.lines[lineno - 1] if 0 < lineno <= len(self.lines) else ""
        if line.isascii():
            return offset
        return len(line.encode("utf-8")[:offset].decode("utf-8", errors="replace"))

    def peek(self, key: tuple[str, int]) -> object | None:
        """The memoized fact under ``key``, or None when it has not been computed."""
        return self._memo.get(key)

    def memo(self, key: tuple[str, int], compute, while_computing: object = _UNSET):
        """Memoize a per-node fact under ``(fact name, id(node))``.

        ``while_computing``: the answer a recursive question about the same key gets while
        ``compute`` runs (e.g. "unknown": a cycle such as ``env = wrap(env)`` adds no evidence).
        """
        try:
            return self._memo[key]
        except KeyError:
            pass
        if while_computing is not _UNSET:
            self._memo[key] = while_computing
            self.memo_writes += 1
        value = self._memo[key] = compute()
        self.memo_writes += 1
        return value


    def computing(self, key: tuple[str, int]) -> bool:
        """``memo`` is computing ``key`` now, asked with ``while_computing=None`` (a fact whose
        answers are never None): a recursive question about it is inside that computation."""
        return key in self._memo and self._memo[key] is None


def param_default(function: ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda, param: ast.arg) -> ast.expr | None:
    """The default value of ``param`` in ``function``'s signature, if it has one."""
    args = function.args
    positional = [*args.posonlyargs, *args.args]
    if param in positional:
        index = positional.index(param) - (len(positional) - len(args.defaults))
        return args.defaults[index] if index >= 0 else None
    if param in args.kwonlyargs:
        return args.kw_defaults[args.kwonlyargs.index(param)]
    return None


def dotted_name(expr: ast.AST) -> str | None:
    """``a.b.c`` for a chain of attributes on a name, else None."""
    parts = []
    while isinstance(expr, ast.Attribute):
        parts.append(expr.attr)
        expr = expr.value
    if not isinstance(expr, ast.Name):
        return None
    parts.append(expr.id)
    return ".".join(reversed(parts))


def full_name(node: ast.AST) -> str | None:
    """The name a reader would say: ``super().step`` -> ``super.step``, ``envs[0]`` -> ``envs``.

    The same spelling LibCST's ``get_full_name_for_node`` gives, so messages read alike.
    """
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        owner = full_name(node.value)
        return None if owner is None else f"{owner}.{node.attr}"
    if isinstance(node, ast.Call):
        return full_name(node.func)
    if isinstance(node, ast.Subscript):
        return full_name(node.value)
    if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
        return node.name
    return None


def statement_lines(statements: list[ast.stmt], start: int = 0) -> Iterator[list[ast.stmt]]:
    """``statements`` from ``start`` on, grouped by the physical line they share, as LibCST
    groups them: ``a; b`` is one line of two statements, a compound statement is alone.
    Lazy: callers often stop at the first line."""
    line: list[ast.stmt] = []
    for statement in statements[start:]:
        previous = line[-1] if line else None
        if (
            previous is not None
            and not isinstance(previous, COMPOUND_STATEMENTS)
            and not isinstance(statement, COMPOUND_STATEMENTS)
            and statement.lineno == previous.end_lineno
        ):
            line.append(statement)
            continue
        if line:
            yield line
        line = [statement]
    if line:
        yield line


def own_returns(function: ast.AST) -> list[ast.Return]:
    """Return statements of ``function`` itself, not of nested defs, lambdas or classes."""
    # Asked again for every call of the def the receiver analysis classifies: walked once
    # per def (a tree is never changed once parsed), a fresh list each time.
    found = _OWN_RETURNS.get(function)
    if found is None:
        found = _OWN_RETURNS[function] = _own_returns(function)
    return list(found)


_OWN_RETURNS: weakref.WeakKeyDictionary[ast.AST, list[ast.Return]] = weakref.WeakKeyDictionary()


def walk(node: ast.AST) -> Iterable[ast.AST]:
    """``ast.walk(node)``, in the same order. The nodes of a module, class or def are listed
    once and the list is handed out again: dozens of facts and rules walk the same module
    and the same classes and defs (a tree is never changed once parsed), and those repeated
    walks had grown to about a third of a run."""
    if not isinstance(node, _WALK_CACHED):
        return ast.walk(node)
    below = _WALKS.get(node)
    if below is None:
        walked = ast.walk(node)
        next(walked)
        # Kept without ``node`` itself, so the cached value does not keep its weak key alive.
        below = _WALKS[node] = tuple(walked)
    # chained, not copied: a module's list is handed out tens of thousands of times a run
    return chain((node,), below)


_WALK_CACHED = (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)
_WALKS: weakref.WeakKeyDictionary[ast.AST, tuple[ast.AST, ...]] = weakref.WeakKeyDictionary()


def _own_returns(function: ast.AST) -> list[ast.Return]:
    found: list[ast.Return] = []
    stack = list(getattr(function, "body", []))
    while stack:
        node = stack.pop()
        if isinstance(node, ast.Return):
            found.append(node)
        if isinstance(node, (*FUNCTIONS, ast.Lambda, ast.ClassDef)):
            continue
        stack.extend(statements_in(node))
    found.sort(key=lambda r: (r.lineno, r.col_offset))
    return found


def keyword(call: ast.Call, name: str) -> ast.keyword | None:
    for kw in call.keywords:
        if kw.arg == name:
            return kw
    return None


def is_super_call(node: ast.AST | None) -> TypeGuard[ast.Call]:
    """``super()`` or ``super(Cls, self)``: the receiver of a call a class makes of its bases."""
    return isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "super"


def unsubscripted(base: ast.expr) -> ast.expr:
    """The class a base of a class statement names: ``Base`` of ``Base[T]`` (a generic class
    parametrized, which is ``Base`` in the subclass's MRO), the base itself otherwise."""
    return base.value if isinstance(base, ast.Subscript) else base


def self_attribute(node: ast.AST | None) -> str | None:
    """``x`` of ``self.x``; None for anything else."""
    if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "self":
        return node.attr
    return None


def named_class_call(
    call: ast.AST | None, method: str, function: ast.AST | None, classes: Iterable[ast.expr]
) -> ast.expr | None:
    """``Base.method(self, ...)`` in ``function``, a method, naming one of ``classes`` as
    they are spelled (``gym.ObservationWrapper``, ``Simulator``) and handing on the method's
    own first parameter: the unbound spelling of ``super().method(...)``, which reaches the
    class it names with this very instance. That entry of ``classes``, else None."""
    if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute) and call.func.attr == method):
        return None
    receiver = call.func.value
    if not isinstance(receiver, (ast.Name, ast.Attribute)) or not call.args or not isinstance(function, FUNCTIONS):
        return None
    params = function.args.posonlyargs + function.args.args
    first = call.args[0]
    if not (params and isinstance(first, ast.Name) and first.id == params[0].arg):
        return None
    text = ast.dump(receiver)
    return next((named for named in classes if ast.dump(named) == text), None)


def string_value(node: ast.AST | None) -> str | None:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    return None


def own_entry_point(entry: ast.expr | None) -> str | None:
    """``__name__ + ":Class"``: an entry point in the registering module itself, spelled
    ``":Class"`` (no module: the join resolves it to the module that registers it)."""
    if (
        isinstance(entry, ast.BinOp)
        and isinstance(entry.op, ast.Add)
        and isinstance(entry.left, ast.Name)
        and entry.left.id == "__name__"
        and isinstance(entry.right, ast.Constant)
        and isinstance(entry.right.value, str)
        and entry.right.value.startswith(":")
    ):
        return entry.right.value
    return None


class ParameterSlot(NamedTuple):
    """A parameter as its def's calls pass it: ``position`` among a call's positional
    arguments (``self`` not counted); ``classdef`` is the class of a method, None for a
    function."""

    function: ast.FunctionDef | ast.AsyncFunctionDef
    classdef: ast.ClassDef | None
    position: int


def call_argument(call: ast.Call, position: int | None, name: str) -> ast.expr | None:
    """The argument ``call`` passes for parameter ``name`` at ``position`` (None if unclear)."""
    for kw in call.keywords:
        if kw.arg == name:
            return kw.value
    if position is None or position < 0:
        return None
    for index, arg in enumerate(call.args):
        if isinstance(arg, ast.Starred):
            return None
        if index == position:
            return arg
    return None


# Expressions that the grammar takes only in parentheses outside their own statement.
NEEDS_PARENTHESES = (ast.NamedExpr, ast.Yield, ast.YieldFrom)


def parenthesized_if_needed(node: ast.AST, text: str) -> str:
    """``text`` (the source of ``node`` without its parentheses), in parentheses when the
    node is a walrus or a ``yield``: ``d := f()`` alone is no expression."""
    return f"({text})" if isinstance(node, NEEDS_PARENTHESES) else text


def _no_record(qualified: str) -> bool:
    return False
