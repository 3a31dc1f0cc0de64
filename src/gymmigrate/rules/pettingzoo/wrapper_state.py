"""PZ112: PettingZoo's wrapper bases no longer copy the wrapped env's state.

Up to PettingZoo 1.24.2, ``BaseWrapper.reset`` and ``BaseWrapper.step`` copied the wrapped
env's ``agent_selection``, ``rewards``, ``terminations``, ``truncations``, ``infos``,
``agents`` and ``_cumulative_rewards`` onto the wrapper after each call, and
``BaseParallelWrapper`` its ``agents``. Since 1.24.3 (PettingZoo#1140, "Update wrappers to
use ``__getattr__`` instead of redefining attributes") they forward them through
``__getattr__``, which reaches the env only while the wrapper has no attribute of that name.
A wrapper that assigns one (``self.rewards = {...}`` to transform the rewards,
``self.agents = self.env.agents[:]``) keeps its own value from then on, through the next
``reset``: rewards and dones of another episode's agents (``KeyError`` on a new agent, a
reward for an agent that is gone), an ``agent_selection`` left from the last episode.

For the attributes the class assigns (the others still reach the env), the copy the base
made is written out where it ran: after each ``super().reset(...)`` / ``super().step(...)``
statement, and in a ``reset`` / ``step`` added where the class inherits PettingZoo's own
(no class of the run on the way defines one). A base call inside an expression
(``return super().step(actions)``) is reported.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.module import FUNCTIONS, is_super_call
from gymmigrate.facts.pz_wrappers import AEC, wrapper_api
from gymmigrate.findings import FixKind
from gymmigrate.rules.pettingzoo.common import PZ112, PettingZooFamily

# What each base copied, in its order.
COPIED = {
    AEC: ("agent_selection", "rewards", "terminations", "truncations", "infos", "agents", "_cumulative_rewards"),
    "parallel": ("agents",),
}
# AECEnv helpers that set ``self.agent_selection`` on the object they are called on.
_SELECTING_HELPERS = frozenset({"_was_dead_step", "_deads_step_first", "_was_done_step", "_dones_step_first"})
_BASE_METHODS = ("reset", "step")
_ADDED = {
    (AEC, "reset"): ("def reset(self, seed=None, options=None):\n    super().reset(seed=seed, options=options)\n", None),
    (AEC, "step"): ("def step(self, action):\n    super().step(action)\n", None),
    ("parallel", "reset"): (
        "def reset(self, seed=None, options=None):\n    observations, infos = super().reset(seed=seed, options=options)\n",
        "    return observations, infos\n",
    ),
    ("parallel", "step"): (
        "def step(self, actions):\n"
        "    observations, rewards, terminations, truncations, infos = super().step(actions)\n",
        "    return observations, rewards, terminations, truncations, infos\n",
    ),
}


class WrapperState(PettingZooFamily):
    RULES = (PZ112,)

    def decide(self) -> None:
        project = self.context.options.project
        view = project.view(self.context.path) if project is not None else None
        wrappers = {id(c): (c, found) for c in self.facts.all_classes if (found := wrapper_api(self.facts, c, view)) is not None}
        if not wrappers:
            return
        own = {key: self._assigned(c, found[0]) for key, (c, found) in wrappers.items()}
        # An instance of a subclass runs its bases' methods: a base's copy covers what the
        # subclasses of this module assign too.
        effective = {key: set(names) for key, names in own.items()}
        for key, (classdef, _) in wrappers.items():
            for ancestor in self._local_ancestors(classdef):
                if id(ancestor) in effective:
                    effective[id(ancestor)] |= own[key]
        for key, (classdef, (api, methods, inherited)) in wrappers.items():
            copied = [name for name in COPIED[api] if name in effective[key]]
            if copied:
                self._plan_class(classdef, api, methods, inherited, copied, bool(own[key]))

    def _local_ancestors(self, classdef: ast.ClassDef) -> list[ast.ClassDef]:
        found: list[ast.ClassDef] = []
        todo = [classdef]
        while todo and len(found) < 16:
            current = todo.pop()
            for base in current.bases:
                local = self.facts.classes.get(base.id) if isinstance(base, ast.Name) else None
                if local is not None and local is not classdef and all(local is not f for f in found):
                    found.append(local)
                    todo.append(local)
        return found

    def _methods(self, classdef: ast.ClassDef) -> list[ast.FunctionDef | ast.AsyncFunctionDef]:
        return [s for s in classdef.body if isinstance(s, FUNCTIONS)]

    def _walk(self, function: ast.AST):
        """The nodes of a method, without nested classes (their ``self`` is another object)."""
        stack = list(ast.iter_child_nodes(function))
        while stack:
            node = stack.pop()
            if isinstance(node, ast.ClassDef):
                continue
            yield node
            stack.extend(ast.iter_child_nodes(node))

    @staticmethod
    def _self_name(function: ast.FunctionDef | ast.AsyncFunctionDef) -> str | None:
        if any(isinstance(d, ast.Name) and d.id in ("staticmethod", "classmethod") for d in function.decorator_list):
            return None
        params = function.args.posonlyargs + function.args.args
        return params[0].arg if params else None

    def _assigned(self, classdef: ast.ClassDef, api: str) -> set[str]:
        """The copied attributes the class's methods store on ``self``."""
        found: set[str] = set()
        for function in self._methods(classdef):
            me = self._self_name(function)
            if me is None:
                continue
            for node in self._walk(function):
                if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == me:
                    if isinstance(node.ctx, ast.Store) and node.attr in COPIED[api]:
                        found.add(node.attr)
                    elif api == AEC and node.attr in _SELECTING_HELPERS and isinstance(self.facts.parent(node), ast.Call):
                        found.add("agent_selection")
        return found

    def _base_call(self, call: ast.AST, classdef: ast.ClassDef, me: str) -> str | None:
        """``reset``/``step`` for ``super().reset(...)`` or ``Base.step(self, ...)`` naming a base."""
        if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute) and call.func.attr in _BASE_METHODS):
            return None
        receiver = call.func.value
        if is_super_call(receiver):
            return call.func.attr
        if (
            isinstance(receiver, ast.Name)
            and any(isinstance(b, ast.Name) and b.id == receiver.id for b in classdef.bases)
            and call.args
            and isinstance(call.args[0], ast.Name)
            and call.args[0].id == me
        ):
            return call.func.attr
        return None

    def _plan_class(
        self, classdef: ast.ClassDef, api: str, chain_methods: frozenset[str], inherited: frozenset[str],
        copied: list[str], assigns: bool,
    ) -> None:
        names = ", ".join(f"`{n}`" for n in copied)
        for function in self._methods(classdef):
            me = self._self_name(function)
            if me is None:
                continue
            for node in self._walk(function):
                method = self._base_call(node, classdef, me)
                if method is None or method in inherited:
                    continue  # a class of the run on the way: its own call of the base copies
                statement = self.facts.parent(node)
                if isinstance(statement, (ast.Expr, ast.Assign, ast.AnnAssign)) and statement.value is node:
                    missing = [n for n in copied if n not in self._copied_after(statement, me)]
                    if not missing:
                        continue
                    self.changed()
                    self.plan.insert_after(statement, *(f"{me}.{n} = {me}.env.{n}" for n in missing))
                    self.report(statement, "PZ112", self._message(method, names, "so the copy follows this call"))
                else:
                    self.report(node, "PZ112", self._message(method, names, "this call sits inside an expression: copy "
                                "them from `self.env` after it by hand"), FixKind.FLAG)
        if not assigns:
            return  # only subclasses assign: they get the methods they inherit from PettingZoo
        last = classdef.body[-1]
        added = []
        for method in _BASE_METHODS:
            if method in chain_methods:
                continue
            head, tail = _ADDED[(api, method)]
            text = head + "".join(f"    self.{n} = self.env.{n}\n" for n in copied) + (tail or "")
            added.append(cst.parse_statement(text).with_changes(leading_lines=[cst.EmptyLine(indent=False)]))
        if added:
            self.changed()
            self.plan.insert_after(last, *added)
            self.report(last, "PZ112", self._message(" and ".join(m for m in _BASE_METHODS if m not in chain_methods), names,
                                                     "the class inherited it: it gets one that makes the copy"))

    def _copied_after(self, statement: ast.stmt, me: str) -> set[str]:
        """The attributes the statements right after ``statement`` already copy from ``self.env``."""
        body = self._block_of(statement)
        found: set[str] = set()
        if body is None:
            return found
        for following in body[body.index(statement) + 1 :]:
            if not (isinstance(following, ast.Assign) and len(following.targets) == 1):
                break
            target, value = following.targets[0], following.value
            if not (
                isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == me
                and isinstance(value, ast.Attribute) and value.attr == target.attr
                and isinstance(value.value, ast.Attribute) and value.value.attr == "env"
                and isinstance(value.value.value, ast.Name) and value.value.value.id == me
            ):
                break
            found.add(target.attr)
        return found

    def _block_of(self, statement: ast.stmt) -> list[ast.stmt] | None:
        parent = self.facts.parent(statement)
        for field in ("body", "orelse", "finalbody"):
            block = getattr(parent, field, None)
            if isinstance(block, list) and any(s is statement for s in block):
                return block
        return None

    @staticmethod
    def _message(method: str, names: str, what: str) -> str:
        return (f"PettingZoo's wrapper {method}() copied {names} from the wrapped env until 1.24.3; now the "
                f"wrapper only forwards them while it has none of its own, and this class assigns them: {what}")
