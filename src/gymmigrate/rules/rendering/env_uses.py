"""How the env a make builds is used away from its renders: where it is stepped (its own
loop, a helper that only steps, a method of the class holding ``self.env``), whether a
loop that steps it also renders it, whether a render runs on every step, and where it is
passed on to code that may train with it (``stepped at line N``, ``passed to f()``).

Separate from ``planning.py`` because these are facts about the env's uses, read the
same for every site of a make; ``planning.py`` decides from them which mode each make
gets and what each site's finding and edit are.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.creation import CreationFinder
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.module import walk
from gymmigrate.rules.render_schedule import render_condition
from gymmigrate.rules.rendering.common import RenderSite
from gymmigrate.rules.rendering.makes import MakeEdits

# What an env exposes without running it: reading them neither steps nor draws.
_INERT_ATTRIBUTES = frozenset({"action_space", "observation_space", "spec", "metadata", "reward_range"})


class EnvUses(MakeEdits):
    """Where the env a make builds is stepped, drawn and passed (mixed into the family)."""

    def _used_where_nothing_renders(self, make: ast.Call, sites: list[RenderSite]) -> str | None:
        """How the env made by ``make`` (``env = gym.make(...)``) is used away from its renders:
        ``"stepped at line N"`` in a loop without a render call, ``"passed to f()"`` (a
        training function, an agent) — or None when every use renders as it goes (a
        legacy script that watches what it runs, where human mode draws as before)."""
        assign = self.facts.parent(make)
        if not (isinstance(assign, ast.Assign) and len(assign.targets) == 1 and isinstance(assign.targets[0], ast.Name)):
            return None
        rendered = {id(site.node) for site in sites}
        receivers = [site.node.func.value for site in sites if isinstance(site.node.func, ast.Attribute)]
        targets = [assign.targets[0]]
        for target in targets:
            # Every read of that binding, in the functions of the module too (a training
            # function that steps the module's ``env``): the scopes already index their reads.
            reads = self.facts.reads_of(target.id)
            for read in reads:
                if target not in self.facts.bindings_of(read):
                    continue
                parent = self.facts.parent(read)
                if isinstance(parent, ast.Call) and read in parent.args and not self._under_gym(parent.func):
                    if self._reads_only_spaces(parent, read):
                        continue
                    wrapped = self._rendered_wrapper(parent, receivers)
                    if wrapped is not None:
                        # ``env = Shim(env)`` and the renders draw ``env``: the wrapper is the
                        # env rendered, and its own uses are the ones to look at.
                        if wrapped not in targets:
                            targets.append(wrapped)
                        continue
                    if self._renders_reach(parent, sites):
                        # The renders' creation search went through this wrapper (a factory
                        # returns it, a loop renders what the factory gives): it is the env
                        # rendered; its binding's own uses are the ones to look at.
                        assign = self.facts.parent(parent)
                        if isinstance(assign, ast.Assign) and len(assign.targets) == 1 and isinstance(assign.targets[0], ast.Name):
                            if assign.targets[0] not in targets:
                                targets.append(assign.targets[0])
                        continue
                    return f"passed to {self.facts.segment(parent.func)}()"
                if isinstance(parent, ast.Attribute) and parent.attr == "step":
                    call = self.facts.parent(parent)
                    if isinstance(call, ast.Call) and call.func is parent and not self._loop_renders(call, rendered):
                        return f"stepped at line {call.lineno}"
        return None

    def _renders_reach(self, call: ast.Call, sites: list[RenderSite]) -> bool:
        """The search from a render site's receiver back to its make went through ``call``:
        what the call makes is what that site renders. Asked of a finder of these sites alone
        (the family's own has followed recorders' and wrappers' arguments too)."""
        probe = CreationFinder(self.facts, self.receivers, self._is_make)
        for site in sites:
            if isinstance(site.node.func, ast.Attribute):
                probe.find(site.node.func.value)
        return probe.reached(call)

    def _rendered_wrapper(self, call: ast.Call, receivers: list[ast.expr]) -> ast.Name | None:
        """``env = Shim(env)`` (the call's result bound to a plain name) where that binding
        is what a render site draws: the new binding, else None."""
        assign = self.facts.parent(call)
        if not (isinstance(assign, ast.Assign) and assign.value is call and len(assign.targets) == 1):
            return None
        bound = assign.targets[0]
        if not isinstance(bound, ast.Name):
            return None
        if any(isinstance(r, ast.Name) and bound in self.facts.bindings_of(r) for r in receivers):
            return bound
        return None

    def _reads_only_spaces(self, call: ast.Call, read: ast.Name) -> bool:
        """``actions(env)`` where ``def actions(env)`` of this module only reads the env's
        spaces or spec (``env.action_space.high``): nothing there steps or draws, so the call
        changes no schedule."""
        if not isinstance(call.func, ast.Name) or any(isinstance(a, ast.Starred) for a in call.args):
            return False
        function = self.facts.functions.get(call.func.id)
        if function is None or self.facts.bindings_of(call.func) != [function]:
            return False
        params = [*function.args.posonlyargs, *function.args.args]
        position = call.args.index(read)
        if position >= len(params):
            return False
        name = params[position].arg
        uses = [n for n in walk(function) if isinstance(n, ast.Name) and n.id == name]
        return all(
            isinstance(n.ctx, ast.Load)
            and isinstance(parent := self.facts.parent(n), ast.Attribute)
            and parent.value is n
            and parent.attr in _INERT_ATTRIBUTES
            for n in uses
        )

    def _steps_render(self, key: int) -> bool:
        """Every ``step`` of the env made by ``key`` sits in a loop that renders it."""
        if key in self._drawn_by_forward:
            return True  # stepped and drawn through a class of the run holding it (sites.py)
        make = self._makes_by_id.get(key)
        steps = (self._steps_of_make(make) if make is not None else None) or []
        if not steps and make is not None:
            steps = self._steps_traced_to(make)
        return bool(steps) and all(self._loop_renders(call, self._rendered_nodes) for call in steps)

    def _steps_traced_to(self, make: ast.Call) -> list[ast.Call]:
        """The ``x.step(...)`` calls of the module whose receiver the creation search follows
        back to ``make`` alone (a loop over what a factory returns, a wrapper of the made
        env): where the env is stepped when its own binding is not."""
        steps = []
        for call in self.facts.attribute_calls.get("step", ()):
            creation = self.finder.find(call.func.value)  # type: ignore[attr-defined]
            if creation.found and any(c is make for c in creation.calls):
                steps.append(call)
        return steps

    def _steps_of_make(self, make: ast.Call) -> list[ast.Call] | None:
        """The steps of the env ``env = make(...)`` binds, or ``self.env = make(...)`` in a
        method (its class's ``self.env.step(...)`` calls); None when the make binds neither."""
        assign = self.facts.parent(make)
        if not (isinstance(assign, ast.Assign) and len(assign.targets) == 1):
            return None
        target = assign.targets[0]
        if isinstance(target, ast.Attribute):
            classdef = self.facts.enclosing_class(make)
            if classdef is None or not (isinstance(target.value, ast.Name) and self.receivers.is_self(target.value)):
                return None
            return [
                call
                for call in self.facts.attribute_calls.get("step", ())
                if isinstance(held := call.func.value, ast.Attribute)  # type: ignore[attr-defined]
                and held.attr == target.attr
                and isinstance(held.value, ast.Name)
                and self.receivers.is_self(held.value)
                and self.facts.enclosing_class(call) is classdef
            ]
        if not isinstance(target, ast.Name):
            return None
        return self._steps_of(target.id, lambda read: target in self.facts.bindings_of(read))

    def _stepping_function(self, make: ast.Call, renders: list[ast.Call] = []) -> ast.AST | None:  # noqa: B006 (never mutated)
        """The one function (not the make's own) where the env ``make`` binds is stepped, or
        None: ``env = gym.make(...)`` at the top, ``env.step`` only inside ``main()``. A
        helper that only steps (``def take_step(a): return env.step(a)``), called only from
        one function that holds the ``renders``, hands the role on to that function: the env
        is stepped exactly when it runs."""
        homes = {self.facts.enclosing_function(call) for call in self._steps_of_make(make) or ()}
        if len(homes) != 1:
            return None
        home = next(iter(homes))
        if home is not None and renders and not any(self.facts.enclosing_function(r) is home for r in renders):
            caller = self._sole_caller(home)
            if caller is not None and any(self.facts.enclosing_function(r) is caller for r in renders):
                home = caller
        return home if home is not None and home is not self.facts.enclosing_function(make) else None

    def _sole_caller(self, function: ast.AST) -> ast.FunctionDef | ast.AsyncFunctionDef | None:
        """The one function from which a module-level def is called, when its name is read
        only to call it (never passed on, never rebound) and every call sits in that function."""
        name = getattr(function, "name", None)
        if name is None or self.facts.functions.get(name) is not function:
            return None
        reads = self.facts.reads_of(name, function)
        callers = set()
        for read in reads:
            call = self.facts.parent(read)
            if not (isinstance(call, ast.Call) and call.func is read):
                return None
            callers.add(self.facts.enclosing_function(call))
        if len(callers) != 1 or len(self.facts.bindings_of(reads[0])) != 1:
            return None
        caller = next(iter(callers))
        return caller if caller is not None and caller is not function else None

    def _under_gym(self, func: ast.expr) -> bool:
        """A gym/gymnasium callable (a wrapper taking the env is no training function)."""
        return any(N.strip_gym_prefix(q) is not None for q in self.facts.qualified_names(func))

    def _loop_renders(self, call: ast.Call, rendered: set[int]) -> bool:
        """The innermost loop around ``call`` holds one of the render sites."""
        loop = next((a for a in self.facts.ancestors(call) if isinstance(a, (ast.For, ast.While, ast.AsyncFor))), None)
        if loop is None and self._rendered_next(call, rendered):
            # ``obs = env.step(a)`` then ``env.render()`` in the same block: this step is
            # drawn as it happens, as human mode draws it.
            return True
        if loop is None:
            helper = self.facts.enclosing_function(call)
            if helper is not None and any(
                id(node) in rendered and self.facts.enclosing_function(node) is helper for node in walk(helper) if isinstance(node, ast.Call)
            ):
                # ``def update(dt): env.step(a); env.render()``, a callback run once per frame:
                # each run of the function is one pass, and it renders what it steps.
                return True
            # ``def take_step(a): return env.step(a)``: the step runs where the helper is
            # called; it renders if every call of the helper sits in a loop that renders.
            if helper is None or self.facts.functions.get(helper.name) is not helper or self._sole_caller(helper) is None:
                return False
            name = helper.name
            calls = [c for c in self.facts.calls_by_name.get(name, ()) if helper in self.facts.bindings_of(c.func)]  # type: ignore[arg-type]
            return bool(calls) and all(self._loop_renders(c, rendered) for c in calls if c is not call)
        return any(id(node) in rendered for node in walk(loop) if isinstance(node, ast.Call))

    def _rendered_next(self, call: ast.Call, rendered: set[int]) -> bool:
        """A statement after the one holding ``call``, in the same block and before any other
        ``step``, is a bare render site (``env.render()`` as a statement of its own): the
        step always runs with a render right after it, nothing between them skipping it."""
        statement = self.facts.statement_of(call)
        found = Flow.of(self.facts).block_of(statement)
        if found is None:
            return False
        block, index = found
        for later in block[index + 1 :]:
            if isinstance(later, ast.Expr) and isinstance(later.value, ast.Call) and id(later.value) in rendered:
                return True
            if any(
                isinstance(node, (ast.Return, ast.Break, ast.Continue, ast.Raise))
                or (isinstance(node, ast.Attribute) and node.attr == "step")
                for node in ast.walk(later)
            ):
                return False
        return False

    def _drawn_every_step(self, render: ast.Call, keys: list[int]) -> bool:
        """``render`` runs on every pass of the loop that holds each step of the envs the
        makes ``keys`` bind: a legacy human render there drew every step, as human mode does."""
        for key in keys:
            make = self._makes_by_id.get(key)
            steps = (self._steps_of_make(make) if make is not None else None) or []
            if make is None or not steps or render_condition(self.facts, render, make, self._stepping_function(make, [render])):
                return False
            if not all(self._loop_renders(call, {id(render)}) for call in steps):
                return False
        return True
