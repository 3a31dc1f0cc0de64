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
  ``min_level``. ``debug()``/``info()`` are reported, not rewritten: gym printed them to
  stdout only when the level had been lowered, and whether a message should become a
  warning, a log record or nothing is the author's call.
* GM907 ``gym.error`` classes Gymnasium dropped (``Unregistered``, ``UnseedableEnv``,
  ``ResetNotAllowed``, the old API-server errors...) are reported wherever they are
  named; the kept classes are left alone.
* GM908 ``check_env(env, warn=...)``: ``warn`` is ignored (and itself warns) in 1.x, so
  it is dropped. Only Gym's checker: Stable-Baselines3's ``check_env`` keeps ``warn``.

GM903 (``Discrete.sample()`` returns ``np.int64``) and GM905 (``Dict.sample()`` returns
a ``dict``) are informational and have no rule: legacy code keeps working in nearly
every use (indexing, arithmetic, key access), and flagging every ``sample()`` would bury
the review items that matter. The docs list them.

Sources: Gymnasium 1.4.0 ``spaces/box.py``, ``spaces/space.py``, ``logger.py``,
``error.py``, ``utils/env_checker.py``; gym 0.21 ``logger.py`` and ``error.py``.
"""

from __future__ import annotations

import libcst as cst
from libcst.codemod.visitors import AddImportsVisitor
from libcst.helpers import get_full_name_for_node
from libcst.metadata import Assignment, PositionProvider, ScopeProvider

from gymmigrate.analysis import names as N
from gymmigrate.analysis.receivers import METADATA, ReceiverAnalysis
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileProfile, Rule, RulePass

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


class SpacesLoggerPass(RulePass):
    RULES = RULES
    ORDER = 80
    METADATA_DEPENDENCIES = (PositionProvider, *METADATA)

    @classmethod
    def applies_to(cls, source: str, profile: FileProfile) -> bool:
        return profile.imports_gym or profile.imports_gymnasium

    def visit_Module(self, node: cst.Module) -> None:
        self.analysis = ReceiverAnalysis(node, self.metadata)

    def _qualified(self, node: cst.CSTNode) -> set[str]:
        return self.analysis.qualified_names(node)

    # -- GM906: logger ---------------------------------------------------------------

    def _is_logger(self, expr: cst.BaseExpression) -> bool:
        return bool(self._qualified(expr) & LOGGER_MODULES)

    def leave_Expr(self, original_node: cst.Expr, updated_node: cst.Expr) -> cst.BaseSmallStatement:
        """``gym.logger.set_level(x)`` as a statement -> ``gym.logger.min_level = x``."""
        call, new_call = original_node.value, updated_node.value
        if not (isinstance(call, cst.Call) and isinstance(call.func, cst.Attribute) and isinstance(new_call, cst.Call)):
            return updated_node
        if call.func.attr.value not in SET_LEVEL or not self._is_logger(call.func.value):
            return updated_node
        if not self._is_statement(call) or len(new_call.args) != 1:
            return updated_node  # reported by leave_Call
        logger = new_call.func.value  # type: ignore[attr-defined]
        self.report(
            original_node,
            "GM906",
            f"`logger.{call.func.attr.value}(...)` was removed in Gymnasium 1.0 (AttributeError): set `logger.min_level` instead",
        )
        target = cst.AssignTarget(target=cst.Attribute(value=logger, attr=cst.Name("min_level")))
        return cst.Assign(targets=[target], value=new_call.args[0].value)

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.BaseExpression:
        func = original_node.func
        if isinstance(func, cst.Attribute) and self._is_logger(func.value):
            name = func.attr.value
            if name in REMOVED_LOG_FUNCTIONS:
                self.report(
                    original_node,
                    "GM906",
                    f"`logger.{name}()` was removed in Gymnasium 1.0 (AttributeError): use `logging.getLogger(__name__).{name}(...)` "
                    "or delete it",
                    kind=FixKind.FLAG,
                )
            elif name in SET_LEVEL and not self._is_statement(original_node):
                self.report(
                    original_node,
                    "GM906",
                    f"`logger.{name}(...)` was removed in Gymnasium 1.0: assign `logger.min_level` in a statement of its own",
                    kind=FixKind.FLAG,
                )
        rest = _gym_rest(self._qualified(func))
        if rest & CHECK_ENV:
            return self._drop_check_env_warn(original_node, updated_node)
        if rest & BOX_CLASSES:
            return self._box(original_node, updated_node)
        return updated_node

    def _is_statement(self, call: cst.Call) -> bool:
        """``logger.set_level(x)`` on its own line, with one plain argument."""
        parent = self.analysis.parent(call)
        if not isinstance(parent, cst.Expr):
            return False
        return len([a for a in call.args if not a.star]) == 1 and len(call.args) == 1

    def leave_Attribute(self, original_node: cst.Attribute, updated_node: cst.Attribute) -> cst.BaseExpression:
        name = original_node.attr.value
        if name in REMOVED_LEVELS and self._is_logger(original_node.value):
            value = REMOVED_LEVELS[name]
            self.report(original_node, "GM906", f"`logger.{name}` was removed in Gymnasium 1.0: it was the level number {value}")
            return cst.Integer(str(value), lpar=updated_node.lpar, rpar=updated_node.rpar)
        if name == "MIN_LEVEL" and self._is_logger(original_node.value):
            self.report(original_node, "GM906", "gym 0.21's `logger.MIN_LEVEL` is `logger.min_level` in Gymnasium")
            return updated_node.with_changes(attr=cst.Name("min_level"))
        if name in REMOVED_ERRORS and self._qualified(original_node.value) & ERROR_MODULES:
            self.report(original_node, "GM907", _error_message(name))
        return updated_node

    def visit_ImportFrom(self, node: cst.ImportFrom) -> None:
        if node.module is None or node.relative or isinstance(node.names, cst.ImportStar):
            return
        module = get_full_name_for_node(node.module) or ""
        imported = [get_full_name_for_node(alias.name) or "" for alias in node.names]
        if module in ERROR_MODULES:
            for name in imported:
                if name in REMOVED_ERRORS:
                    self.report(node, "GM907", _error_message(name))
        elif module in LOGGER_MODULES:
            removed = [name for name in imported if name in REMOVED_LOGGER_NAMES]
            if removed:
                self.report(
                    node,
                    "GM906",
                    f"`{', '.join(removed)}` no longer exist in gymnasium.logger (ImportError): use `logger.min_level` "
                    "and the level numbers (10 debug, 20 info, 50 disabled)",
                    kind=FixKind.FLAG,
                )

    # -- GM908: check_env(warn=) -------------------------------------------------------

    def _drop_check_env_warn(self, original: cst.Call, updated: cst.Call) -> cst.Call:
        args = list(updated.args)
        positional = [i for i, a in enumerate(args) if a.keyword is None and not a.star]
        index = next((i for i, a in enumerate(args) if a.keyword is not None and a.keyword.value == "warn"), None)
        if index is None and len(positional) > 2:
            # check_env(env, warn, skip_render_check): dropping warn would shift the rest.
            self.report(original, "GM908", "`check_env`'s `warn` argument is ignored now: drop it and pass the rest by keyword", kind=FixKind.FLAG)
            return updated
        if index is None and len(positional) == 2:
            index = positional[1]
        if index is None:
            return updated
        self.report(original, "GM908", "`check_env`'s `warn` argument is ignored (and itself warns) in Gymnasium 1.x: dropped")
        removed = args.pop(index)
        if index == len(args) and args:  # it was the last argument: the new last keeps its comma style
            args[-1] = args[-1].with_changes(comma=removed.comma)
        return updated.with_changes(args=args)

    # -- GM904: Box ----------------------------------------------------------------------

    def _box(self, original: cst.Call, updated: cst.Call) -> cst.Call:
        keywords = {a.keyword.value: a for a in original.args if a.keyword is not None}
        dtype_arg = keywords.get("dtype")
        positional = [a for a in original.args if a.keyword is None and not a.star]
        if dtype_arg is None and len(positional) >= 4:
            dtype_arg = positional[3]
        if dtype_arg is not None and isinstance(dtype_arg.value, cst.Name) and dtype_arg.value.value == "None":
            self.report(original, "GM904", "`Box(dtype=None)` raises in Gymnasium 1.x: give the dtype explicitly (np.float32 was the default)", kind=FixKind.FLAG)
            return updated
        bounds = [i for i, a in enumerate(original.args) if _is_bound(a, i)]
        literal = [i for i in bounds if isinstance(original.args[i].value, (cst.List, cst.Tuple))]
        if not literal:
            return updated
        dtype_text = get_full_name_for_node(dtype_arg.value) if dtype_arg is not None else "np.float32"
        if dtype_arg is not None and dtype_text is None and not isinstance(dtype_arg.value, cst.SimpleString):
            self.report(original, "GM904", "`Box` low/high must be arrays or scalars (a list raises): wrap them in `np.array(...)`", kind=FixKind.FLAG)
            return updated
        is_float = dtype_text in FLOAT_DTYPES or (
            isinstance(dtype_arg.value, cst.SimpleString) and "float" in dtype_arg.value.value  # type: ignore[union-attr]
        )
        if not is_float and any(_mentions_inf(original.args[i].value) for i in literal):
            self.report(
                original,
                "GM904",
                "`Box` low/high must be arrays or scalars (a list raises); this list holds infinities and the dtype is not a "
                "float: use the dtype's limits in an `np.array(...)`",
                kind=FixKind.FLAG,
            )
            return updated
        self.report(original, "GM904", "`Box` low/high lists raise in Gymnasium 1.x: wrapped in `np.array(..., dtype=...)` with the Box dtype")
        AddImportsVisitor.add_needed_import(self.context.codemod, "numpy", asname="np")
        dtype = dtype_arg.value if dtype_arg is not None else cst.parse_expression("np.float32")
        args = list(updated.args)
        for i in literal:
            arg = args[i]
            wrapped = cst.Call(
                func=cst.parse_expression("np.array"),
                args=[
                    cst.Arg(value=arg.value, comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))),
                    cst.Arg(
                        keyword=cst.Name("dtype"),
                        value=dtype,
                        equal=cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace("")),
                    ),
                ],
            )
            args[i] = arg.with_changes(value=wrapped)
        return updated.with_changes(args=args)

    # -- GM902: Space.seed() result ----------------------------------------------------

    def visit_Subscript(self, node: cst.Subscript) -> None:
        if self._is_space_seed(node.value) and not _gm205_covers(node.value):
            self.report(
                node,
                "GM902",
                "`Space.seed()` returns an int (a dict for Dict, a tuple for Tuple spaces) since Gymnasium 1.0, not a list: "
                "drop the index",
            )

    def visit_Assign(self, node: cst.Assign) -> None:
        if self._is_space_seed(node.value) and any(isinstance(t.target, (cst.Tuple, cst.List)) for t in node.targets):
            self.report(
                node,
                "GM902",
                "`Space.seed()` returns an int (a dict for Dict, a tuple for Tuple spaces) since Gymnasium 1.0, not a list: "
                "assign it to one name",
            )

    def _is_space_seed(self, expr: cst.BaseExpression) -> bool:
        if not (isinstance(expr, cst.Call) and isinstance(expr.func, cst.Attribute) and expr.func.attr.value == "seed"):
            return False
        return self._is_space(expr.func.value)

    def _is_space(self, expr: cst.BaseExpression) -> bool:
        if isinstance(expr, cst.Attribute) and expr.attr.value in SPACE_ATTRIBUTES:
            return True
        if isinstance(expr, cst.Call):
            return any(rest.startswith("spaces.") for rest in _gym_rest(self._qualified(expr.func)))
        if isinstance(expr, cst.Name):
            scope = self.get_metadata(ScopeProvider, expr, None)
            if scope is None:
                return False
            assignments = list(scope[expr.value])
            values = [_assigned_value(self.analysis, a) for a in assignments]
            return bool(values) and all(v is not None and not isinstance(v, cst.Name) and self._is_space(v) for v in values)
        return False


def _assigned_value(analysis: ReceiverAnalysis, assignment: object) -> cst.BaseExpression | None:
    if not isinstance(assignment, Assignment):
        return None
    holder = analysis.parent(assignment.node)
    statement = analysis.parent(holder) if isinstance(holder, cst.AssignTarget) else None
    return statement.value if isinstance(statement, cst.Assign) else None


def _gm205_covers(call: cst.Call) -> bool:
    """reset_seed.py (GM205) already reports ``<...>space.seed(s)[i]`` by the receiver's
    spelling; GM902 reports the other spaces (traced to a ``spaces.*`` constructor) and
    unpacked results, so one site never gets two findings."""
    receiver = call.func.value  # type: ignore[attr-defined]
    while isinstance(receiver, cst.Subscript):
        receiver = receiver.value
    name = receiver.attr.value if isinstance(receiver, cst.Attribute) else receiver.value if isinstance(receiver, cst.Name) else ""
    return name.lower().endswith(("space", "spaces"))


def _is_bound(arg: cst.Arg, index: int) -> bool:
    if arg.keyword is not None:
        return arg.keyword.value in ("low", "high")
    return not arg.star and index < 2


def _mentions_inf(expr: cst.BaseExpression) -> bool:
    code = cst.Module(body=[]).code_for_node(expr)
    return "inf" in code


def _error_message(name: str) -> str:
    return f"`gym.error.{name}` does not exist in Gymnasium (AttributeError/ImportError): {REMOVED_ERRORS[name]}"
