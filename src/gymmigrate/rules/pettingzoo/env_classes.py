"""PZ108 (with PZ103-PZ106 inside env classes): custom ``AECEnv`` and ``ParallelEnv`` subclasses.

PettingZoo 1.21 renamed the helpers ``_was_done_step`` -> ``_was_dead_step`` and
``_dones_step_first`` -> ``_deads_step_first``, and replaced ``self.dones`` by two dicts
that ``last()``, ``_was_dead_step`` and the API tests all read: ``self.terminations``
(the game is over for the agent) and ``self.truncations`` (a step limit cut it short).
Which one a store means needs judgement, so stores are rewritten for review: a store
whose value mentions a step or cycle count becomes a truncation, any other a
termination, and the other dict is kept all False. Reads read both.

A parallel env's ``step`` returns five dicts (its local ``dones`` becomes
``terminations``, with ``truncations`` all False beside it), and its ``reset`` returns
``(observations, infos)`` without ``return_info`` (1.23). Every ``reset`` takes
``seed=None, options=None``; a class that seeds itself in ``seed()`` calls it from there.
"""

from __future__ import annotations

import ast
import re

from gymmigrate.edits.lazy import cst

from gymmigrate.facts.module import FUNCTIONS, own_returns
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.findings import FixKind
from gymmigrate.facts.flow import Flow
from gymmigrate.rules.pettingzoo.common import AGENT, PZ108, PettingZooFamily, either, values_call

RENAMED_HELPERS = {"_was_done_step": "_was_dead_step", "_dones_step_first": "_deads_step_first"}
# A store of ``dones`` whose value counts steps ends episodes by a limit: a truncation.
_STEP_LIMIT = re.compile(r"cycle|iter|step|moves|horizon|time_?limit", re.IGNORECASE)


class EnvClasses(PettingZooFamily):
    RULES = (PZ108,)

    def decide(self) -> None:
        facts = self.facts
        for old, new in RENAMED_HELPERS.items():
            for attr in facts.attributes.get(old, ()):
                self.rename_attribute(attr, new)
                self.report(attr, "PZ108", f"`{old}` is `{new}` since PettingZoo 1.21")
        for statement in facts.import_statements:
            if isinstance(statement, ast.ImportFrom) and statement.module == "pettingzoo.utils" and statement.level == 0:
                self._plan_agent_selector(statement)
        self.classes = {id(c): kind for c in facts.all_classes if (kind := self.multi_agent.class_kind(c)) is not None}
        if not self.classes:
            return
        for attr in facts.attributes.get("dones", ()):
            classdef = facts.enclosing_class(attr)
            if classdef is not None and id(classdef) in self.classes and isinstance(attr.value, ast.Name) and self.receivers.is_self(attr.value):
                self._plan_self_dones(attr)
        for classdef in facts.all_classes:
            kind = self.classes.get(id(classdef))
            if kind is None:
                continue
            methods = {m.name: m for m in classdef.body if isinstance(m, FUNCTIONS)}
            if "reset" in methods:
                self._plan_reset(methods["reset"], kind, "seed" in methods)
            if kind is EnvKind.PZ_PARALLEL and "step" in methods:
                self._plan_parallel_step(methods["step"])
            if "render" in methods:
                self._plan_render(classdef, methods)
            if "__init__" in methods:
                self._plan_space_methods(classdef, methods)
            if "last" in methods:
                self.report(methods["last"], "PZ108", "`last()` returns `observation, reward, termination, truncation, "
                            "info` since PettingZoo 1.21: check this override", FixKind.FLAG)

    def _plan_agent_selector(self, statement: ast.ImportFrom) -> None:
        """``from pettingzoo.utils import agent_selector`` is the module since 1.24 (the class is
        ``AgentSelector``): calling it raises ``TypeError: 'module' object is not callable``."""
        if not any(alias.name == "agent_selector" and alias.asname is None for alias in statement.names):
            return
        self.changed()

        def build(node: cst.ImportFrom) -> cst.ImportFrom:
            names = [
                alias.with_changes(name=cst.Name("AgentSelector"), asname=cst.AsName(name=cst.Name("agent_selector")))
                if isinstance(alias.name, cst.Name) and alias.name.value == "agent_selector" and alias.asname is None
                else alias
                for alias in node.names  # type: ignore[union-attr]
            ]
            return node.with_changes(names=names)

        self.plan.replace(statement, build)
        self.report(statement, "PZ108", "`pettingzoo.utils.agent_selector` is a module in current PettingZoo: "
                    "the class is `AgentSelector`")

    # -- self.dones -----------------------------------------------------------------------

    def _plan_self_dones(self, attr: ast.Attribute) -> None:
        parent = self.facts.parent(attr)
        if isinstance(parent, ast.Assign) and parent.targets == [attr]:
            self._split_store(attr, parent, self.facts.segment(parent.value), whole=True)
            return
        if isinstance(parent, ast.Subscript) and parent.value is attr:
            statement = self.facts.parent(parent)
            if isinstance(parent.ctx, ast.Store) and isinstance(statement, ast.Assign) and statement.targets == [parent]:
                self._split_store(attr, statement, self.facts.segment(statement.value), whole=False)
                return
            if isinstance(parent.ctx, ast.Load):
                index = self.facts.segment(parent.slice)
                text = f"self.terminations[{index}] or self.truncations[{index}]"
                self.replace_text(parent, either(parent, text, self.facts))
                self.report(parent, "PZ108", "an agent is done when it is terminated or truncated (PettingZoo 1.21)")
                return
        aggregate = values_call(attr, self.facts)
        if aggregate is not None:
            outer, name = aggregate
            self.replace_text(outer, f"{name}(self.terminations[{AGENT}] or self.truncations[{AGENT}] for {AGENT} in self.terminations)")
            self.report(outer, "PZ108", "an agent is done when it is terminated or truncated (PettingZoo 1.21)")
            return
        self.report(attr, "PZ108", "`self.dones` was replaced by `self.terminations` and `self.truncations` in "
                    "PettingZoo 1.21: change this use by hand", FixKind.FLAG)

    def _split_store(self, attr: ast.Attribute, statement: ast.Assign, value: str, whole: bool) -> None:
        limit = bool(_STEP_LIMIT.search(value))
        stored, other = ("truncations", "terminations") if limit else ("terminations", "truncations")
        self.rename_attribute(attr, stored)
        if whole:
            self.plan.insert_after(statement, f"self.{other} = {{{AGENT}: False for {AGENT} in self.{stored}}}")
        self._report_split(statement, stored)

    def _report_split(self, statement: ast.stmt, stored: str) -> None:
        why = "it counts steps, so it reads as a step limit" if stored == "truncations" else "it reads as the game ending"
        self.report(statement, "PZ108", f"`self.dones` split: this store goes to `self.{stored}` ({why}); "
                    "review: game over is a termination, a step limit a truncation", FixKind.ASSIST)

    # -- spaces -----------------------------------------------------------------------------

    def _plan_space_methods(self, classdef: ast.ClassDef, methods: dict[str, ast.FunctionDef | ast.AsyncFunctionDef]) -> None:
        """Only ``self.observation_spaces`` / ``self.action_spaces`` dicts: PettingZoo (1.18 on)
        reads spaces through ``observation_space(agent)`` / ``action_space(agent)``, and its
        fallback to the dicts warns on every call since 1.22."""
        stores = {
            attr.attr
            for name in ("observation_spaces", "action_spaces")
            for attr in self.facts.attributes.get(name, ())
            if isinstance(attr.ctx, ast.Store) and self.facts.enclosing_class(attr) is classdef
        }
        added = [
            cst.parse_statement(f"def {name[:-1]}(self, agent):\n    return self.{name}[agent]\n").with_changes(
                leading_lines=[cst.EmptyLine(indent=False)]
            )
            for name in ("observation_spaces", "action_spaces")
            if name in stores and name[:-1] not in methods
        ]
        if not added:
            return
        self.changed()
        self.plan.insert_after(methods["__init__"], *added)
        self.report(methods["__init__"], "PZ108", "the env gets `observation_space(agent)` / `action_space(agent)` "
                    "methods over its space dicts (PettingZoo warns on every fallback to the dicts)")

    # -- render ---------------------------------------------------------------------------

    def _plan_render(self, classdef: ast.ClassDef, methods: dict[str, ast.FunctionDef | ast.AsyncFunctionDef]) -> None:
        """``def render(self, mode="human")``: since 1.22 the mode is ``self.render_mode``, set at
        construction (PettingZoo's wrappers assert that the attribute exists)."""
        render = methods["render"]
        params = [a.arg for a in render.args.args[1:]]
        if "mode" not in params or any(
            isinstance(attr.ctx, ast.Store) and self.facts.enclosing_class(attr) is classdef
            for attr in self.facts.attributes.get("render_mode", ())
        ):
            return  # no mode to move, or the class already stores ``self.render_mode``
        init = methods.get("__init__")
        if init is None or init.args.vararg or init.args.kwarg or init.args.kwonlyargs or any(
            a.arg == "render_mode" for a in init.args.args
        ):
            self.report(render, "PZ107", "`render()` takes no mode since PettingZoo 1.22: take `render_mode` in "
                        "`__init__`, store `self.render_mode` and read it in `render()`", FixKind.FLAG)
            return
        self.changed()
        self.plan.replace(render, lambda node: _without_param(node, "mode"))
        _insert_first(self.plan, render, "mode = self.render_mode")
        self.plan.replace(init, lambda node: _with_params(node, ["render_mode"]))
        _insert_first(self.plan, init, "self.render_mode = render_mode")
        self.report(render, "PZ107", "the render mode is fixed at construction (`render_mode=`, PettingZoo 1.22); "
                    "review: `render()` now reads `self.render_mode`", FixKind.ASSIST)

    # -- reset ----------------------------------------------------------------------------

    def _plan_reset(self, reset: ast.FunctionDef | ast.AsyncFunctionDef, kind: EnvKind, seeds_itself: bool) -> None:
        self._dropped: list[ast.If] = []
        args = reset.args
        names = [a.arg for a in (*args.posonlyargs, *args.args, *args.kwonlyargs)]
        return_info = next((a for a in args.args if a.arg == "return_info"), None)
        missing = [name for name in ("seed", "options") if name not in names]
        if args.vararg is not None or args.kwarg is not None:
            missing = []
        uses_info = [read for read in self.facts.scopes[reset].reads.get("return_info", [])] if return_info else []
        if return_info is not None and not self._plan_return_info_branches(uses_info):
            self.report(reset, "PZ105", "`return_info` was removed in PettingZoo 1.23: return `(observations, infos)` "
                        "by hand", FixKind.FLAG)
            return
        if missing or return_info is not None:
            self.changed()
            self.plan.replace(reset, lambda node: _reset_signature(node, missing))
            self.report(reset, "PZ105", "`reset` takes `seed=None, options=None` (PettingZoo 1.23 dropped `return_info`)",
                        FixKind.AUTO)
        if "seed" in missing and seeds_itself:
            _insert_first(self.plan, reset, "if seed is not None:\n    self.seed(seed)")
            self.report(reset, "PZ106", "the env seeds itself in `seed()`, which PettingZoo no longer calls: "
                        "`reset(seed=...)` calls it now; review", FixKind.ASSIST)
        if kind is EnvKind.PZ_PARALLEL:
            for returned in own_returns(reset):
                value = returned.value
                if value is None or isinstance(value, ast.Tuple) and len(value.elts) == 2:
                    continue
                if _is_reset_of(value) and self.multi_agent.kind(value.func.value) is not None:  # type: ignore[attr-defined]
                    continue  # a wrapper handing its env's reset on: that returns the pair already
                if any(self.facts.enclosing(returned, ast.If) is branch for branch in self._dropped):
                    continue
                text = self.facts.segment(value)
                self.replace_text(value, f"{text}, {{{AGENT}: {{}} for {AGENT} in self.agents}}")
                self.report(returned, "PZ105", "a parallel `reset` returns `(observations, infos)` since PettingZoo 1.23",
                            FixKind.AUTO)

    def _plan_return_info_branches(self, reads: list[ast.Name]) -> bool:
        """``if not return_info: return obs`` / ``else: ...``: keep the branch that returns infos.

        Decides every read first and plans only when each one is such a test (or the
        keyword that hands ``return_info`` on to a wrapped env); otherwise nothing changes.
        """
        branches: list[tuple[ast.If, bool]] = []  # (the if, keep its body rather than its else)
        for read in reads:
            test = self.facts.parent(read)
            if isinstance(test, ast.keyword) and test.arg == "return_info":
                continue  # ``self.env.reset(..., return_info=return_info)``: parallel.py drops it
            negated = isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not)
            branch, test = (self.facts.parent(test), test) if negated else (test, read)
            if not (isinstance(branch, ast.If) and branch.test is test):
                return False
            kept = branch.orelse if negated else branch.body
            if kept and (not self._own_line(kept[0]) or (len(kept) == 1 and isinstance(kept[0], ast.If) and branch.orelse is kept)):
                return False  # ``if x: return obs`` on one line, or an ``elif``: by hand
            branches.append((branch, not negated))
        for branch, keep_body in branches:
            self._dropped.append(branch)
            self.changed()
            if keep_body:
                self.plan.replace(branch, lambda node: cst.FlattenSentinel(node.body.body))
            elif branch.orelse:
                self.plan.replace(branch, lambda node: cst.FlattenSentinel(node.orelse.body.body))
            else:
                self.plan.remove(branch)
        return True

    def _own_line(self, statement: ast.stmt) -> bool:
        """``if x: return obs`` shares the ``if`` line: LibCST gives such a branch no indented block."""
        line = self.facts.lines[statement.lineno - 1]
        return not line[: statement.col_offset].strip()

    # -- parallel step --------------------------------------------------------------------

    def _plan_parallel_step(self, step: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        scope = self.facts.scopes[step]
        if "terminations" in scope.bindings or "truncations" in scope.bindings:
            return  # already migrated
        renamed: set[str] = set()
        for returned in own_returns(step):
            value = returned.value
            if not (isinstance(value, ast.Tuple) and len(value.elts) == 4):
                continue
            dones = value.elts[2]
            if isinstance(dones, ast.Dict) and not dones.keys:
                self.split_target(value, 2, "{}", "{}")
                self.report(returned, "PZ104", "a parallel `step` returns five dicts since PettingZoo 1.21", FixKind.AUTO)
                continue
            if isinstance(dones, ast.Name) and self._unpacked_from_step(scope.bindings.get(dones.id, [])):
                continue  # ``obs, rewards, dones, infos = self.env.step(...)``: parallel.py passes both on
            if isinstance(dones, ast.Name) and dones.id in scope.bindings:
                renamed.add(dones.id)
                self.split_target(value, 2, "terminations", "truncations")
                self.plan.insert_before(returned, f"truncations = {{{AGENT}: False for {AGENT} in terminations}}")
            else:
                self.report(returned, "PZ104", "a parallel `step` returns five dicts since PettingZoo 1.21: split "
                            f"`{self.facts.segment(dones)}` into terminations and truncations", FixKind.FLAG)
                continue
            self.report(returned, "PZ104", "a parallel `step` returns terminations and truncations; review: the "
                        "old dones are all terminations here, a step limit is a truncation", FixKind.ASSIST)
        flow = Flow.of(self.facts)
        for name in renamed:
            bindings = [b for b in scope.bindings[name] if isinstance(b, ast.Name)]
            reads = {id(r): r for b in bindings for r in flow.reads(b)}
            for node in [*bindings, *reads.values()]:
                self.rename(node, "terminations")


    def _unpacked_from_step(self, bindings: list[ast.AST]) -> bool:
        for binding in bindings:
            holder = self.facts.parent(binding)
            assign = self.facts.parent(holder) if isinstance(holder, (ast.Tuple, ast.List)) else None
            if isinstance(assign, ast.Assign) and isinstance(assign.value, ast.Call):
                func = assign.value.func
                if isinstance(func, ast.Attribute) and func.attr == "step":
                    return self.multi_agent.kind(func.value) is EnvKind.PZ_PARALLEL
        return False


def _reset_signature(node: cst.FunctionDef, missing: list[str]) -> cst.FunctionDef:
    return _with_params(_without_param(node, "return_info"), missing)


def _without_param(node: cst.FunctionDef, name: str) -> cst.FunctionDef:
    params = node.params
    kept = [p for p in params.params if p.name.value != name]
    if len(kept) != len(params.params) and kept:
        kept[-1] = kept[-1].with_changes(comma=params.params[-1].comma)
    return node.with_changes(params=params.with_changes(params=kept))


def _with_params(node: cst.FunctionDef, missing: list[str]) -> cst.FunctionDef:
    params = node.params
    kept = list(params.params)
    comma = cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
    for name in missing:
        if kept:
            kept[-1] = kept[-1].with_changes(comma=comma)
        kept.append(
            cst.Param(
                name=cst.Name(name),
                default=cst.Name("None"),
                equal=cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace("")),
            )
        )
    return node.with_changes(params=params.with_changes(params=kept))


def _insert_first(plan, function: ast.FunctionDef | ast.AsyncFunctionDef, code: str) -> None:  # type: ignore[no-untyped-def]
    """``code`` as the first statement of ``function`` (after its docstring)."""
    first = function.body[0]
    if _is_docstring(first) and len(function.body) > 1:
        plan.insert_after(first, code)
    else:
        plan.insert_before(first, code)


def _is_docstring(statement: ast.stmt) -> bool:
    return isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant) and isinstance(statement.value.value, str)


def _is_reset_of(value: ast.AST) -> bool:
    return isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == "reset"
