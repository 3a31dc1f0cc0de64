"""``x.seed(...)`` / ``x.render(mode)`` calls a module makes on receivers it cannot trace:
the join keeps the ``seed`` and ``render(mode)`` of the run's env classes that such a call
may reach (``ModuleSummary.untraced_seed_call``, ``untraced_render_call``,
``render_makers``, ``seed_makers``).
"""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.creation import CreationFinder
from gymmigrate.facts.decisions import Action, decide
from gymmigrate.facts.gym_use import handles_gym_envs
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import ModuleFacts, is_super_call, string_value
from gymmigrate.facts.profile import FileProfile
from gymmigrate.facts.render_modes import passes_mode
from gymmigrate.facts.summaries.calls import CallSummarizer


def calls_from_outside(facts: ModuleFacts, method: str) -> bool:
    """``x.<method>(...)`` or ``x._<method>(...)`` on a receiver other than ``self`` or
    ``super()``: a call no class decides with its own methods."""
    for name in (method, "_" + method):
        for call in facts.attribute_calls.get(name, ()):
            receiver = call.func.value  # type: ignore[attr-defined]
            if not (isinstance(receiver, ast.Name) and receiver.id == "self") and not is_super_call(receiver):
                return True
    return False


def passes_return_info(facts: ModuleFacts) -> bool:
    """``x.reset(return_info=...)`` choosing a mode (anything but ``True``, or a reset's own
    ``return_info`` handed on to an inner reset): a caller that may expect the bare
    observation a gym 0.22-0.25 reset gave without the flag."""
    for name in ("reset", "_reset"):
        for call in facts.attribute_calls.get(name, ()):
            for kw in call.keywords:
                if kw.arg != "return_info":
                    continue
                value = kw.value
                if isinstance(value, ast.Constant) and value.value is True:
                    continue
                if isinstance(value, ast.Name) and value.id == "return_info":
                    continue
                return True
    return False


def calls_seed(facts: ModuleFacts) -> bool:
    """``x.seed(...)`` or ``x._seed(...)`` on anything but a library module
    (``np.random.seed``) or a space: a call that may reach an env class's seed()."""
    for name in ("seed", "_seed"):
        for call in facts.attribute_calls.get(name, ()):
            receiver = call.func.value  # type: ignore[attr-defined]
            named = facts.qualified_names(receiver)
            if named and all(N.is_library(q) for q in named):
                continue
            if _names_a_space(receiver):
                continue
            return True
    return False


def calls_seed_without_a_value(facts: ModuleFacts) -> bool:
    """One of the calls ``calls_seed`` counts, on another object than ``self`` or
    ``super()``, passes no seed: ``x.seed()``, ``x.seed(None)`` or one whose seed cannot be
    read (``x.seed(*args)``, ``x.seed(**kw)``). A seed() reached only by calls that pass a
    value (an int, a computed seed) ran only on a given seed, as reset(seed=...) under
    ``if seed is not None:`` does. A class's own ``self.seed()`` calls are its decision's
    (they reach its own seed(), or a base's that keeps it for them)."""
    for name in ("seed", "_seed"):
        for call in facts.attribute_calls.get(name, ()):
            receiver = call.func.value  # type: ignore[attr-defined]
            if (isinstance(receiver, ast.Name) and receiver.id == "self") or is_super_call(receiver):
                continue
            named = facts.qualified_names(receiver)
            if (named and all(N.is_library(q) for q in named)) or _names_a_space(receiver):
                continue
            if not passes_a_value(call):
                return True
    return False


def passes_a_value(call: ast.Call) -> bool:
    """``x.seed(s)`` with one seed written out that is not ``None``."""
    if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
        return False
    argument = call.args[0] if call.args else next((k.value for k in call.keywords), None)
    return argument is not None and not (isinstance(argument, ast.Constant) and argument.value is None)


def _names_a_space(receiver: ast.expr) -> bool:
    """``env.action_space``, ``space``, ``spaces["x"]``: its seed() is Space.seed."""
    while isinstance(receiver, ast.Subscript):
        receiver = receiver.value
    name = receiver.attr if isinstance(receiver, ast.Attribute) else receiver.id if isinstance(receiver, ast.Name) else ""
    return name.lower().endswith(("space", "spaces"))


class UntracedCalls:
    """Asks of one module's seed and render calls, with the classes its call summaries
    resolve (``CallSummarizer.instance_class``)."""

    def __init__(self, calls: CallSummarizer) -> None:
        self.render_makers: set[str] = set()  # what made the receivers of render(mode) calls (run names)
        self.seed_makers: set[str] = set()  # what made the receivers of seed(s) calls, for the join
        self.calls = calls
        self.facts = calls.facts
        self.receivers = calls.receivers

    def has_untraced_call(self, method: str) -> bool:
        """``x.seed(...)`` / ``x.render(mode)`` on a receiver this module cannot trace."""
        if method == "seed" and self._seeds_through_wrapper_attr():
            return True
        for call in self.facts.attribute_calls.get(method, ()):
            receiver = call.func.value  # type: ignore[attr-defined]
            if isinstance(receiver, ast.Name) and receiver.id == "self":
                continue  # a class's own call: decided with that class
            if is_super_call(receiver):
                continue
            if method == "render" and not passes_mode(call, self.facts):
                continue  # a bare render() (the Gymnasium call), or a render method forwarding
            kind = self.receivers.kind_of(receiver)
            if method == "render" and kind is EnvKind.GYM_ENV and _keeps_mode(call):
                return True  # a Gym env the rendering rules leave passing its mode: any class's render
            if method == "render" and kind in (EnvKind.GYM_ENV, EnvKind.UNKNOWN):
                made_by = self.calls.instance_class(receiver)
                if made_by is not None and not N.is_library(made_by) and not self._made_here(receiver):
                    # ``env = pkg.make_board()``: the join tells a class of the run (its
                    # construction takes the mode, GM401) from a def, where no mode can move
                    self.render_makers.add(made_by)
                    continue
            if method == "seed" and kind is EnvKind.GYM_ENV and self._in_own_seed_method(call):
                # ``def seed(self, s): for env in self.envs: env.seed(s)`` of a plain class: the
                # seed rules leave it (or send it to ``env.unwrapped.seed``), so the env classes
                # it may build keep their seed()
                return True
            if kind is not EnvKind.UNKNOWN:
                continue
            if method == "seed" and self._seed_call_rewritten_here(call):
                continue  # GM203 makes it reset(seed=...) in this run: no seed() caller is left
            # the value that reaches the call, as GM203 sees it: counting a name's later
            # ``env = Monitor(env)`` kept a class's seed() that the same run's
            # reset(seed=...) rewrite left without a caller, and the next run removed it
            made_by = self.calls.reaching_instance_class(receiver) if method == "seed" else self.calls.instance_class(receiver)
            if made_by is not None and not N.is_library(made_by):
                continue  # an instance of a class it imports: the run knows that class
            if method == "seed" and (makers := self._seed_makers(call)) is not None:
                # ``A()`` in one branch, ``B()`` in another, both of the run: the join knows
                # whether GM203 rewrites the call (every one a Gym env), and only then is
                # it no caller
                self.seed_makers.add(makers)
                continue
            return True
        return False

    def _seeds_through_wrapper_attr(self) -> bool:
        """``x.get_wrapper_attr("seed")(s)`` (a migrated ``x.seed(s)``, GM203): it reaches the
        seed() of whichever class of the chain defines one, so the run's env classes keep
        theirs, on a second run as on the first."""
        for call in self.facts.attribute_calls.get("get_wrapper_attr", ()):
            if len(call.args) == 1 and string_value(call.args[0]) == "seed":
                parent = self.facts.parent(call)
                if isinstance(parent, ast.Call) and parent.func is call:
                    return True
        return False

    def _made_here(self, receiver: ast.AST) -> bool:
        """``receiver`` goes back to a ``make`` (or a construction of an env class of this
        module): where the rendering rules move a literal mode to (GM401)."""
        facts, receivers = self.facts, self.receivers

        def is_creation(call: ast.Call) -> bool:
            return receivers.local_class(call.func) is not None or any(
                N.strip_gym_prefix(q) in N.GYM_ENV_FACTORIES for q in facts.qualified_names(call.func)
            )

        finder = facts.memo(("summary-make-finder", 0), lambda: CreationFinder(facts, receivers, is_creation))
        return finder.find(receiver).found

    def _in_own_seed_method(self, call: ast.Call) -> bool:
        """``call`` sits in a ``seed()`` of a plain class (or a def): the project's own, not
        the Gym hook of an env or wrapper class."""
        function = self.facts.enclosing_function(call)
        if function is None or function.name != "seed":
            return False
        classdef = self.facts.enclosing_class(function)
        return classdef is None or not (
            self.receivers.class_kind(classdef) is EnvKind.GYM_ENV or self.receivers.is_gym_wrapper_class(classdef)
        )

    def _rewritable_seed_call(self, call: ast.Call) -> bool:
        """``env.seed(s)`` as a statement, with one seed, outside a ``seed()`` method: the
        shape GM203 makes ``reset(seed=s)`` wherever it knows the receiver for a Gym env."""
        if not isinstance(self.facts.parent(call), ast.Expr) or len(call.args) + len(call.keywords) != 1:
            return False
        if (call.args and isinstance(call.args[0], ast.Starred)) or (call.keywords and call.keywords[0].arg != "seed"):
            return False
        function = self.facts.enclosing_function(call)
        return function is None or function.name != "seed"

    def _seed_makers(self, call: ast.Call) -> str | None:
        """What made every value reaching the receiver of a rewritable ``env.seed(s)``,
        names of the run among them (``CallSummarizer.reaching_makers``). Counting such a
        call as untraced kept the seed() of the classes it builds in one run while GM203,
        knowing them for Gym envs through the join, rewrote it; the next run removed them."""
        receiver = call.func.value  # type: ignore[attr-defined]
        if not isinstance(receiver, ast.Name) or not self._rewritable_seed_call(call):
            return None
        return self.calls.reaching_makers(receiver)

    def _seed_call_rewritten_here(self, call: ast.Call) -> bool:
        """``env.seed(s)`` as a statement, with one seed, on an untraced receiver that GM203
        rewrites anyway (an env-like name in a file that uses only Gym). Counting it as a
        caller kept a class's seed() in one run and removed it in the next."""
        if not self._rewritable_seed_call(call):
            return False
        receiver = call.func.value  # type: ignore[attr-defined]
        profile = FileProfile.from_source(self.facts.text)
        if decide(EnvKind.UNKNOWN, receiver, profile).action is not Action.REWRITE_FOR_REVIEW:
            return False
        # the fallback needs a module that handles Gym envs, as GM203's ``decide`` asks
        # (``MadeObjects.handles_gym_envs``, which also counts the run's classes). (A
        # receiver annotated with a class not shown to be Gym's is reported there too, but
        # this summary knows no other module's classes; such a receiver holds no Gym env
        # class of the run, so whether it counts changes no env class's seed().)
        return handles_gym_envs(self.facts)


def _keeps_mode(call: ast.Call) -> bool:
    """A render call on a Gym env that the rendering rules report and leave passing its
    mode (GM401): a mode that is not a string literal, or other arguments beside it
    (``env.render(mode="rgb_array", tile_size=8)`` on an env class that takes them)."""
    mode = next((k.value for k in call.keywords if k.arg == "mode"), None)
    if mode is None and call.args:
        mode = call.args[0]
    others = len(call.args) + len(call.keywords) - 1
    return others > 0 or not (isinstance(mode, ast.Constant) and isinstance(mode.value, str))
