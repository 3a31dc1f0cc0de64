"""GM108: gym-or-gymnasium ``try/except ImportError`` fallbacks, ``sys.modules`` hacks and
``gym.__version__`` checks are reported, not rewritten: after the migration one branch
is dead and a person should delete it. An ImportError guard around gym alone is
rewritten and listed for review (GM101)."""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.module import FUNCTIONS, dotted_name, walk
from gymmigrate.facts.version_checks import settled_test
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.gymnasium_api import GYMNASIUM_VERSION
from gymmigrate.rules.imports.common import ImportsBase
from gymmigrate.rules.imports.table import LEGACY_PACKAGES

# Calls that only show a value: printing, logging, notebook display, string building.
_SHOWING_CALLS = frozenset({"print", "display", "str", "repr", "format", "info", "debug", "warning", "warn", "write", "log"})


def _call_name(call: ast.Call) -> str | None:
    """The called name: ``print`` in ``print(x)``, ``info`` in ``log.info(x)``."""
    func = call.func
    if isinstance(func, ast.Name):
        return func.id
    if isinstance(func, ast.Attribute):
        return func.attr
    return None


class ImportGuards(ImportsBase):
    """GM108 (mixed into the family)."""

    def _guards(self) -> dict[ast.Try, str]:
        """How each try statement that imports gym treats a missing package.

        fallback: it tries gym and gymnasium (one branch is dead after the migration);
        detector: an ImportError guard around gym in a file that already uses gymnasium
        (it asks whether *legacy* gym is installed: rewriting it would change the answer);
        guarded: an ImportError guard around gym alone (rewritten, but listed for review).
        """
        packages: dict[ast.Try, set[str]] = {}
        for node in self._imports():
            for ancestor in self.facts.ancestors(node):
                if isinstance(ancestor, (ast.Try, getattr(ast, "TryStar", ast.Try))):
                    packages.setdefault(ancestor, set()).update(_packages(node))  # type: ignore[arg-type]
        guards: dict[ast.Try, str] = {}
        for try_node, imported in packages.items():
            if "gym" not in imported:
                continue
            if "gymnasium" in imported:
                guards[try_node] = "fallback"
                self.report(try_node, "GM108", "gym-or-gymnasium import fallback: keep the gymnasium branch and delete the legacy one")
            elif any(_catches_import_error(handler) for handler in try_node.handlers):
                if self.context.profile.imports_gymnasium:
                    guards[try_node] = "detector"
                    self.report(
                        try_node,
                        "GM108",
                        "this try/except ImportError detects whether legacy gym is installed (the file already uses "
                        "gymnasium): left as it is; delete it if legacy gym support is no longer wanted",
                    )
                else:
                    guards[try_node] = "guarded"
        return guards

    def _record_names(self, node: ast.Import | ast.ImportFrom) -> None:
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] in LEGACY_PACKAGES:
                    self._gym_names.add(alias.asname or alias.name.split(".")[0])

    def _sys_modules_hacks(self) -> None:
        if "sys.modules" not in self.facts.text:
            return
        for node in walk(self.facts.tree):
            if not isinstance(node, ast.Assign):
                continue
            for target in node.targets:
                if isinstance(target, ast.Subscript) and dotted_name(target.value) == "sys.modules":
                    key = target.slice
                    if isinstance(key, ast.Constant) and isinstance(key.value, str):
                        if key.value in ("gym", "gymnasium") or key.value.startswith("gym."):
                            self.report(node, "GM108", "sys.modules hack aliasing gym: remove it once the code uses gymnasium")

    def _version_checks(self) -> None:
        """One finding per check: the reads of ``gym.__version__`` under one ``if`` (its test,
        and a message in its body that prints the version) are one check. A comparison of
        parsed versions against a literal answers the same on every Gymnasium run, so it is
        settled with a note naming the answer; other checks remain an item."""
        if "__version__" not in self.facts.text:
            return
        reads = [
            node
            for node in walk(self.facts.tree)
            if isinstance(node, ast.Attribute)
            and node.attr == "__version__"
            and isinstance(node.value, ast.Name)
            and node.value.id in self._gym_names
        ]
        checks: dict[int, ast.AST] = {}
        for node in sorted(reads, key=lambda n: (n.lineno, n.col_offset)):
            check = self._version_check_of(node)
            if check is None and self._settled_helper(node):
                function = self.facts.enclosing_function(node)
                self.report(
                    node,
                    "GM108",
                    f"`{function.name if function else ''}` compares the gym version with a 0.x release, and every "
                    f"call of it in this file does so with a 0.x literal: on Gymnasium {GYMNASIUM_VERSION} (the version "
                    "imported as gym now) each check takes the same branch on every run, the other one is dead",
                    tier=Tier.NOTE,
                )
                continue
            if check is not None:
                if id(check) in checks:
                    continue  # the same check: its first read speaks for it
                checks[id(check)] = check
                answer = _settled_comparison(check.test) if isinstance(check, (ast.If, ast.IfExp, ast.Assert)) else None
                if answer is None and isinstance(check, (ast.If, ast.IfExp)):
                    # a raw string comparison with a 0.x literal: "1..." sorts after "0..." too
                    value = settled_test(check.test, self.facts)
                    answer = None if value is None else (check.test, value)  # type: ignore[assignment]
                if answer is not None:
                    compare, value = answer
                    self.report(
                        compare,
                        "GM108",
                        f"`{self.facts.segment(compare)}` is {value} on Gymnasium {GYMNASIUM_VERSION} (the version "
                        "imported as gym now): the code takes the same branch on every run, the other one is dead",
                        tier=Tier.NOTE,
                    )
                    continue
            if check is None and self._drop_legacy_demand(node):
                continue
            if check is None and self._only_shown(node):
                continue  # printed or displayed: it shows Gymnasium's version now, nothing branches on it
            self.report(node, "GM108", "gym version check: after the migration one branch is dead; delete the legacy one")

    def _only_shown(self, node: ast.AST) -> bool:
        """The read is an expression statement of its own (a notebook cell displaying it),
        or an argument of one (``print(gym.__version__)``, ``log.info(...)``), with no
        comparison or test between them: nothing chooses a branch by it."""
        statement = self.facts.statement_of(node)
        if not isinstance(statement, ast.Expr):
            return False
        current: ast.AST = node
        while current is not statement:
            parent = self.facts.parent(current)
            if parent is None:
                return False
            current = parent
            if isinstance(current, ast.Call) and _call_name(current) not in _SHOWING_CALLS:
                return False  # a def of the project may check what it is given
            if isinstance(current, (ast.Compare, ast.BoolOp, ast.IfExp, ast.Subscript, ast.Lambda)):
                return False
        return True

    def _drop_legacy_demand(self, node: ast.AST) -> bool:
        """``minor = int(gym.__version__.split('.')[1])`` read only by guards that stop the
        program on a newer gym (``if minor >= 19: exit("install gym 0.19")``): they exist to
        demand the legacy API this run has just replaced, and on Gymnasium they would test its
        own version. The assignment and the guards are deleted (a note)."""
        statement = self.facts.statement_of(node)
        if not (
            isinstance(statement, ast.Assign)
            and len(statement.targets) == 1
            and isinstance(statement.targets[0], ast.Name)
        ):
            return False
        target = statement.targets[0]
        scope = self.facts.scope_of(target)
        if len(scope.bindings.get(target.id, ())) != 1:
            return False
        reads = [r for r in scope.reads.get(target.id, ()) if isinstance(r, ast.Name)]
        guards: list[ast.If] = []
        for read in reads:
            guard = self.facts.parent(self.facts.parent(read))
            if not (isinstance(guard, ast.If) and _exits_on_newer(guard, read)):
                return False
            guards.append(guard)
        if not guards:
            return False
        for guard in guards:
            self.plan.remove(guard)
        self.plan.remove(statement)
        self.report(
            statement,
            "GM108",
            f"`{target.id}` is the gym version, read only to stop the program on a newer gym (line "
            f"{', '.join(str(g.lineno) for g in guards)}): that guard demanded the legacy API this migration replaced, "
            "and would now test Gymnasium's own version; deleted with it",
            FixKind.AUTO,
            tier=Tier.NOTE,
        )
        return True

    def _settled_helper(self, node: ast.AST) -> bool:
        """``node`` reads the version in a helper (``def ge(v): return parse(gym.__version__)
        >= parse(v)``) that this module calls, each time as a check Gymnasium settles."""
        function = self.facts.enclosing_function(node)
        if function is None:
            return False
        calls = self.facts.calls_by_name.get(function.name, ())
        return bool(calls) and all(settled_test(call, self.facts) is not None for call in calls)

    def _version_check_of(self, node: ast.AST) -> ast.AST | None:
        """The ``if`` (or conditional expression, or assert) whose test reads ``gym.__version__``
        and holds ``node``, in its test or its body; None when there is none."""
        for ancestor in self.facts.ancestors(node):
            if isinstance(ancestor, (ast.If, ast.IfExp, ast.Assert)) and _reads_version(ancestor.test, self._gym_names):
                return ancestor
            if isinstance(ancestor, FUNCTIONS + (ast.ClassDef,)):
                return None
        return None


# Callables that parse a version string into something ordered as versions are.
_VERSION_PARSERS = frozenset({"parse", "Version", "LooseVersion", "StrictVersion", "parse_version"})


def _reads_version(test: ast.AST, gym_names: set[str]) -> bool:
    return any(
        isinstance(n, ast.Attribute) and n.attr == "__version__" and isinstance(n.value, ast.Name) and n.value.id in gym_names
        for n in walk(test)
    )


def _parsed(node: ast.AST) -> ast.AST | None:
    """``version.parse(x)``, ``LooseVersion(x)``, ``Version(x)``: the argument ``x``."""
    if not (isinstance(node, ast.Call) and len(node.args) == 1 and not node.keywords):
        return None
    return node.args[0] if _call_name(node) in _VERSION_PARSERS else None


def _release(text: str) -> tuple[int, ...] | None:
    """``"0.24.0"`` -> (0, 24, 0); None for anything but dotted numbers."""
    parts = text.split(".")
    if not parts or not all(part.isdigit() for part in parts):
        return None
    return tuple(int(part) for part in parts)


def _settled_comparison(test: ast.AST) -> tuple[ast.Compare, bool] | None:
    """The comparison in ``test`` of the parsed gym version with a parsed legacy (0.x)
    literal (``version.parse(gym.__version__) >= version.parse("0.24.0")``, under ``not``
    or in an ``and``/``or`` too) and its value, the same on every Gymnasium 1.x release."""
    for node in walk(test):
        if not (isinstance(node, ast.Compare) and len(node.ops) == 1):
            continue
        left, right = _parsed(node.left), _parsed(node.comparators[0])
        if left is None or right is None:
            continue
        op = node.ops[0]
        if isinstance(right, ast.Attribute) and right.attr == "__version__":
            left, right = right, left
            op = _MIRRORED.get(type(op), op)
        if not (isinstance(left, ast.Attribute) and left.attr == "__version__"):
            continue
        if not (isinstance(right, ast.Constant) and isinstance(right.value, str)):
            continue
        target, other = _release(GYMNASIUM_VERSION), _release(right.value.strip())  # a parse strips blanks
        if target is None or other is None or type(op) not in _COMPARE or other >= (1,):
            continue  # a 1.x literal may answer differently on another Gymnasium release
        width = max(len(target), len(other))
        padded = (target + (0,) * width)[:width], (other + (0,) * width)[:width]
        return node, _COMPARE[type(op)](*padded)
    return None


_COMPARE = {
    ast.Lt: lambda a, b: a < b,
    ast.LtE: lambda a, b: a <= b,
    ast.Gt: lambda a, b: a > b,
    ast.GtE: lambda a, b: a >= b,
    ast.Eq: lambda a, b: a == b,
    ast.NotEq: lambda a, b: a != b,
}
_MIRRORED: dict[type, ast.cmpop] = {ast.Lt: ast.Gt(), ast.LtE: ast.GtE(), ast.Gt: ast.Lt(), ast.GtE: ast.LtE()}


def _packages(node: ast.Import | ast.ImportFrom) -> set[str]:
    if isinstance(node, ast.Import):
        return {alias.name.split(".")[0] for alias in node.names}
    if node.module is not None and not node.level:
        return {node.module.split(".")[0]}
    return set()


def innermost_guard(node: ast.AST, guards: dict[ast.Try, str], facts: ModuleFacts) -> str | None:
    """The guard kind of the nearest enclosing try that is a fallback, detector or guard.

    A fallback or detector anywhere above wins, as the old traversal's depth counters did.
    """
    kinds = [guards[a] for a in facts.ancestors(node) if a in guards]
    if "fallback" in kinds or "detector" in kinds:
        return "fallback"
    return "guarded" if kinds else None


def _catches_import_error(handler: ast.ExceptHandler) -> bool:
    if handler.type is None:
        return True  # a bare except catches it too
    caught = handler.type.elts if isinstance(handler.type, ast.Tuple) else [handler.type]
    names = {dotted_name(item) for item in caught}
    return bool(names & {"ImportError", "ModuleNotFoundError", "Exception", "BaseException"})


_EXITS = frozenset({"exit", "quit", "sys.exit", "os._exit"})


def _exits_on_newer(guard: ast.If, read: ast.Name) -> bool:
    """``if read >= 19: exit(...)`` (or ``>``, or ``19 <= read``), with no else: the body
    only prints and stops the program."""
    test = guard.test
    if guard.orelse or not (isinstance(test, ast.Compare) and len(test.ops) == 1):
        return False
    left, op, right = test.left, test.ops[0], test.comparators[0]
    newer = (left is read and isinstance(op, (ast.GtE, ast.Gt)) and isinstance(right, ast.Constant)) or (
        right is read and isinstance(op, (ast.LtE, ast.Lt)) and isinstance(left, ast.Constant)
    )
    if not newer:
        return False
    *before, last = guard.body
    stops = isinstance(last, ast.Raise) or (
        isinstance(last, ast.Expr) and isinstance(last.value, ast.Call) and dotted_name(last.value.func) in _EXITS
    )
    prints = all(
        isinstance(s, ast.Expr) and isinstance(s.value, ast.Call) and dotted_name(s.value.func) == "print" for s in before
    )
    return stops and prints
