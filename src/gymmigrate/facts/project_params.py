"""Per parameter of the run's defs, the kinds other modules pass
(``ProjectFacts.param_kinds``): a pass of ``ProjectFacts.join``.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable
from typing import TYPE_CHECKING

from gymmigrate.facts.kinds import EnvKind, agreed_kind, join_kinds
from gymmigrate.facts.module_summary import (
    HELD,
    KNOWN,
    MAX_CHAIN,
    NEW,
    OWN,
    PARAM,
    REF,
    TABLE,
    CallSummary,
    InitHeld,
    Kind,
    ModuleSummary,
    Signature,
)
from gymmigrate.facts.project_classes import imported_class

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts


class ParamJoin:
    """Per parameter, the kinds other modules pass (``ProjectFacts.param_kinds``).

    An argument that is itself a parameter of the calling def (``_test(env)`` passing
    ``env`` on to ``demo(env)``) has the kind every call of that def gives it, in the
    whole run: one memoized answer per parameter, so the join is linear in the calls;
    a cycle or a chain longer than ``MAX_CHAIN`` is unknown.
    """

    def __init__(self, facts: ProjectFacts, by_path: dict[str, ModuleSummary], calls_to: dict[tuple[str, str], list[tuple[str, CallSummary]]]) -> None:
        self.facts = facts
        self.by_path = by_path
        self.calls_to = calls_to
        self.memo: dict[tuple[str, str, str], EnvKind] = {}
        self.creator_memo: dict[tuple[str, str, str], EnvKind] = {}
        self.reach_memo: dict[tuple[str, str, str], EnvKind] = {}  # GYM_ENV where some call up the chain gives one
        self.depth = 0
        self.subclassed: set[tuple[str, str]] | None = None

    def run(self) -> None:
        external: dict[tuple[str, str, str], list[EnvKind]] = defaultdict(list)
        kept: dict[tuple[str, str, str], list[str | None]] = defaultdict(list)
        sources: dict[tuple[str, str, str], list[str | None]] = defaultdict(list)
        # calls that hand on their own parameter (or what their class holds from one)
        handers: dict[tuple[str, str, str], list[tuple[str, int, str]]] = defaultdict(list)
        for (path, qualname), calls in self.calls_to.items():
            signature = self.by_path[path].defs[qualname]
            outside = [call for caller, call in calls if caller != path]  # the file sees its own call sites itself
            for caller, call in calls:
                if caller == path:
                    continue
                thunks = dict(call.thunks)
                stacks = dict(call.thunk_stacks) if caller not in self.facts.blocked else {}
                items = dict(call.items)
                creators = dict(call.creators)
                positional = list(signature.params[1:] if signature.is_method else signature.params)
                for param, source in self._sources(positional, call):
                    sources[(path, qualname, param)].append(f"{caller}|{source}" if source is not None else None)
                for param, kind in self._passed(signature, call):
                    resolved = self._resolve(kind, caller)
                    # what calling each item of a list of thunks passed there returns (unknown
                    # for anything else), aligned with ``param_kinds``
                    index = positional.index(param)
                    slot = str(index) if index < len(call.args) else param
                    self.facts.thunk_kinds.setdefault((path, qualname, param), []).append(self._thunks_kind(thunks.get(slot), caller))
                    # what calling the class (or other creator) passed there gives
                    self.facts.creator_kinds.setdefault((path, qualname, param), []).append(self._creator_kind(creators.get(slot), caller))
                    self.facts.thunk_stacks.setdefault((path, qualname, param), []).append(self._thunks_stack(stacks.get(slot), caller))
                    item = items.get(slot)
                    self.facts.item_kinds.setdefault((path, qualname, param), []).append(EnvKind.UNKNOWN if item is None else self._resolve(item, caller))
                    external[(path, qualname, param)].append(resolved)
                    kept[(path, qualname, param)].append(self._kept_class(kind, caller))
                    key = (path, qualname, param)
                    if resolved is not EnvKind.GYM_ENV and isinstance(kind, str) and kind.startswith((HELD, PARAM)):
                        handers[key].append((caller, call.line, kind))
                    if resolved is EnvKind.GYM_ENV:
                        self.facts.gym_env_callers[key] = (*self.facts.gym_env_callers.get(key, ()), (caller, call.line))
                    elif not resolved.is_gym and resolved not in (EnvKind.NOT_ENV, EnvKind.UNKNOWN):
                        self.facts.other_env_callers[key] = (*self.facts.other_env_callers.get(key, ()), (caller, call.line))
            if outside and not signature.is_method:
                for param in signature.params:
                    self.facts.passed_ids[(path, qualname, param)] = tuple(self._id_passed(signature, call, param) for call in outside)
        self.facts.param_kinds = dict(external)
        for key, handed in handers.items():
            found = tuple((caller, line) for caller, line, kind in handed if self._reaches_gym_env(kind, caller))
            if found:
                self.facts.gym_env_handers[key] = found
        self.facts.param_sources = {key: tuple(found) for key, found in sources.items()}
        self.facts.kept_params = {key: tuple(names) for key, names in kept.items() if any(names)}

    def _thunks_kind(self, kind: Kind | None, caller: str) -> EnvKind:
        """What the items of a list of thunks a call passes return: the kind the caller found,
        or for ``ref:<qualified>`` (calls of a def it imports) what that def's thunks return
        (``ModuleSummary.thunk_factories``). Unknown for a module left as it is (its thunks
        keep the old API) and for anything else."""
        if kind is None or caller in self.facts.blocked:
            return EnvKind.UNKNOWN
        if isinstance(kind, EnvKind):
            return kind
        if not kind.startswith(REF):
            return EnvKind.UNKNOWN
        if kind.startswith(REF + OWN):
            # a def of the calling module whose thunks build classes of other modules
            # (``join_thunk_factory_refs`` gave it its kind)
            found = self.facts.thunk_factories.get(caller, {}).get(kind[len(REF + OWN) :])
            return found if found is not None else EnvKind.UNKNOWN
        found = self.facts.thunk_factory(kind[len(REF) :], caller)
        return found if found is not None else EnvKind.UNKNOWN

    def _creator_kind(self, kind: Kind | None, caller: str) -> EnvKind:
        """What calling a creator a call passes gives (``CallSummary.creators``): the kind the
        caller found; for a name of the run, what calling it gives (``call_kinds``); for a
        lookup in a closed table of the run, what calling through it gives (``table_kinds``);
        for a parameter of the calling def, what every call of that def passes there gives.
        Unknown for a module left as it is and for anything else."""
        if kind is None or caller in self.facts.blocked:
            return EnvKind.UNKNOWN
        if isinstance(kind, EnvKind):
            return kind
        view = self.facts.view(caller)
        if kind.startswith(REF):
            return view.call_kind(kind[len(REF) :]) or EnvKind.UNKNOWN
        if kind.startswith(TABLE):
            return view.table_kind(kind[len(TABLE) :], None) or EnvKind.UNKNOWN
        if kind.startswith(PARAM):
            qualname, _, param = kind[len(PARAM) :].rpartition(":")
            return self.creator_param_kind(caller, qualname, param)
        return EnvKind.UNKNOWN

    def creator_param_kind(self, path: str, qualname: str, param: str) -> EnvKind:
        """What calling the creator every call of the run passes to ``param`` of ``qualname``
        gives, where they all agree (``agreed_kind``); a cycle or a chain longer than
        ``MAX_CHAIN`` is unknown."""

        def agreed() -> EnvKind:
            signature = self.by_path[path].defs.get(qualname)
            calls = self.calls_to.get((path, qualname), ()) if signature is not None else ()
            kinds: list[EnvKind] = []
            for caller, call in calls:
                positional = list(signature.params[1:] if signature.is_method else signature.params)  # type: ignore[union-attr]
                creators = dict(call.creators)
                for passed, _ in self._passed(signature, call):  # type: ignore[arg-type]
                    if passed == param:
                        index = positional.index(param)
                        kinds.append(self._creator_kind(creators.get(str(index) if index < len(call.args) else param), caller))
            return agreed_kind(kinds)

        return self._chained(self.creator_memo, (path, qualname, param), agreed)

    def _chained(self, memo: dict[tuple[str, str, str], EnvKind], key: tuple[str, str, str], compute: Callable[[], EnvKind]) -> EnvKind:
        """The answer ``memo`` holds for ``key``, else ``compute()`` one link further down a
        chain of calls, remembered: unknown past ``MAX_CHAIN`` links, and unknown to a
        ``compute`` that meets ``key`` again (a cycle adds no evidence)."""
        known = memo.get(key)
        if known is not None:
            return known
        if self.depth >= MAX_CHAIN:
            return EnvKind.UNKNOWN
        memo[key] = EnvKind.UNKNOWN
        self.depth += 1
        try:
            result = memo[key] = compute()
        finally:
            self.depth -= 1
        return result

    def _thunks_stack(self, stack: str | None, caller: str) -> str | None:
        """The Gym-only stack the thunks a call passes make envs of: the caller's own answer,
        or for ``ref:<qualified>`` (every env made by one def it imports) that def's stack
        (``ModuleSummary.gym_only_makers``). None for anything else."""
        if stack is None or not stack.startswith(REF):
            return stack
        where = self.facts._split(stack[len(REF) :], caller)
        return None if where is None else self.facts.gym_only_makers.get(where[0], {}).get(where[1])

    def _kept_class(self, kind: Kind, caller: str) -> str | None:
        """The class whose step and reset the run keeps on their own contract (``legacy_steps``)
        that an argument of kind ``kind`` is an instance of, or None."""
        if isinstance(kind, EnvKind) or not kind.startswith(NEW) or "|" in kind:
            return None
        made = kind[len(NEW) :]
        where = (caller, made[len(OWN) :]) if made.startswith(OWN) else self.facts._split(made, caller)
        return where[1] if where is not None and where in self.facts.legacy_steps else None

    @staticmethod
    def _sources(positional: list[str], call: CallSummary) -> list[tuple[str, str | None]]:
        """(parameter, the variable ``call`` hands on there, or None) for every parameter."""
        given = dict(call.sources)
        keywords = {name for name, _ in call.keywords}
        found: list[tuple[str, str | None]] = []
        for index, param in enumerate(positional):
            slot = str(index) if index < len(call.args) else param if param in keywords else None
            found.append((param, given.get(slot) if slot is not None else None))
        return found

    @staticmethod
    def _id_passed(signature: Signature, call: CallSummary, param: str) -> str | None:
        """The env id ``call`` passes to ``param``: "" for none given (its default), None
        for an argument that is no id literal."""
        position = signature.params.index(param)
        ids = dict(call.ids)
        if position < len(call.args):
            return ids.get(str(position))
        if any(name == param for name, _ in call.keywords):
            return ids.get(param)
        return None if call.open_ended else ""

    def _subclassed(self) -> set[tuple[str, str]]:
        """The classes of the run that a class of another module derives from (computed once,
        the first time a held attribute asks)."""
        if self.subclassed is None:
            self.subclassed = {
                base
                for path, summary in self.by_path.items()
                for _name, bases, _methods in summary.subclasses
                for qualified in bases
                if (base := imported_class(self.facts, self.by_path, path, qualified)) is not None and base[0] != path
            }
        return self.subclassed

    def param_kind(self, path: str, qualname: str, param: str) -> EnvKind:
        """The kinds every call of the run passes to ``param`` of ``qualname``, joined
        (``join_kinds``); a cycle or a chain longer than ``MAX_CHAIN`` is unknown."""

        def joined() -> EnvKind:
            signature = self.by_path[path].defs.get(qualname)
            kinds: list[EnvKind] = []
            for caller, call in self.calls_to.get((path, qualname), ()) if signature is not None else ():
                kinds.extend(self._resolve(k, caller) for p, k in self._passed(signature, call) if p == param)  # type: ignore[arg-type]
            return join_kinds(kinds)

        return self._chained(self.memo, (path, qualname, param), joined)

    def _reaches_gym_env(self, kind: str, caller: str) -> bool:
        """``param:f:env`` or ``held:Agent.__init__:env`` that some call of the run, up the
        chain of defs handing it on, gives a Gym env, whatever the others give (their kinds
        joined may well be unknown): ``gym_env_handers``."""
        prefix = HELD if kind.startswith(HELD) else PARAM
        qualname, _, param = kind[len(prefix) :].rpartition(":")
        return self._gym_env_upstream(caller, qualname, param) is EnvKind.GYM_ENV

    def _gym_env_upstream(self, path: str, qualname: str, param: str) -> EnvKind:
        def reached() -> EnvKind:
            signature = self.by_path[path].defs.get(qualname)
            for caller, call in self.calls_to.get((path, qualname), ()) if signature is not None else ():
                for p, k in self._passed(signature, call):  # type: ignore[arg-type]
                    if p != param:
                        continue
                    if self._resolve(k, caller) is EnvKind.GYM_ENV:
                        return EnvKind.GYM_ENV
                    if isinstance(k, str) and k.startswith((HELD, PARAM)) and self._reaches_gym_env(k, caller):
                        return EnvKind.GYM_ENV
            return EnvKind.UNKNOWN

        return self._chained(self.reach_memo, (path, qualname, param), reached)

    def _resolve(self, kind: Kind, caller: str) -> EnvKind:
        if isinstance(kind, EnvKind):
            return kind
        if kind.startswith(NEW):
            # ``new:a.Env|b.Other``: a name bound to instances of several classes of the run,
            # and maybe to what the caller settled itself (``=GYM_ENV``)
            return join_kinds(
                EnvKind[made[len(KNOWN) :]] if made.startswith(KNOWN) else self.facts._class_kind(NEW + made, caller)
                for made in kind[len(NEW) :].split("|")
            )
        if kind.startswith(HELD):
            # ``self.test_env`` held from a constructor parameter: what every construction of
            # the class passes there, unless another module derives a class from it (its
            # instances are built with arguments no call of the class shows)
            qualname, _, param = kind[len(HELD) :].rpartition(":")
            if (caller, qualname.split(".", 1)[0]) in self._subclassed():
                return EnvKind.UNKNOWN
            return self.param_kind(caller, qualname, param)
        qualname, _, param = kind[len(PARAM) :].rpartition(":")
        return self.param_kind(caller, qualname, param)

    @staticmethod
    def _passed(signature: Signature, call: CallSummary) -> list[tuple[str, Kind]]:
        """(parameter, kind of what the call passes there) for every parameter."""
        params = list(signature.params[1:] if signature.is_method else signature.params)
        given = dict(call.keywords)
        found: list[tuple[str, Kind]] = []
        for index, param in enumerate(params):
            if index < len(call.args):
                found.append((param, call.args[index]))
            elif param in given:
                found.append((param, given[param]))
            elif call.open_ended or param not in signature.defaults:
                found.append((param, EnvKind.UNKNOWN))  # may be passed unseen, or the call would fail
        return found


def join_held(facts: ProjectFacts, by_path: dict[str, ModuleSummary], params: ParamJoin) -> None:
    """``held_kinds``: a holder's attribute is a Gym env when every construction of the
    run (its own module's included) passes one; a class subclassed in another module is
    built there too, through calls this join does not follow: left out."""
    for path, summary in by_path.items():
        if path in facts.blocked:
            continue
        for name, stored in summary.init_held.items():
            init = summary.defs.get(f"{name}.__init__")
            for attribute, (param, handed_on) in stored.items():
                if init is not None and param in init.params[1:]:
                    facts.init_held[(path, name, attribute)] = InitHeld(param, init.params.index(param) - 1, handed_on)
        for name, held in summary.held_params.items():
            init = summary.defs.get(f"{name}.__init__")
            if (path, name) in facts.subclasses_of:
                continue
            for attribute, param in held.items():
                if params.param_kind(path, f"{name}.__init__", param) is EnvKind.GYM_ENV:
                    facts.held_kinds[(path, name, attribute)] = EnvKind.GYM_ENV
                if init is not None and param in init.params[1:]:
                    facts.held_slots[(path, name, attribute)] = (param, init.params.index(param) - 1)  # no ``self``
