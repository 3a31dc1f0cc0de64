"""PZ108 (with PZ103-PZ107 inside env classes): custom ``AECEnv`` and ``ParallelEnv`` subclasses.

PettingZoo 1.21 renamed the helpers ``_was_done_step`` -> ``_was_dead_step`` and
``_dones_step_first`` -> ``_deads_step_first``, and replaced ``self.dones`` by two dicts
that ``last()``, ``_was_dead_step`` and the API tests all read: ``self.terminations``
(the game is over for the agent) and ``self.truncations`` (a step limit cut it short).
Each store is split by meaning (``endings.py`` traces its causes): a step or cycle limit
goes to ``self.truncations``, any other cause to ``self.terminations``, ``a or <limit>``
to both; what cannot be traced goes to ``self.terminations`` for review (one store:
``dones_split.py``). Reads read both.

This family finds the env classes and plans their ``self.dones``, renamed helpers and
space methods; each class's own methods are planned beside it: a parallel ``step``
returns five dicts (``class_step.py``), every ``reset`` takes ``seed=None,
options=None`` (``class_reset.py``), ``render`` takes its mode at construction
(``class_render.py``).
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import names as N
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import FUNCTIONS, own_returns
from gymmigrate.findings import FixKind
from gymmigrate.rules.pettingzoo.class_render import plan_render
from gymmigrate.rules.pettingzoo.class_reset import plan_reset
from gymmigrate.rules.pettingzoo.class_step import plan_parallel_step
from gymmigrate.rules.pettingzoo.common import (
    AGENT,
    PZ108,
    PettingZooFamily,
    either,
    values_call,
)
from gymmigrate.rules.pettingzoo.dones_split import DonesSplit
from gymmigrate.rules.pettingzoo.endings import Endings, Traced, joined
from gymmigrate.rules.pettingzoo.inner_dones import (
    dones_question,
    inner_step_unpack,
    plan_inner_dones,
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
        self.classes_dones_left: set[int] = set()
        self.classes_dones_split: set[int] = set()
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
                plan_reset(self, methods["reset"], kind, methods.get("seed"))
            if kind is EnvKind.PZ_PARALLEL and "step" in methods:
                plan_parallel_step(self, classdef, methods["step"])
            if kind is EnvKind.PZ_AEC:
                self._report_gym_protocol(methods)
            if "render" in methods:
                plan_render(self, classdef, methods)
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
            self.classes_dones_split.add(id(classdef))
            return {id(attr)} | {id(target.value) for statement in dels for target in statement.targets}  # type: ignore[attr-defined]
        self.classes_dones_left.add(id(classdef))
        return {id(attr)}

    def _plan_self_dones(self, attr: ast.Attribute) -> None:
        parent = self.facts.parent(attr)
        classdef = self.facts.enclosing_class(attr)
        assert classdef is not None
        split = DonesSplit(self, classdef, "self.terminations", "self.truncations", lambda new: self.rename_attribute(attr, new))
        if isinstance(parent, ast.Assign) and parent.targets == [attr]:
            split.whole(parent, owned=True)
            self.classes_dones_split.add(id(classdef))
            return
        if self._returned_by_parallel_step(attr, classdef):
            return  # the returned dict: PZ104's (``class_step.py``)
        if isinstance(parent, ast.Subscript) and parent.value is attr:
            statement = self.facts.parent(parent)
            if isinstance(parent.ctx, ast.Store) and isinstance(statement, ast.Assign) and statement.targets == [parent]:
                split.item(statement, parent)
                return
            if isinstance(parent.ctx, ast.Load):
                self.read_both(parent, "self.terminations", "self.truncations")
                return
        if not self.aggregate_both(attr, "self.terminations", "self.truncations"):
            self.classes_dones_left.add(id(classdef))
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

    def read_both(self, subscript: ast.Subscript, terminations: str, truncations: str) -> None:
        index = self.facts.segment(subscript.slice)
        text = f"{terminations}[{index}] or {truncations}[{index}]"
        self.replace_text(subscript, either(subscript, text, self.facts))
        self.report(subscript, "PZ108", "an agent is done when it is terminated or truncated (PettingZoo 1.21)")

    def aggregate_both(self, dones: ast.AST, terminations: str, truncations: str) -> bool:
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
            and self.own_line(assign)
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

    def own_line(self, statement: ast.stmt) -> bool:
        """``if x: return obs`` shares the ``if`` line: LibCST gives such a branch no indented block."""
        line = self.facts.lines[statement.lineno - 1]
        return not line[: statement.col_offset].strip()

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
