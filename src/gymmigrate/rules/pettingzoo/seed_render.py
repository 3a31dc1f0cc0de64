"""PZ106, PZ107: seeding and rendering at call sites of PettingZoo envs.

``seed()`` is gone from ``AECEnv`` (1.23.0) and ``ParallelEnv`` (1.23.1): the seed goes
to ``reset(seed=...)``. When the statement right after ``env.seed(s)`` is the env's
plain ``reset()``, the seed moves into it; otherwise ``env.seed(s)`` becomes its own
``env.reset(seed=s)``. Either way only that one reset is seeded, so later episodes
still differ (a seed on every reset would replay one episode forever).

``render(mode=...)`` lost its argument in 1.22: the mode is fixed where the env is made
(``rps_v2.env(render_mode="rgb_array")``). The creation call is found through the same
evidence as Gym's render rules; when it cannot be found the call is reported.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.arguments import append_keyword, remove_args
from gymmigrate.edits.lazy import cst
from gymmigrate.facts.creation import CreationFinder
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import call_argument, full_name, keyword
from gymmigrate.findings import FixKind
from gymmigrate.rules.pettingzoo.common import PZ106, PZ107, PettingZooFamily

PZ_FACTORY_SUFFIXES = (".env", ".parallel_env", ".raw_env")


class SeedRender(PettingZooFamily):
    RULES = (PZ106, PZ107)

    def decide(self) -> None:
        for call in self.facts.attribute_calls.get("seed", ()):
            func = call.func
            if not isinstance(func, ast.Attribute):  # ``x.method(...)`` calls only
                continue
            receiver = func.value
            if self.multi_agent.kind(receiver) is not None and not _is_self(receiver):
                self._plan_seed(call, receiver)
        self.finder: CreationFinder | None = None
        for call in self.facts.attribute_calls.get("render", ()):
            func = call.func
            if not isinstance(func, ast.Attribute):  # ``x.method(...)`` calls only
                continue
            receiver = func.value
            if (call.args or keyword(call, "mode")) and self.multi_agent.kind(receiver) is not None and not _is_self(receiver):
                self._plan_render(call)

    # -- seed ---------------------------------------------------------------------------

    def _plan_seed(self, call: ast.Call, receiver: ast.expr) -> None:
        statement = self.facts.parent(call)
        if not isinstance(statement, ast.Expr):
            self.report(call, "PZ106", "`seed()` was removed in PettingZoo 1.23: pass the seed to `reset(seed=...)`",
                        FixKind.FLAG)
            return
        seed = call_argument(call, 0, "seed")
        env = self.facts.segment(receiver)
        self.changed()
        if seed is None:
            self.plan.remove(statement, keep_comments=True)
            self.report(call, "PZ106", "`seed()` without a seed was removed in PettingZoo 1.23; `reset()` draws one itself")
            return
        seed_text = self.facts.segment(seed)
        following = self._next_plain_reset(statement, env)
        if following is not None:
            self.plan.remove(statement, keep_comments=True)
            self.plan.replace(following, lambda node: append_keyword(node, "seed", cst.parse_expression(seed_text)))
            self.report(call, "PZ106", "the seed moves to the first `reset(seed=...)` (PettingZoo 1.23 removed `seed()`)")
            return
        self.plan.replace(call, lambda node: cst.parse_expression(f"{env}.reset(seed={seed_text})"))
        self.report(call, "PZ106", "`seed(s)` becomes `reset(seed=s)` (PettingZoo 1.23 removed `seed()`)")

    def _next_plain_reset(self, statement: ast.stmt, env: str) -> ast.Call | None:
        holder = self.facts.parent(statement)
        for field in ("body", "orelse", "finalbody"):
            block = getattr(holder, field, None)
            if isinstance(block, list) and statement in block:
                index = block.index(statement)
                if index + 1 >= len(block):
                    return None
                following = block[index + 1]
                value = following.value if isinstance(following, (ast.Expr, ast.Assign)) else None
                if (
                    isinstance(value, ast.Call)
                    and isinstance(value.func, ast.Attribute)
                    and value.func.attr == "reset"
                    and self.facts.segment(value.func.value) == env
                    and not value.args
                    and all(k.arg not in ("seed", None) for k in value.keywords)
                ):
                    return value
                return None
        return None

    # -- render -------------------------------------------------------------------------

    def _plan_render(self, call: ast.Call) -> None:
        mode = call_argument(call, 0, "mode")
        if self._gym_class_forwards(call, mode):
            return  # the Gym env class's render rule (GM405) drops that mode and says where it goes
        if not (isinstance(mode, ast.Constant) and isinstance(mode.value, str)):
            self.report(call, "PZ107", "`render()` takes no mode since PettingZoo 1.22: pass `render_mode=` "
                        "where the env is made", FixKind.FLAG)
            return
        if self.finder is None:
            self.finder = CreationFinder(self.facts, self.receivers, self._is_creation)
        creation = self.finder.find(call.func.value)  # type: ignore[attr-defined]
        if not creation.found:
            self.report(call, "PZ107", f"`render()` takes no mode since PettingZoo 1.22: pass `render_mode={mode.value!r}` "
                        f"where the env is made ({creation.gap or 'not found here'})", FixKind.FLAG)
            return
        text = self.facts.segment(mode)
        for made in creation.calls:
            existing = keyword(made, "render_mode")
            if existing is None:
                self.plan.replace(made, lambda node: append_keyword(node, "render_mode", cst.parse_expression(text)))
            elif self.facts.segment(existing.value) != text:
                self.report(call, "PZ107", f"the env is made with another `render_mode`; this call asked for {text}",
                            FixKind.FLAG)
                return
        self.changed()
        self.plan.replace(call, lambda node: remove_args(node, lambda arg: True))
        self.report(call, "PZ107", f"the render mode {text} moves to where the env is made; review: "
                    "an env renders in one mode only")

    def _gym_class_forwards(self, call: ast.Call, mode: ast.AST | None) -> bool:
        """``self.env.render(mode)`` in the ``render(self, mode)`` of a Gym env class: the
        class's own ``mode`` handed on, which the Gym render rule migrates with the class."""
        function = self.facts.enclosing_function(call)
        classdef = self.facts.enclosing_class(call)
        return (
            isinstance(mode, ast.Name)
            and function is not None
            and function.name == "render"
            and classdef is not None
            and self.facts.enclosing_class(function) is classdef
            and any(arg.arg == mode.id for arg in function.args.args)
            and self.receivers.class_kind(classdef) is EnvKind.GYM_ENV
        )

    def _is_creation(self, call: ast.Call) -> bool:
        for qualified in self.facts.qualified_names(call.func):
            if qualified.startswith("pettingzoo.") and (qualified.endswith(PZ_FACTORY_SUFFIXES) or qualified == "pettingzoo.make"):
                return True
        local = self.receivers.local_class(call.func)
        return local is not None and self.multi_agent.class_kind(local) is not None


def _is_self(receiver: ast.AST) -> bool:
    return full_name(receiver) == "self"
