"""PZ108 (with PZ103-PZ106 inside env classes): custom ``AECEnv`` and ``ParallelEnv`` subclasses.

PettingZoo 1.21 renamed the helpers ``_was_done_step`` -> ``_was_dead_step`` and
``_dones_step_first`` -> ``_deads_step_first``, and replaced ``self.dones`` by two dicts
that ``last()``, ``_was_dead_step`` and the API tests all read: ``self.terminations``
(the game is over for the agent) and ``self.truncations`` (a step limit cut it short).
Each store is split by meaning (``endings.py`` traces its causes): a step or cycle limit
goes to ``self.truncations``, any other cause to ``self.terminations``, ``a or <limit>``
to both; what cannot be traced goes to ``self.terminations`` for review (one store:
``dones_split.py``). Reads read both.

A parallel env's ``step`` returns five dicts (its local ``dones`` is split the same way,
store by store), and its ``reset`` returns
``(observations, infos)`` without ``return_info`` (1.23). Every ``reset`` takes
``seed=None, options=None``; a class that seeds itself in ``seed()`` calls it from there.
"""

from __future__ import annotations

import ast
from functools import partial

from gymmigrate.edits.arguments import remove_args
from gymmigrate.edits.lazy import cst
from gymmigrate.facts import names as N
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, own_returns
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.pettingzoo.common import (
    AGENT,
    PZ108,
    PettingZooFamily,
    either,
    values_call,
)
from gymmigrate.rules.pettingzoo.dones_split import DonesSplit, is_empty_dict
from gymmigrate.rules.pettingzoo.endings import Endings, Traced, joined
from gymmigrate.rules.pettingzoo.inner_dones import (
    dones_question,
    inner_step_unpack,
    plan_inner_dones,
    settled,
    trailing_dels,
)
from gymmigrate.rules.pettingzoo.renamed_names import plan_renamed_names

RENAMED_HELPERS = {"_was_done_step": "_was_dead_step", "_dones_step_first": "_deads_step_first"}


class EnvClasses(PettingZooFamily):
    RULES = (PZ108,)

    def decide(self) -> None:
        facts = self.facts
        self._endings: dict[int, Endings] = {}
        self._split_assignments: dict[int, bool] = {}
        for old, new in RENAMED_HELPERS.items():
            for attr in facts.attributes.get(old, ()):
                self.rename_attribute(attr, new)
                self.report(attr, "PZ108", f"`{old}` is `{new}` since PettingZoo 1.21")
        for statement in facts.import_statements:
            if isinstance(statement, ast.ImportFrom) and statement.module == "pettingzoo.utils" and statement.level == 0:
                self._plan_agent_selector(statement)
        plan_renamed_names(self)
        self.classes = {id(c): kind for c in facts.all_classes if (kind := self.multi_agent.class_kind(c)) is not None}
        if not self.classes:
            return
        self._plan_wrapper_rng()
        # Classes whose ``self.dones`` a person splits (one question each), and those whose
        # stores were all split: only these return both dicts in place of ``self.dones``.
        self._dones_left: set[int] = set()
        self._dones_split: set[int] = set()
        own_dones = [
            attr
            for attr in facts.attributes.get("dones", ())
            if (classdef := facts.enclosing_class(attr)) is not None and id(classdef) in self.classes
            and isinstance(attr.value, ast.Name) and self.receivers.is_self(attr.value)
        ]
        taken: set[int] = set()  # the uses an unpack from an inner step decided with it
        for attr in own_dones:
            taken |= self._plan_unpacked_self_dones(attr)
        for attr in own_dones:
            if id(attr) not in taken:
                self._plan_self_dones(attr)
        for classdef in facts.all_classes:
            kind = self.classes.get(id(classdef))
            if kind is None:
                continue
            methods = {m.name: m for m in classdef.body if isinstance(m, FUNCTIONS)}
            if "reset" in methods:
                self._plan_reset(methods["reset"], kind, methods.get("seed"))
            if kind is EnvKind.PZ_PARALLEL and "step" in methods:
                self._plan_parallel_step(classdef, methods["step"])
            if kind is EnvKind.PZ_AEC:
                self._report_gym_protocol(methods)
            if "render" in methods:
                self._plan_render(classdef, methods)
            if "__init__" in methods:
                self._plan_space_methods(classdef, methods)
            if "last" in methods:
                self.report(methods["last"], "PZ108", "`last()` returns `observation, reward, termination, truncation, "
                            "info` since PettingZoo 1.21: check this override", FixKind.FLAG)

    def _report_gym_protocol(self, methods: dict[str, ast.FunctionDef | ast.AsyncFunctionDef]) -> None:
        """An AEC env class whose ``reset`` returns an observation and whose ``step`` returns
        four values: a Gym env's protocol on a PettingZoo base (a framework's adapter, stepped
        by Gym-style workers). The run migrates Gym-style callers to ``(obs, info)`` and five
        values; nothing here changes, so both sides are named for review."""
        reset, step = methods.get("reset"), methods.get("step")
        if reset is None or step is None:
            return
        bare = [r for r in own_returns(reset) if r.value is not None and not (isinstance(r.value, ast.Constant) and r.value.value is None)]
        four = [r for r in own_returns(step) if isinstance(r.value, ast.Tuple) and len(r.value.elts) == 4]
        if not bare or not four:
            return
        callers = (
            "code of the run that steps it as a Gym env (a worker's `obs, info = env.reset()`, five-value `step`) "
            "is migrated to Gymnasium's protocol and no longer matches it"
        )
        self.report(reset, "PZ108", f"an AEC env's reset() returns None, this one returns an observation as a Gym env's "
                    f"did: {callers}; return `(obs, {{}})` here, or keep those callers as they were", FixKind.FLAG)
        self.report(four[0], "PZ108", f"step returns four values as a Gym env's did (PettingZoo's AEC step returns "
                    f"None): {callers}; return `obs, rewards, termination, truncation, info`, or keep those callers",
                    FixKind.FLAG)

    def _plan_wrapper_rng(self) -> None:
        """``self.np_random`` in a ``BaseParallelWrapper`` subclass: PettingZoo 1.21's parallel
        wrappers and its AEC-to-parallel conversion forwarded unknown attributes to the env
        they wrap; the conversion no longer does (1.24: "'aec_to_parallel_wrapper' object has
        no attribute 'np_random'"). The generator belongs to the raw env: read it there."""
        for attr in self.facts.attributes.get("np_random", ()):
            if not (isinstance(attr.ctx, ast.Load) and isinstance(attr.value, ast.Name) and self.receivers.is_self(attr.value)):
                continue
            classdef = self.facts.enclosing_class(attr)
            if classdef is None or not self._is_parallel_wrapper(classdef) or any(
                isinstance(other.ctx, ast.Store) and self.facts.enclosing_class(other) is classdef
                for other in self.facts.attributes.get("np_random", ())
            ):
                continue
            self.changed()
            self.plan.replace(attr, lambda node: node.with_changes(value=cst.Attribute(value=node.value, attr=cst.Name("unwrapped"))))
            self.report(attr, "PZ108", "a parallel wrapper's `self.np_random` is the raw env's: read it through "
                        "`self.unwrapped` (PettingZoo's AEC-to-parallel conversion no longer forwards attributes)")

    def _is_parallel_wrapper(self, classdef: ast.ClassDef) -> bool:
        return any(
            qualified in N.PZ_PARALLEL_BASES and qualified in N.PZ_WRAPPER_BASES
            for base in classdef.bases
            for qualified in self.facts.qualified_names(base)
        )

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

    def _plan_unpacked_self_dones(self, attr: ast.Attribute) -> set[int]:
        """``obs, rews, self.dones, infos = self.<held>.step(actions)``: the ``self.dones`` uses
        decided with it (inner_dones.py), none when it is no such unpack."""
        unpack = inner_step_unpack(self, attr)
        if unpack is None or self.multi_agent.kind(unpack[1]) is not None:
            return set()  # a PettingZoo env's step: its dones are split already
        assign, held = unpack
        classdef = self.facts.enclosing_class(attr)
        assert classdef is not None
        dels = trailing_dels(self, assign, "self.dones")
        if plan_inner_dones(self, classdef, assign, held, "self.dones", lambda new: self.rename_attribute(attr, new), dels):
            self._dones_split.add(id(classdef))
            return {id(attr)} | {id(target.value) for statement in dels for target in statement.targets}  # type: ignore[attr-defined]
        self._dones_left.add(id(classdef))
        return {id(attr)}

    def _plan_self_dones(self, attr: ast.Attribute) -> None:
        parent = self.facts.parent(attr)
        classdef = self.facts.enclosing_class(attr)
        assert classdef is not None
        split = DonesSplit(self, classdef, "self.terminations", "self.truncations", lambda new: self.rename_attribute(attr, new))
        if isinstance(parent, ast.Assign) and parent.targets == [attr]:
            split.whole(parent, owned=True)
            self._dones_split.add(id(classdef))
            return
        if self._returned_by_parallel_step(attr, classdef):
            return  # the returned dict: PZ104's (``_plan_parallel_step``)
        if isinstance(parent, ast.Subscript) and parent.value is attr:
            statement = self.facts.parent(parent)
            if isinstance(parent.ctx, ast.Store) and isinstance(statement, ast.Assign) and statement.targets == [parent]:
                split.item(statement, parent)
                return
            if isinstance(parent.ctx, ast.Load):
                self._read_both(parent, "self.terminations", "self.truncations")
                return
        if not self._aggregate_both(attr, "self.terminations", "self.truncations"):
            self._dones_left.add(id(classdef))
            self.report(attr, "PZ108", "`self.dones` was replaced by `self.terminations` and `self.truncations` in "
                        "PettingZoo 1.21: change this use by hand", FixKind.FLAG, question=dones_question(classdef))

    def _returned_by_parallel_step(self, attr: ast.Attribute, classdef: ast.ClassDef) -> bool:
        """``return obs, rews, self.dones, infos`` in a parallel env's own ``step``."""
        holder = self.facts.parent(attr)
        function = self.facts.enclosing_function(attr)
        return (
            self.classes.get(id(classdef)) is EnvKind.PZ_PARALLEL
            and isinstance(holder, ast.Tuple) and len(holder.elts) == 4 and holder.elts[2] is attr
            and isinstance(self.facts.parent(holder), ast.Return)
            and function is not None and function.name == "step" and self.facts.parent(function) is classdef
        )

    def _read_both(self, subscript: ast.Subscript, terminations: str, truncations: str) -> None:
        index = self.facts.segment(subscript.slice)
        text = f"{terminations}[{index}] or {truncations}[{index}]"
        self.replace_text(subscript, either(subscript, text, self.facts))
        self.report(subscript, "PZ108", "an agent is done when it is terminated or truncated (PettingZoo 1.21)")

    def _aggregate_both(self, dones: ast.AST, terminations: str, truncations: str) -> bool:
        aggregate = values_call(dones, self.facts)
        if aggregate is None:
            return False
        outer, name = aggregate
        self.replace_text(outer, f"{name}({terminations}[{AGENT}] or {truncations}[{AGENT}] for {AGENT} in {terminations})")
        self.report(outer, "PZ108", "an agent is done when it is terminated or truncated (PettingZoo 1.21)")
        return True

    def replace_value(self, statement: ast.Assign, text: str) -> None:
        """The value of ``statement`` becomes ``text`` (a ``BoolOp`` cannot be addressed alone)."""
        self.changed()
        self.plan.replace(statement, lambda node: node.with_changes(value=cst.parse_expression(text)))

    def replace_element(self, value: ast.expr, text: str) -> None:
        """The per-agent value of a ``{k: v for k in ...}`` or ``dict.fromkeys(keys, v)`` becomes ``text``."""
        self.changed()
        if isinstance(value, ast.DictComp):
            self.plan.replace(value, lambda node: node.with_changes(value=cst.parse_expression(text)))
        else:
            self.plan.replace(value, lambda node: node.with_changes(
                args=[node.args[0], node.args[1].with_changes(value=cst.parse_expression(text))]))

    def endings(self, classdef: ast.ClassDef) -> Endings:
        if id(classdef) not in self._endings:
            self._endings[id(classdef)] = Endings(self.facts, classdef)
        return self._endings[id(classdef)]

    def split_assignment(self, traced: Traced, read: ast.AST) -> bool:
        """``done = caught or <limit>`` -> ``termination = caught`` / ``truncation = not
        termination and <limit>`` (and ``done = termination or truncation`` while other code
        reads ``done``), once per assignment; False when it cannot be done."""
        assign, name = traced.assign, traced.name
        assert assign is not None and name is not None
        key = id(assign)
        if key in self._split_assignments:
            return self._split_assignments[key]
        target = assign.targets[0]
        function = self.facts.enclosing_function(assign)
        bindings = self.facts.scopes[function].bindings if function is not None else {}
        ok = (
            isinstance(target, ast.Name)
            and "termination" not in bindings and "truncation" not in bindings
            and self._own_line(assign)
        )
        self._split_assignments[key] = ok
        if not ok or not isinstance(target, ast.Name):  # ``ok`` implies a Name
            return False
        reads = Flow.of(self.facts).reads(target)
        self.rename(target, "termination")
        self.replace_value(assign, joined(traced.task, self.facts))
        limit = joined(traced.limit, self.facts)
        limit = f"({limit})" if len(traced.limit) > 1 else limit
        inserted = [f"truncation = not termination and {limit}"]
        if len(reads) > 1 or any(r is not read for r in reads):
            inserted.append(f"{name.id} = termination or truncation")
        self.plan.insert_after(assign, *inserted)
        return True

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
        handed_on = self._mode_handed_to_modeless_render(render)
        if handed_on is not None:
            # ``def render(self, mode="human"): return self.env.render(mode)`` around an env
            # whose render takes no mode (it reads its own render_mode): that call raised
            # TypeError already; without the mode, both are what PettingZoo 1.22 calls.
            self.changed()
            self.plan.replace(render, lambda node: _without_param(node, "mode"))
            self.plan.replace(handed_on, lambda node: remove_args(node, lambda arg: True))
            held = self.facts.segment(handed_on.func.value)  # type: ignore[attr-defined]
            self.report(render, "PZ107", f"`render()` takes no mode since PettingZoo 1.22, and `{held}.render()`, which "
                        "this one handed the mode to, takes none either (its own render_mode decides): the mode is "
                        "dropped from both", FixKind.ASSIST)
            return
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

    def _mode_handed_to_modeless_render(self, render: ast.FunctionDef | ast.AsyncFunctionDef) -> ast.Call | None:
        """The one use of ``mode`` in ``render`` is ``self.<x>.render(mode)``, where every value
        the class stores in ``self.<x>`` is an instance of a class of this module whose
        ``render(self)`` takes nothing: that call; else None."""
        reads = self.facts.scopes[render].reads.get("mode", []) if render in self.facts.scopes else []
        if len(reads) != 1:
            return None
        call = self.facts.parent(reads[0])
        if not (
            isinstance(call, ast.Call)
            and len(call.args) == 1
            and call.args[0] is reads[0]
            and not call.keywords
            and isinstance(call.func, ast.Attribute)
            and call.func.attr == "render"
        ):
            return None
        held = call.func.value
        if not (isinstance(held, ast.Attribute) and isinstance(held.value, ast.Name) and held.value.id == "self"):
            return None
        values = self.receivers.self_attribute_values(held, held.attr)
        if not values:
            return None
        for value in values:
            classdef = self.receivers.local_class(value.func) if isinstance(value, ast.Call) else None
            if classdef is None:
                return None
            inner = next((m for m in classdef.body if isinstance(m, FUNCTIONS) and m.name == "render"), None)
            if inner is None or inner.args.vararg or inner.args.kwarg or len([*inner.args.posonlyargs, *inner.args.args]) != 1 or inner.args.kwonlyargs:
                return None
        return call

    # -- reset ----------------------------------------------------------------------------

    def _plan_reset(self, reset: ast.FunctionDef | ast.AsyncFunctionDef, kind: EnvKind, seed: ast.FunctionDef | ast.AsyncFunctionDef | None) -> None:
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
        if "seed" in missing and seed is not None:
            doubt = _seed_doubt(seed)
            if doubt is None:
                # ``env.seed(s); env.reset()`` ran the same two bodies in the same order.
                _insert_first(self.plan, reset, "if seed is not None:\n    self.seed(seed)")
                self.report(reset, "PZ106", "the env seeds itself in `seed()`, which PettingZoo no longer calls: "
                            "`reset(seed=...)` calls it first, as `env.seed(s)` before `env.reset()` did",
                            FixKind.ASSIST, tier=Tier.NOTE)
            else:
                self.report(reset, "PZ106", "the env seeds itself in `seed()`, which PettingZoo no longer calls, "
                            f"and {doubt}: seed the env from `reset(seed=...)` by hand", FixKind.FLAG)
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
        handed_on: list[ast.Call] = []
        for read in reads:
            test = self.facts.parent(read)
            if isinstance(test, ast.keyword) and test.arg == "return_info":
                # ``self.env.reset(..., return_info=return_info)``: the keyword goes with the
                # parameter (parallel.py drops it on a PettingZoo env; here on any other).
                call = self.facts.parent(test)
                if isinstance(call, ast.Call) and not (
                    isinstance(call.func, ast.Attribute) and self.multi_agent.kind(call.func.value) is not None
                ):
                    handed_on.append(call)
                continue
            negated = isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not)
            if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
                branch, test = self.facts.parent(test), test
            else:
                branch, test = test, read
            if not (isinstance(branch, ast.If) and branch.test is test):
                return False
            kept = branch.orelse if negated else branch.body
            if kept and (not self._own_line(kept[0]) or (len(kept) == 1 and isinstance(kept[0], ast.If) and branch.orelse is kept)):
                return False  # ``if x: return obs`` on one line, or an ``elif``: by hand
            branches.append((branch, not negated))
        for call in handed_on:
            self.changed()
            self.plan.replace(call, lambda node: remove_args(node, lambda arg: arg.keyword is not None and arg.keyword.value == "return_info"))
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

    def _plan_parallel_step(self, classdef: ast.ClassDef, step: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        scope = self.facts.scopes[step]
        if "terminations" in scope.bindings or "truncations" in scope.bindings:
            return  # already migrated
        names: set[str] = set()  # the local dicts split already (two returns may hand one back)
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
            if isinstance(dones, ast.Name) and dones.id in scope.bindings and (
                dones.id in names or self._local_dones(classdef, step, dones.id)
            ):
                names.add(dones.id)
                self.split_target(value, 2, "terminations", "truncations")
                self.report(returned, "PZ104", "a parallel `step` returns terminations and truncations since PettingZoo "
                            "1.21", FixKind.AUTO)
            elif self._split_self_dones(classdef, dones):
                # every store of ``self.dones`` in the class went to one dict, with the other beside it
                self.split_target(value, 2, "self.terminations", "self.truncations")
                self.report(returned, "PZ104", "a parallel `step` returns terminations and truncations since PettingZoo "
                            "1.21", FixKind.AUTO)
            else:
                self.report(returned, "PZ104", "a parallel `step` returns five dicts since PettingZoo 1.21: split "
                            f"`{self.facts.segment(dones)}` into terminations and truncations", FixKind.FLAG,
                            question=dones_question(classdef))

    def _split_self_dones(self, classdef: ast.ClassDef, dones: ast.expr) -> bool:
        return (
            isinstance(dones, ast.Attribute) and dones.attr == "dones"
            and isinstance(dones.value, ast.Name) and self.receivers.is_self(dones.value)
            and id(classdef) in self._dones_split and id(classdef) not in self._dones_left
        )

    def _local_dones(self, classdef: ast.ClassDef, step: ast.FunctionDef | ast.AsyncFunctionDef, name: str) -> bool:
        """Split the local ``dones`` of a parallel ``step``: each whole store and item store by
        its causes, each read of both dicts. False (nothing planned) when a binding is not a
        plain ``dones = ...``."""
        scope = self.facts.scopes[step]
        bindings = [b for b in scope.bindings[name] if isinstance(b, ast.Name)]
        # ``obs, rews, dones, infos = self.<held>.step(actions)``: the dones of what the env drives
        unpacks = {id(b): u for b in bindings if (u := inner_step_unpack(self, b)) is not None and self.multi_agent.kind(u[1]) is None}
        if len(bindings) != len(scope.bindings[name]) or not all(
            id(b) in unpacks or _plain_assign(self.facts.parent(b), b) for b in bindings
        ):
            return False
        dels = {id(b): trailing_dels(self, unpacks[id(b)][0], name) for b in bindings if id(b) in unpacks}
        unsettled = [b for b in bindings if id(b) in unpacks and settled(self, *unpacks[id(b)], dels[id(b)])[0] is None]
        for binding in unsettled or [b for b in bindings if id(b) in unpacks]:
            # an unsettled unpack is asked about there, and nothing of the step is planned
            plan_inner_dones(self, classdef, *unpacks[id(binding)], name, partial(self.rename, binding), dels[id(binding)])
        if unsettled:
            return False
        taken = {id(target.value) for found in dels.values() for statement in found for target in statement.targets}  # type: ignore[attr-defined]
        flow = Flow.of(self.facts)
        reads = [r for r in {id(r): r for b in bindings for r in flow.reads(b)}.values() if id(r) not in taken]
        bindings = [b for b in bindings if id(b) not in unpacks]
        empty = any(is_empty_dict(self.facts.parent(b).value) for b in bindings)  # type: ignore[union-attr]
        splits: list[DonesSplit] = []
        item_stores: list[tuple[ast.Assign, ast.Subscript, DonesSplit]] = []
        other_reads: list[ast.Name] = []
        # An unpack at the top of the step binds both dicts before any later store: such a
        # store keeps an agent that terminated on the step terminated, as ``self.dones`` does.
        bound = [unpacks[key][0] for key in unpacks if unpacks[key][0] in step.body]
        for binding in bindings:
            split = DonesSplit(self, classdef, "terminations", "truncations", partial(self.rename, binding), empty)
            splits.append(split)
            store = self.facts.parent(binding)
            owned = any(assign.lineno < binding.lineno for assign in bound)
            split.whole(store, owned=owned)  # type: ignore[arg-type]
        for read in reads:
            subscript = self.facts.parent(read)
            statement = self.facts.parent(subscript) if subscript is not None else None
            if (
                isinstance(subscript, ast.Subscript) and subscript.value is read and isinstance(subscript.ctx, ast.Store)
                and isinstance(statement, ast.Assign) and statement.targets == [subscript]
            ):
                split = DonesSplit(self, classdef, "terminations", "truncations", partial(self.rename, read), empty)
                item_stores.append((statement, subscript, split))
                split.item(statement, subscript)
                splits.append(split)
            else:
                other_reads.append(read)
        limited = any(split.limited for split in splits)
        for read in other_reads:
            parent = self.facts.parent(read)
            if self._is_returned(read):
                continue
            if not limited:
                self.rename(read, "terminations")
            elif isinstance(parent, ast.Subscript) and parent.value is read and isinstance(parent.ctx, ast.Load):
                self._read_both(parent, "terminations", "truncations")
            elif not self._aggregate_both(read, "terminations", "truncations"):
                self.rename(read, "terminations")
                self.report(read, "PZ104", f"`{name}` is split into terminations and truncations: this use reads only "
                            "the terminations; check it", FixKind.ASSIST)
        return True

    def _is_returned(self, read: ast.Name) -> bool:
        holder = self.facts.parent(read)
        return isinstance(holder, ast.Tuple) and isinstance(self.facts.parent(holder), ast.Return) and len(holder.elts) == 4 \
            and holder.elts[2] is read

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


def _insert_first(plan, function: ast.FunctionDef | ast.AsyncFunctionDef, code: str) -> None:
    """``code`` as the first statement of ``function`` (after its docstring)."""
    first = function.body[0]
    if _is_docstring(first) and len(function.body) > 1:
        plan.insert_after(first, code)
    else:
        plan.insert_before(first, code)


def _seed_doubt(seed: ast.FunctionDef | ast.AsyncFunctionDef) -> str | None:
    """Why ``self.seed(seed)`` at the top of ``reset`` may not do what a caller's
    ``env.seed(s)`` before ``env.reset()`` did; None when it does."""
    args = seed.args
    positional = [*args.posonlyargs, *args.args][1:]  # after ``self``
    required = len(positional) - len(args.defaults)
    if not positional and args.vararg is None:
        return "its `seed()` takes no seed by position"
    if required > 1 or any(default is None for default in args.kw_defaults):
        return "its `seed()` takes more than the seed"
    if isinstance(seed, ast.AsyncFunctionDef):
        return "its `seed()` is a coroutine"
    for node in ast.walk(seed):
        if (
            isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "reset"
            and isinstance(node.func.value, ast.Name) and node.func.value.id == "self"
        ):
            return "its `seed()` calls `self.reset()` (calling it from `reset` would loop)"
    return None


def _is_docstring(statement: ast.stmt) -> bool:
    return isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant) and isinstance(statement.value.value, str)


def _is_reset_of(value: ast.AST) -> bool:
    return isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == "reset"


def _plain_assign(statement: ast.AST | None, target: ast.AST) -> bool:
    return isinstance(statement, ast.Assign) and statement.targets == [target]
