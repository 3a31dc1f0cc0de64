"""Spaces, logger, errors and utils (GM902, GM904, GM906-GM908).

* GM902 ``Space.seed()`` returns an int (a dict for ``Dict``, a tuple for ``Tuple``)
  since Gymnasium 1.0, not ``[seed]``: ``space.seed(s)[0]`` and unpacking the result
  are reported; the right fix depends on the space type, which is not known here.
* GM904 ``Box`` low/high must be scalars or arrays (a list raises ``ValueError`` in
  1.4, checked): list and tuple literals are wrapped in ``np.array(..., dtype=<the
  Box dtype, float32 by default>)``, which is exactly what ``Box`` would have built.
  ``dtype=None`` raises and is reported.
* GM906 Gymnasium 1.0 removed ``logger.set_level``/``setLevel``/``DEBUG``/``INFO``/
  ``DISABLED``/``debug``/``info`` (only ``WARN``, ``ERROR``, ``min_level``, ``warn``,
  ``error``, ``deprecation`` are left): ``set_level(x)`` becomes ``min_level = x``, the
  level constants become their values (10, 20, 50), gym 0.21's ``MIN_LEVEL`` becomes
  ``min_level``. ``debug()``/``info()`` become the standard library's
  ``logging.getLogger(__name__).debug()/info()`` (catalog: "use warnings/logging"): gym
  printed them only when its level had been lowered, and an unconfigured standard logger
  drops them too. In a file that lowers gym's level (it wanted them printed) or with
  keyword arguments they are reported instead.
* GM907 ``gym.error`` classes Gymnasium dropped (``Unregistered``, ``UnseedableEnv``,
  ``ResetNotAllowed``, the old API-server errors...) are reported wherever they are
  named; the kept classes are left alone.
* GM908 ``check_env(env, warn=...)``: ``warn`` is ignored (and itself warns) in 1.x, so
  it is dropped. Only Gym's checker: Stable-Baselines3's ``check_env`` keeps ``warn``.

GM903 (NumPy ints from ``Discrete``) and GM905 (``Dict.sample()`` is a ``dict``) live in
``rules/spaces/drift.py`` with the other space drift (GM909, GM910).

Sources: Gymnasium 1.4.0 ``spaces/box.py``, ``spaces/space.py``, ``logger.py``,
``error.py``, ``utils/env_checker.py``; gym 0.21 ``logger.py`` and ``error.py``.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.module import full_name
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.repeats import Repeats

RULES = (
    Rule("GM902", "Space.seed() return value", FixKind.FLAG, "`space.seed(s)[0]` and unpacking its result are reported."),
    Rule(
        "GM904",
        "Box bounds and dtype",
        FixKind.AUTO,
        "List literals given to `Box` low/high become `np.array(..., dtype=...)`; `dtype=None` is reported.",
    ),
    Rule("GM906", "logger API", FixKind.AUTO, "`gym.logger.set_level(x)` becomes `gym.logger.min_level = x`; removed levels become numbers."),
    Rule("GM907", "removed gym.error classes", FixKind.FLAG, "Exception classes Gymnasium removed from `gym.error` are reported."),
    Rule("GM908", "check_env(warn=)", FixKind.AUTO, "The ignored `warn` argument of Gym's `check_env` is dropped."),
)

# -- GM906 ----------------------------------------------------------------------------
LOGGER_MODULES = frozenset({"gymnasium.logger", "gym.logger"})
REMOVED_LEVELS = {"DEBUG": 10, "INFO": 20, "DISABLED": 50}  # gym 0.21-0.29 values
KEPT_LEVELS = frozenset({"WARN", "ERROR"})
SET_LEVEL = frozenset({"set_level", "setLevel"})
REMOVED_LOG_FUNCTIONS = frozenset({"debug", "info"})
REMOVED_LOGGER_NAMES = SET_LEVEL | REMOVED_LOG_FUNCTIONS | set(REMOVED_LEVELS)

# -- GM907 ----------------------------------------------------------------------------
ERROR_MODULES = frozenset({"gymnasium.error", "gym.error"})
# Still in gymnasium.error (checked against the installed 1.4 by the tests).
KEPT_ERRORS = frozenset(
    {
        "Error", "UnregisteredEnv", "DeprecatedEnv", "DependencyNotInstalled", "UnsupportedMode",
        "ResetNeeded", "InvalidAction", "AlreadyPendingCallError", "NoAsyncCallError",
        "ClosedEnvironmentError", "CustomSpaceError", "NamespaceNotFound", "NameNotFound",
        "VersionNotFound", "RegistrationError", "InvalidMetadata", "MissingArgument",
        "InvalidProbability", "InvalidBound", "DeprecatedWrapper",
    }
)  # fmt: skip
# gym 0.21-0.26 classes that are gone, with what to catch or raise instead.
REMOVED_ERRORS = {
    "Unregistered": "catch `UnregisteredEnv` (or `NameNotFound` / `VersionNotFound`)",
    "UnregisteredBenchmark": "benchmarks are gone; drop the handler",
    "UnseedableEnv": "seeding goes through `reset(seed=...)`; drop the handler",
    "ResetNotAllowed": "raise `ResetNeeded` or a plain `Error`",
    "APIError": "the gym API-server errors are gone; drop the handler",
    "APIConnectionError": "the gym API-server errors are gone; drop the handler",
    "InvalidRequestError": "the gym API-server errors are gone; drop the handler",
    "AuthenticationError": "the gym API-server errors are gone; drop the handler",
    "RateLimitError": "the gym API-server errors are gone; drop the handler",
    "VideoRecorderError": "video recording errors are plain exceptions now; catch `Error`",
    "InvalidFrame": "video recording errors are plain exceptions now; catch `Error`",
    "DoubleWrapperError": "the check is gone; drop the handler",
    "WrapAfterConfigureError": "the check is gone; drop the handler",
    "RetriesExceededError": "the gym API-server errors are gone; drop the handler",
}

# -- GM908 ----------------------------------------------------------------------------
CHECK_ENV = frozenset({"utils.env_checker.check_env"})

# -- GM902 / GM904 ----------------------------------------------------------------------
SPACE_ATTRIBUTES = frozenset({"action_space", "observation_space", "single_action_space", "single_observation_space"})
BOX_CLASSES = frozenset({"spaces.Box", "spaces.box.Box"})
FLOAT_DTYPES = frozenset({"float", "float16", "float32", "float64", "np.float16", "np.float32", "np.float64", "numpy.float32", "numpy.float64", "numpy.float16"})  # fmt: skip


def _gym_rest(qualified: set[str]) -> set[str]:
    return {rest for q in qualified if (rest := N.strip_gym_prefix(q)) is not None}


# A single string literal, not an implicit concatenation (``"float" "32"``).
_ONE_STRING = re.compile(r"""^[rRuU]?(\"\"\"[\s\S]*\"\"\"|'''[\s\S]*'''|"(?:[^"\\\n]|\\.)*"|'(?:[^'\\\n]|\\.)*')$""")


class SpacesLogger(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        profile = context.profile
        if not (profile.imports_gym or profile.imports_gymnasium):
            return False
        return any(word in facts.text for word in ("logger", "error", "check_env", "Box", "seed"))

    def decide(self) -> None:
        self._decide_logger()
        self._decide_errors()
        self._decide_imports()
        for call in self._calls_of(CHECK_ENV, "check_env"):
            self._decide_check_env(call)
        for call in self._calls_of(BOX_CLASSES, "Box"):
            self._decide_box(call)
        for call in self.facts.attribute_calls.get("seed", ()):
            self._decide_space_seed(call)

    def _is_logger(self, expr: ast.AST) -> bool:
        return bool(self.facts.qualified_names(expr) & LOGGER_MODULES)

    def _calls_of(self, qualified: frozenset[str], name: str) -> list[ast.Call]:
        """Calls of a gym callable (``qualified`` without the package), however it is imported."""
        bound = {name}
        for alias, full in self.facts.imports.items():
            rest = N.strip_gym_prefix(full)
            if rest in qualified and alias.asname:
                bound.add(alias.asname)
        candidates = [call for local in sorted(bound) for call in self.facts.calls_by_name.get(local, ())]
        candidates += self.facts.attribute_calls.get(name, ())
        return [call for call in candidates if _gym_rest(self.facts.qualified_names(call.func)) & qualified]

    # -- GM906: logger ---------------------------------------------------------------

    def _decide_logger(self) -> None:
        for method in sorted(SET_LEVEL | REMOVED_LOG_FUNCTIONS):
            for call in self.facts.attribute_calls.get(method, ()):
                func = call.func
                assert isinstance(func, ast.Attribute)
                if not self._is_logger(func.value):
                    continue
                if method in REMOVED_LOG_FUNCTIONS:
                    self._removed_log_call(call, method)
                elif self._is_statement(call):
                    self._set_level_statement(call, method)
                else:
                    self.report(
                        call,
                        "GM906",
                        f"`logger.{method}(...)` was removed in Gymnasium 1.0: assign `logger.min_level` in a statement of its own",
                        kind=FixKind.FLAG,
                    )
        for name, value in REMOVED_LEVELS.items():
            for attribute in self.facts.attributes.get(name, ()):
                if self._is_logger(attribute.value):
                    self.report(attribute, "GM906", f"`logger.{name}` was removed in Gymnasium 1.0: it was the level number {value}")
                    self.plan.replace(
                        attribute, lambda node, value=value: cst.Integer(str(value), lpar=node.lpar, rpar=node.rpar)
                    )
        for attribute in self.facts.attributes.get("MIN_LEVEL", ()):
            if self._is_logger(attribute.value):
                self.report(attribute, "GM906", "gym 0.21's `logger.MIN_LEVEL` is `logger.min_level` in Gymnasium")
                self.plan.replace(attribute, lambda node: node.with_changes(attr=cst.Name("min_level")))

    def _removed_log_call(self, call: ast.Call, method: str) -> None:
        """``logger.info(msg, *args)`` -> ``logging.getLogger(__name__).info(msg, *args)``.

        gym formatted ``msg % args`` and printed it only when the level had been lowered
        to INFO/DEBUG; the standard library does the same by default (a logger without
        handlers drops records below WARNING). A file that lowers gym's level wanted these
        printed, and a call with keywords is not gym's signature: both are reported."""
        if self._lowers_level() or call.keywords:
            self.report(
                call,
                "GM906",
                f"`logger.{method}()` was removed in Gymnasium 1.0 (AttributeError): use `logging.getLogger(__name__).{method}(...)` "
                "(and configure logging if these messages must still print) or delete it",
                kind=FixKind.FLAG,
            )
            return
        logging = self.plan.ensure_import("logging")
        self.report(call, "GM906", f"`logger.{method}()` was removed in Gymnasium 1.0: the standard library's logger.{method}() replaces it")
        replacement = f"{logging}.getLogger(__name__).{method}"
        self.plan.replace(call, lambda node: node.with_changes(func=cst.parse_expression(replacement)))

    def _lowers_level(self) -> bool:
        """The file sets gym's log level (or names DEBUG/INFO): it wanted debug/info printed."""
        def compute() -> bool:
            return any(
                self._is_logger(call.func.value)  # type: ignore[attr-defined]
                for method in SET_LEVEL
                for call in self.facts.attribute_calls.get(method, ())
            ) or any(
                self._is_logger(attribute.value)
                for name in ("min_level", "MIN_LEVEL", "DEBUG", "INFO")
                for attribute in self.facts.attributes.get(name, ())
            )

        return self.facts.memo(("gym-logger-level-set", 0), compute)

    def _is_statement(self, call: ast.Call) -> bool:
        """``logger.set_level(x)`` on its own line, with one plain argument."""
        if not isinstance(self.facts.parent(call), ast.Expr):
            return False
        if call.keywords:
            return not call.args and len(call.keywords) == 1 and call.keywords[0].arg is not None
        return len(call.args) == 1 and not isinstance(call.args[0], ast.Starred)

    def _set_level_statement(self, call: ast.Call, method: str) -> None:
        """``gym.logger.set_level(x)`` as a statement -> ``gym.logger.min_level = x``."""
        statement = self.facts.parent(call)
        assert isinstance(statement, ast.Expr)
        self.report(
            statement,
            "GM906",
            f"`logger.{method}(...)` was removed in Gymnasium 1.0 (AttributeError): set `logger.min_level` instead",
        )

        def build(node: cst.Expr) -> cst.Assign:
            new_call = node.value
            logger = new_call.func.value  # type: ignore[attr-defined]
            target = cst.AssignTarget(target=cst.Attribute(value=logger, attr=cst.Name("min_level")))
            return cst.Assign(targets=[target], value=new_call.args[0].value)  # type: ignore[attr-defined]

        self.plan.replace(statement, build)

    def _decide_imports(self) -> None:
        """``from gym.error import Unregistered`` / ``from gym.logger import set_level``."""
        statements = {self.facts.parent(alias) for alias in self.facts.imports}
        for statement in sorted((s for s in statements if isinstance(s, ast.ImportFrom)), key=lambda s: (s.lineno, s.col_offset)):
            if statement.module is None or statement.level:
                continue
            imported = [alias.name for alias in statement.names]
            if statement.module in ERROR_MODULES:
                for name in imported:
                    if name in REMOVED_ERRORS:
                        self.report(statement, "GM907", _error_message(name))
            elif statement.module in LOGGER_MODULES:
                removed = [name for name in imported if name in REMOVED_LOGGER_NAMES]
                if removed:
                    self.report(
                        statement,
                        "GM906",
                        f"`{', '.join(removed)}` no longer exist in gymnasium.logger (ImportError): use `logger.min_level` "
                        "and the level numbers (10 debug, 20 info, 50 disabled)",
                        kind=FixKind.FLAG,
                    )

    # -- GM907: gym.error ------------------------------------------------------------------

    def _decide_errors(self) -> None:
        repeats = Repeats("GM907")  # one review item per removed class and file
        for name in REMOVED_ERRORS:
            for attribute in sorted(self.facts.attributes.get(name, ()), key=lambda a: (a.lineno, a.col_offset)):
                if self.facts.qualified_names(attribute.value) & ERROR_MODULES:
                    self.report(attribute, "GM907", _error_message(name), question=repeats.question(name))

    # -- GM908: check_env(warn=) -------------------------------------------------------

    def _decide_check_env(self, call: ast.Call) -> None:
        positional = [a for a in call.args if not isinstance(a, ast.Starred)]
        has_warn = any(kw.arg == "warn" for kw in call.keywords)
        if not has_warn and len(positional) > 2:
            # check_env(env, warn, skip_render_check): dropping warn would shift the rest.
            self.report(call, "GM908", "`check_env`'s `warn` argument is ignored now: drop it and pass the rest by keyword", kind=FixKind.FLAG)
            return
        if not has_warn and len(positional) != 2:
            return
        self.report(call, "GM908", "`check_env`'s `warn` argument is ignored (and itself warns) in Gymnasium 1.x: dropped")
        self.plan.replace(call, _drop_warn)

    # -- GM904: Box ----------------------------------------------------------------------

    def _decide_box(self, call: ast.Call) -> None:
        builds = [build for build in (self._decide_box_shape(call), self._decide_box_bounds(call)) if build is not None]
        if builds:
            self.plan.replace(call, _applying(builds))

    def _decide_box_shape(self, call: ast.Call) -> Callable[[cst.Call], cst.Call] | None:
        """gym's Box took ``shape=1``; Gymnasium's iterates the shape (TypeError on an int).
        Rewritten where the value is an int for certain (a literal, ``len(...)``, a name bound
        only to such); reported where the source parenthesises a value that is not a tuple
        (``shape=(n)``: meant as a tuple, an int if ``n`` is one)."""
        keyword = next((kw for kw in call.keywords if kw.arg == "shape"), None)
        positional = [a for a in call.args if not isinstance(a, ast.Starred)]
        if keyword is not None:
            shape: ast.expr | None = keyword.value
        elif len(positional) >= 3 and len(positional) == len(call.args):
            shape = positional[2]
        else:
            return None
        if shape is None or isinstance(shape, (ast.Tuple, ast.List)) or self._never_int(shape):
            return None
        if self._is_int(shape, 3):
            self.report(call, "GM904", "`Box(shape=<int>)` raises TypeError in Gymnasium (it iterates the shape): written as a one-element tuple")
            return _tuple_shape
        if keyword is not None and self.facts.segment(keyword).split("=", 1)[-1].lstrip().startswith("("):
            self.report(
                call,
                "GM904",
                "`Box` shape is parenthesised but not a tuple: Gymnasium raises TypeError on an int shape; if it is an int, "
                "write `(n,)`",
                kind=FixKind.FLAG,
            )
        return None

    def _never_int(self, node: ast.expr) -> bool:
        """A value that cannot be an int whatever its names hold: a tuple literal joined or
        repeated (``shp[:-1] + (k,)``: int + tuple raises TypeError, so it never reaches the
        Box as an int), or the builtin ``tuple(...)``."""
        if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Mult)):
            return any(isinstance(side, ast.Tuple) or self._never_int(side) for side in (node.left, node.right))
        return (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id == "tuple"
            and not self.facts.bindings_of(node.func)
        )

    def _is_int(self, node: ast.expr, depth: int) -> bool:
        """A Python int for certain: an int literal, ``len(...)``/``int(...)`` (the builtins, not
        shadowed), or a name every binding of which assigns one."""
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            node = node.operand
        if isinstance(node, ast.Constant):
            return isinstance(node.value, int) and not isinstance(node.value, bool)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("len", "int"):
            return not self.facts.bindings_of(node.func) and len(node.args) == 1 and not node.keywords
        if isinstance(node, ast.Name) and depth > 0:
            bindings = self.facts.bindings_of(node)
            values = [self._assigned_value(binding) for binding in bindings]
            return bool(values) and all(value is not None and self._is_int(value, depth - 1) for value in values)
        return False

    def _decide_box_bounds(self, call: ast.Call) -> Callable[[cst.Call], cst.Call] | None:
        positional = [a for a in call.args if not isinstance(a, ast.Starred)]
        dtype = next((kw.value for kw in call.keywords if kw.arg == "dtype"), None)
        if dtype is None and len(positional) >= 4:
            dtype = positional[3]
        if isinstance(dtype, ast.Constant) and dtype.value is None:
            self.report(call, "GM904", "`Box(dtype=None)` raises in Gymnasium 1.x: give the dtype explicitly (np.float32 was the default)", kind=FixKind.FLAG)
            return None
        literal = [value for value in _bounds(call) if isinstance(value, (ast.List, ast.Tuple))]
        if not literal:
            return None
        dtype_text = full_name(dtype) if dtype is not None else "np.float32"
        dtype_string = self._one_string(dtype)
        if dtype is not None and dtype_text is None and dtype_string is None:
            self.report(call, "GM904", "`Box` low/high must be arrays or scalars (a list raises): wrap them in `np.array(...)`", kind=FixKind.FLAG)
            return None
        is_float = dtype_text in FLOAT_DTYPES or (dtype_string is not None and "float" in dtype_string)
        if not is_float and any("inf" in self.facts.segment(value) for value in literal):
            self.report(
                call,
                "GM904",
                "`Box` low/high must be arrays or scalars (a list raises); this list holds infinities and the dtype is not a "
                "float: use the dtype's limits in an `np.array(...)`",
                kind=FixKind.FLAG,
            )
            return None
        self.report(call, "GM904", "`Box` low/high lists raise in Gymnasium 1.x: wrapped in `np.array(..., dtype=...)` with the Box dtype")
        if not self._numpy_imported_as_np():
            self.plan.add_import("import numpy as np")
        return _wrap_bounds

    def _one_string(self, node: ast.AST | None) -> str | None:
        """The source of a single string literal (quotes included), else None."""
        if not (isinstance(node, ast.Constant) and isinstance(node.value, str)):
            return None
        source = self.facts.segment(node)
        return source if _ONE_STRING.match(source) else None

    def _numpy_imported_as_np(self) -> bool:
        return any(
            full == "numpy" and alias.asname == "np" and self.facts.scope_of(alias) is self.facts.module_scope
            for alias, full in self.facts.imports.items()
        )

    # -- GM902: Space.seed() result ----------------------------------------------------

    def _decide_space_seed(self, call: ast.Call) -> None:
        parent = self.facts.parent(call)
        if isinstance(parent, ast.Subscript) and parent.value is call:
            if self._is_space(call.func.value) and not _gm205_covers(call):  # type: ignore[attr-defined]
                self.report(
                    parent,
                    "GM902",
                    "`Space.seed()` returns an int (a dict for Dict, a tuple for Tuple spaces) since Gymnasium 1.0, not a list: "
                    "drop the index",
                )
        elif isinstance(parent, ast.Assign) and parent.value is call and any(isinstance(t, (ast.Tuple, ast.List)) for t in parent.targets):
            if self._is_space(call.func.value):  # type: ignore[attr-defined]
                self.report(
                    parent,
                    "GM902",
                    "`Space.seed()` returns an int (a dict for Dict, a tuple for Tuple spaces) since Gymnasium 1.0, not a list: "
                    "assign it to one name",
                )

    def _is_space(self, expr: ast.AST) -> bool:
        if isinstance(expr, ast.Attribute) and expr.attr in SPACE_ATTRIBUTES:
            return True
        if isinstance(expr, ast.Call):
            return any(rest.startswith("spaces.") for rest in _gym_rest(self.facts.qualified_names(expr.func)))
        if isinstance(expr, ast.Name):
            # Every binding is ``name = <a space>`` (one level: no chains of names).
            values = [self._assigned_value(binding) for binding in self.facts.bindings_of(expr)]
            return bool(values) and all(v is not None and not isinstance(v, ast.Name) and self._is_space(v) for v in values)
        return False

    def _assigned_value(self, binding: ast.AST) -> ast.expr | None:
        statement = self.facts.parent(binding)
        if isinstance(binding, ast.Name) and isinstance(statement, ast.Assign) and binding in statement.targets:
            return statement.value
        return None


def _gm205_covers(call: ast.Call) -> bool:
    """reset_seed.py (GM205) already reports ``<...>space.seed(s)[i]`` by the receiver's
    spelling; GM902 reports the other spaces (traced to a ``spaces.*`` constructor) and
    unpacked results, so one site never gets two findings."""
    receiver = call.func.value  # type: ignore[attr-defined]
    while isinstance(receiver, ast.Subscript):
        receiver = receiver.value
    name = receiver.attr if isinstance(receiver, ast.Attribute) else receiver.id if isinstance(receiver, ast.Name) else ""
    return name.lower().endswith(("space", "spaces"))


def _bounds(call: ast.Call) -> list[ast.expr]:
    """The values given for ``low`` / ``high``: the first two arguments, or by keyword."""
    arguments: list[ast.expr | ast.keyword] = sorted([*call.args, *call.keywords], key=lambda a: (a.lineno, a.col_offset))
    found: list[ast.expr] = []
    for index, argument in enumerate(arguments):
        if isinstance(argument, ast.keyword):
            if argument.arg in ("low", "high"):
                found.append(argument.value)
        elif not isinstance(argument, ast.Starred) and index < 2:
            found.append(argument)
    return found


def _error_message(name: str) -> str:
    return f"`gym.error.{name}` does not exist in Gymnasium (AttributeError/ImportError): {REMOVED_ERRORS[name]}"


# -- building the new code ------------------------------------------------------------------


def _drop_warn(call: cst.Call) -> cst.Call:
    """``check_env(env, warn=...)`` / ``check_env(env, False)`` without the ``warn`` argument."""
    args = list(call.args)
    index = next((i for i, a in enumerate(args) if a.keyword is not None and a.keyword.value == "warn"), None)
    if index is None:
        positional = [i for i, a in enumerate(args) if a.keyword is None and not a.star]
        index = positional[1]
    removed = args.pop(index)
    if index == len(args) and args:  # it was the last argument: the new last keeps its comma style
        args[-1] = args[-1].with_changes(comma=removed.comma)
    return call.with_changes(args=args)


def _is_bound(arg: cst.Arg, index: int) -> bool:
    if arg.keyword is not None:
        return arg.keyword.value in ("low", "high")
    return not arg.star and index < 2


def _applying(builds: list[Callable[[cst.Call], cst.Call]]) -> Callable[[cst.Call], cst.Call]:
    """One replacement of the Box call that makes each of its changes in turn."""

    def build(call: cst.Call) -> cst.Call:
        for each in builds:
            call = each(call)
        return call

    return build


def _tuple_shape(call: cst.Call) -> cst.Call:
    """``shape=1`` -> ``shape=(1,)`` (keyword, or the third positional argument)."""
    args = list(call.args)
    positional = [i for i, a in enumerate(args) if a.keyword is None and not a.star]
    index = next((i for i, a in enumerate(args) if a.keyword is not None and a.keyword.value == "shape"), None)
    if index is None:
        index = positional[2]
    value = args[index].value.with_changes(lpar=[], rpar=[])
    args[index] = args[index].with_changes(value=cst.Tuple([cst.Element(value, comma=cst.Comma())]))
    return call.with_changes(args=args)


def _wrap_bounds(call: cst.Call) -> cst.Call:
    """List and tuple bounds -> ``np.array(<bound>, dtype=<the Box dtype>)``: what Box built from them."""
    dtype_arg = next((a for a in call.args if a.keyword is not None and a.keyword.value == "dtype"), None)
    positional = [a for a in call.args if a.keyword is None and not a.star]
    if dtype_arg is None and len(positional) >= 4:
        dtype_arg = positional[3]
    dtype = dtype_arg.value if dtype_arg is not None else cst.parse_expression("np.float32")
    no_space = cst.SimpleWhitespace("")
    args = list(call.args)
    for i, arg in enumerate(args):
        if not (_is_bound(arg, i) and isinstance(arg.value, (cst.List, cst.Tuple))):
            continue
        wrapped = cst.Call(
            func=cst.parse_expression("np.array"),
            args=[
                cst.Arg(value=arg.value, comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))),
                cst.Arg(keyword=cst.Name("dtype"), value=dtype, equal=cst.AssignEqual(whitespace_before=no_space, whitespace_after=no_space)),
            ],
        )
        args[i] = arg.with_changes(value=wrapped)
    return call.with_changes(args=args)
