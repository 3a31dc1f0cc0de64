"""The registry API (GM802), ``EnvSpec``'s private attributes (GM806), and registrations
that turn the env checker off (GM807, GM808).

* GM802 gym 0.21's ``EnvRegistry`` object became the plain dict ``gym.registry``
  (``dict[str, EnvSpec]``) in gym 0.24/0.26: ``registry.env_specs`` is the registry
  itself, ``registry.all()`` is ``registry.values()``, and ``registry.spec()`` /
  ``make()`` / ``register()`` are the module functions ``gym.spec`` / ``gym.make`` /
  ``gym.register``. ``gym.envs.registry`` is spelled ``gym.registry``.
* GM806 ``EnvSpec._kwargs`` / ``_entry_point`` / ``_env_name`` became ``kwargs`` / ``entry_point`` / ``name`` (and gym 0.9's
  ``timestep_limit`` is ``max_episode_steps``; ``trials``, ``tags``... are gone and reported): rewritten where
  the object is an ``EnvSpec`` (``x.spec``, ``gym.spec(...)``, an item of the registry,
  a name only ever bound to one of those).
  The same keywords of gym 0.9's ``register(...)`` / ``EnvSpec(...)``: ``timestep_limit=N``
  (or ``tags`` holding only the time-limit tag) is ``max_episode_steps=N``; ``tags``, ``trials``
  and ``local_only`` are dropped where their value runs no code; the others are reported.
  ``timestep_limit=None`` (the default) is dropped. A call of a module function that hands
  its ``**kwargs`` unchanged to one ``register`` is decided as that ``register``.
* GM807 ``register(...)`` of a class of the run whose ``action_space`` or
  ``observation_space`` is an instance of a class of the run that certainly is not a
  ``Space`` (``class MultiAgentActionSpace(list)``, the multi-agent lists of spaces of
  gym-era packages): Gymnasium 1.x's ``make`` wraps every env in ``PassiveEnvChecker``,
  whose constructor raises TypeError on it, where gym <= 0.21 had no checker. The call gets
  ``disable_env_checker=True`` (ASSIST: a ``gymnasium.spaces.Tuple`` of the per-agent
  spaces would let the checker run). Only in a run of several files, which knows the class
  behind the ``entry_point`` string.
* GM808 ``register(...)`` of a class whose ``reset`` steps the wrapper that handed itself
  to it (``self._top.step(...)`` after ``env.unwrapped.set_top(self)``;
  facts/wrapper_steps.py), or of an entry point the call does not resolve but whose values
  in the module name a module or class of the run (facts/entry_sources.py), in a run with
  such a class: Gymnasium 1.x's checker, between those wrappers and the env, raises TypeError
  on that step inside its own reset. The call gets ``disable_env_checker=True`` (ASSIST); an
  entry point nothing ties to the run (read from a file, the command line) is reported once.
* GM810 ``register(...)`` with ``order_enforce=False`` and no step limit: gym 0.21's make
  returned the bare env for it (no checker, no OrderEnforcing, no TimeLimit), the env's own
  attributes and reset keywords in reach; Gymnasium 1.x's make wraps it in
  ``PassiveEnvChecker``, which forwards none of them. The call gets
  ``disable_env_checker=True``, so make returns what it made before. Through a helper that
  sets ``kwargs["order_enforce"]`` and hands ``**kwargs`` on, the keyword goes into a dict
  before them, computed from what the call passes (a caller's own choice wins).

Source: gym 0.21 ``envs/registration.py`` against Gymnasium 1.4 ``envs/registration.py``.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from gymmigrate.edits.arguments import append_keyword
from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.entry_sources import entry_from_run
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.module import full_name, keyword, own_returns, string_value
from gymmigrate.facts.summaries import plain_classes, space_calls
from gymmigrate.facts.wrapper_steps import reset_steps, self_handoffs, steps_its_wrapper
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.env_ids import registry_edits as E
from gymmigrate.rules.env_ids.catalog import is_atari_id
from gymmigrate.rules.env_ids.env_specs import is_env_spec
from gymmigrate.rules.env_ids.syntax import gym_alias, is_registry

if TYPE_CHECKING:
    from gymmigrate.facts.receivers import Receivers

RULES = (
    Rule("GM802", "registry API", FixKind.AUTO, "`registry.env_specs/all()/spec()/make()` become `gym.registry` and `gym.spec/make`."),
    Rule(
        "GM806",
        "EnvSpec attributes",
        FixKind.AUTO,
        "`spec._kwargs` / `spec._entry_point` / `spec._env_name` / `spec.timestep_limit` become `spec.kwargs` / "
        "`spec.entry_point` / `spec.name` / `spec.max_episode_steps`; removed ones (`trials`, `tags`...) are reported. "
        "gym 0.9's `register(timestep_limit=N)` (or a time-limit tag) becomes `max_episode_steps=N`, "
        "`timestep_limit=None` is dropped, also through a module function that hands its `**kwargs` to `register`; "
        "its `tags`, `trials` and `local_only` are dropped (reported where their value runs code), its other keywords reported.",
    ),
    Rule(
        "GM807",
        "spaces that are not Spaces",
        FixKind.ASSIST,
        "`register(...)` of an env whose spaces are the run's own non-`Space` classes (a `list` of spaces) gets `disable_env_checker=True`.",
    ),
    Rule(
        "GM808",
        "envs whose reset steps their wrappers",
        FixKind.ASSIST,
        "`register(...)` of an env whose reset steps the wrapper that handed itself to it (or of an entry point the module "
        "traces only to the run's own modules and classes, in a run with such an env) gets `disable_env_checker=True`.",
    ),
    Rule(
        "GM810",
        "registrations that made the bare env",
        FixKind.AUTO,
        "`register(...)` with `order_enforce=False` and no `max_episode_steps` (gym 0.21's make returned the bare env) "
        "gets `disable_env_checker=True`, also through a helper that sets `kwargs[\"order_enforce\"]`.",
    ),
)
_REGISTER_FUNCTIONS = frozenset({"register", "envs.register", "envs.registration.register"})

REGISTRY_METHODS = frozenset({"spec", "make", "register"})
SPEC_ATTRIBUTES = {"_kwargs": "kwargs", "_entry_point": "entry_point", "_env_name": "name", "timestep_limit": "max_episode_steps"}
# EnvSpec attributes of gym < 0.21 that Gymnasium's EnvSpec does not have (AttributeError).
REMOVED_SPEC_ATTRIBUTES = {
    "trials": "gym 0.9's number of trials for the reward threshold is gone: use your own count (e.g. 100)",
    "tags": "the spec's tags are gone (gym 0.9's `wrapper_config.TimeLimit.max_episode_steps` tag is `spec.max_episode_steps`)",
    "max_episode_seconds": "the time limit in seconds is gone: only `max_episode_steps` is kept",
    "local_only": "gone with the scoreboard: drop it",
}
_SPEC_CONSTRUCTORS = _REGISTER_FUNCTIONS | {"envs.registration.EnvSpec", "envs.EnvSpec", "EnvSpec"}
# gym 0.9's EnvSpec keywords that Gymnasium's register()/EnvSpec() do not take.
LEGACY_SPEC_KEYWORDS = frozenset({"timestep_limit", "tags", "trials", "max_episode_seconds", "local_only"})
# The legacy keywords a register call can lose without changing what make builds.
DROPPED_SPEC_KEYWORDS = frozenset({"tags", "trials", "local_only"})
_LEGACY_KEYWORD_HINTS = {
    "timestep_limit": "`timestep_limit` was gym 0.9's spelling of `max_episode_steps` and overrode it there: "
    "keep the one limit you mean as `max_episode_steps=`",
    "tags": "the tags are gone (a `wrapper_config.TimeLimit.max_episode_steps` tag is `max_episode_steps=`); "
    "drop them, after moving what the code reads of `spec.tags` elsewhere",
    "trials": "gym 0.9's number of trials for the reward threshold is gone: drop it",
    "max_episode_seconds": "the time limit in seconds is gone: drop it, or keep a step limit in `max_episode_steps=`",
    "local_only": "gone with the scoreboard: drop it",
}
# gym's entry points whose envs Gymnasium's ids make with another class, as the spec now
# names it: gym's Atari ids were ``gym.envs.atari:AtariEnv``; ale-py registers every
# Atari id (``ALE/Pong-v5``, ``PongNoFrameskip-v4``) with ``ale_py.env:AtariEnv``.
_MOVED_ENTRY_POINTS = {"gym.envs.atari:AtariEnv": "ale_py.env:AtariEnv"}


class RegistryApi(RuleFamily):
    RULES = RULES
    after = ("EnvIds",)

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        text = facts.text
        return "registry" in text or "entry_point" in text or "order_enforce" in text or any(
            word in text for word in (*SPEC_ATTRIBUTES, *REMOVED_SPEC_ATTRIBUTES)
        )

    def decide(self) -> None:
        self._gym_alias = gym_alias(self.facts)
        for attribute in self.facts.attributes.get("env_specs", ()):
            if is_registry(self.facts, attribute.value):
                self.report(attribute, "GM802", "`registry.env_specs` -> the registry itself: `gym.registry` is a plain dict of EnvSpec")
                self.plan.replace(attribute, self._current_registry_build(attribute.value, lambda node: node.value))
        for method in ("all", *sorted(REGISTRY_METHODS)):
            for call in self.facts.attribute_calls.get(method, ()):
                func = call.func
                if isinstance(func, ast.Attribute) and is_registry(self.facts, func.value):
                    self._decide_registry_call(call, method)
        limit_reads = self._time_limit_tag_reads()
        for private, public in SPEC_ATTRIBUTES.items():
            if not private.startswith("_") and not self.context.profile.imports_gym:
                if private == "timestep_limit":
                    self._decide_proven_timestep_limits(limit_reads)
                continue
            why = "the private attribute was made public" if private.startswith("_") else "gym 0.9's name for the same limit"
            for attribute in self.facts.attributes.get(private, ()):
                if is_env_spec(self.facts, attribute.value):
                    self.report(attribute, "GM806", f"`EnvSpec.{private}` -> `EnvSpec.{public}`: {why}")
                    self.plan.replace(attribute, lambda node, public=public: node.with_changes(attr=cst.Name(public)))
        for attribute in self.facts.attributes.get("entry_point", ()):
            if is_env_spec(self.facts, attribute.value):
                self._decide_entry_point_text(attribute)
        if self.context.profile.imports_gym:
            for removed, hint in REMOVED_SPEC_ATTRIBUTES.items():
                for attribute in self.facts.attributes.get(removed, ()):
                    if attribute in limit_reads:
                        continue  # the time-limit tag: decided with its read
                    if is_env_spec(self.facts, attribute.value):
                        self.report(
                            attribute, "GM806", f"`EnvSpec.{removed}` does not exist in Gymnasium (AttributeError): {hint}", FixKind.FLAG
                        )
        if self.context.profile.imports_gym:
            constructions = self._spec_constructions()
            for spec_call in constructions:
                self._decide_legacy_spec_keywords(spec_call)
            for outer, inner, certain in self._forwarded_spec_constructions(constructions):
                if certain:
                    self._decide_legacy_spec_keywords(outer, inner)
                elif legacy := list(dict.fromkeys(kw.arg for kw in outer.keywords if kw.arg in LEGACY_SPEC_KEYWORDS)):
                    names = ", ".join(f"`{arg}=`" for arg in legacy)
                    self.report(
                        outer,
                        "GM806",
                        f"{names} reaches Gymnasium's `register(...)` through `**` (TypeError where this runs), after the "
                        f"function reads or changes the keywords: {'; '.join(_LEGACY_KEYWORD_HINTS[arg] for arg in legacy)}",
                        FixKind.FLAG,
                    )
        calls = [*self.facts.calls_by_name.get("register", ()), *self.facts.attribute_calls.get("register", ())]
        for call in calls:
            if not any(N.strip_gym_prefix(q) in _REGISTER_FUNCTIONS for q in self.facts.qualified_names(call.func)):
                continue
            if self._decide_rootless_register(call):
                continue  # make rejects it whatever the checker does
            if _checker_chosen(call):
                continue  # set already
            if not self._decide_non_space_register(call) and not self._decide_wrapper_stepper(call):
                self._decide_bare_make(call)
        # ``from gym.envs.registration import register as gym_register`` (a helper of the run that
        # keeps the name ``register`` for itself): the call under another name is the same registration
        for alias, imported in self.facts.imports.items():
            local = alias.asname or alias.name
            if local != "register" and N.strip_gym_prefix(imported) in _REGISTER_FUNCTIONS:
                for call in self.facts.calls_by_name.get(local, ()):
                    if not _checker_chosen(call):
                        self._decide_bare_make(call)

    # -- GM806: gym 0.9's time-limit tag, read -------------------------------------------

    def _time_limit_tag_reads(self) -> dict[ast.Attribute, ast.expr]:
        """``spec.tags.get("wrapper_config.TimeLimit.max_episode_steps")`` and
        ``spec.tags["wrapper_config.TimeLimit.max_episode_steps"]``, each decided here: the
        ``tags`` attribute -> the whole read. The key is gym's own (gym 0.8 to 0.9 kept the
        limit under it on every ``EnvSpec``), so it proves the spec even in a module that
        never imports gym (the env comes from another module); ``spec.max_episode_steps``
        holds the same value on every gym since 0.8 and on Gymnasium (None where unset, as
        ``get`` gave)."""
        reads: dict[ast.Attribute, ast.expr] = {}
        for attribute in self.facts.attributes.get("tags", ()):
            read = self._time_limit_read(attribute)
            if read is None:
                continue
            proven = self.context.profile.imports_gym and is_env_spec(self.facts, attribute.value)
            if not (proven or (isinstance(attribute.value, ast.Attribute) and attribute.value.attr == "spec")):
                continue
            reads[attribute] = read
            stripped = self._stripped_env(attribute.value)
            if stripped is not None:
                self.report(
                    read,
                    "GM806",
                    "`EnvSpec.tags` does not exist in Gymnasium (AttributeError): gym 0.9's time-limit tag is the "
                    f"registered `max_episode_steps`, but `{stripped}` is the env under make's TimeLimit, whose spec "
                    "has no limit in Gymnasium (`spec.max_episode_steps` is None there): read it from the registry, "
                    "`gym.spec(<the id made>).max_episode_steps`, or from the env make returned",
                    FixKind.FLAG,
                )
                continue
            if self._names_atari_ids():
                # ale-py registers no step limit: the name is the same, the value is not
                self.report(
                    read,
                    "GM806",
                    "gym 0.9's time-limit tag of `EnvSpec.tags` -> `EnvSpec.max_episode_steps`, but the run makes Atari ids, "
                    "which ale-py registers with no step limit: this reads None for them (a comparison with it raises "
                    "TypeError) where gym gave a limit; pass `max_episode_steps=` where the env is made, or a default here",
                    FixKind.ASSIST,
                )
            else:
                self.report(read, "GM806", "gym 0.9's time-limit tag of `EnvSpec.tags` -> `EnvSpec.max_episode_steps`: the same limit")
            self.plan.replace(read, E.spec_max_episode_steps)
        return reads

    def _names_atari_ids(self) -> bool:
        """An Atari id among the run's ids (the module's alone, processed by itself)."""
        project = self.context.options.project
        ids = project.named_ids if project is not None else {node.value for node in self.facts.strings if isinstance(node.value, str)}
        return any(is_atari_id(env_id) for env_id in ids)

    def _time_limit_read(self, attribute: ast.Attribute) -> ast.expr | None:
        """The read of the time-limit tag that ``attribute`` (a ``.tags``) starts, if it is one."""
        if not isinstance(attribute.ctx, ast.Load):
            return None
        parent = self.facts.parent(attribute)
        if isinstance(parent, ast.Subscript) and parent.value is attribute and isinstance(parent.ctx, ast.Load):
            return parent if string_value(parent.slice) == E.TIME_LIMIT_TAG else None
        call = self.facts.parent(parent) if isinstance(parent, ast.Attribute) else None
        if (
            isinstance(parent, ast.Attribute)
            and parent.attr == "get"
            and isinstance(call, ast.Call)
            and call.func is parent
            and len(call.args) == 1
            and not call.keywords
            and string_value(call.args[0]) == E.TIME_LIMIT_TAG
        ):
            return call  # a default would stand for None: ``get(key, 100)`` is not this
        return None

    def _stripped_env(self, spec: ast.expr) -> str | None:
        """``env`` in ``env.spec`` where ``env`` is the env under make's wrappers
        (``env.env``, ``env.unwrapped``, or a name every value reaching the read was so
        assigned): the spec there is the inner env's. Its text, or None."""
        if not isinstance(spec, ast.Attribute):
            return None
        owner = spec.value
        if isinstance(owner, ast.Attribute) and owner.attr in ("env", "unwrapped"):
            return self.facts.segment(owner)
        if not isinstance(owner, ast.Name):
            return None
        reaching = Flow.of(self.facts).reaching(owner)
        if not reaching:
            return None
        for binding in reaching:
            assign = self.facts.parent(binding)
            if not (
                isinstance(assign, ast.Assign)
                and isinstance(assign.value, ast.Attribute)
                and assign.value.attr in ("env", "unwrapped")
            ):
                return None
        return owner.id

    def _decide_proven_timestep_limits(self, limit_reads: dict[ast.Attribute, ast.expr]) -> None:
        """``env.spec.timestep_limit`` in a module that never imports gym, where the same
        function reads gym's time-limit tag from the same spec (``env.spec``): the tag proves
        that spec is gym's, and ``timestep_limit`` was gym 0.9's name for ``max_episode_steps``."""
        proven = {
            (id(self.facts.enclosing_function(tags)), self.facts.segment(tags.value))
            for tags, read in limit_reads.items()
            if self._stripped_env(tags.value) is None
        }
        for attribute in self.facts.attributes.get("timestep_limit", ()):
            key = (id(self.facts.enclosing_function(attribute)), self.facts.segment(attribute.value))
            if key in proven and isinstance(attribute.ctx, ast.Load):
                self.report(attribute, "GM806", "`EnvSpec.timestep_limit` -> `EnvSpec.max_episode_steps`: gym 0.9's name for the same limit")
                self.plan.replace(attribute, lambda node: node.with_changes(attr=cst.Name("max_episode_steps")))

    # -- GM806: gym 0.9's register()/EnvSpec() keywords ------------------------------------

    def _spec_constructions(self) -> list[ast.Call]:
        """The calls that build an ``EnvSpec``: ``register(...)`` (any spelling under gym,
        ``registry.register(...)`` included) and ``EnvSpec(...)``."""
        found: list[ast.Call] = []
        for name in ("register", "EnvSpec"):
            for call in (*self.facts.calls_by_name.get(name, ()), *self.facts.attribute_calls.get(name, ())):
                func = call.func
                if any(N.strip_gym_prefix(q) in _SPEC_CONSTRUCTORS for q in self.facts.qualified_names(func)) or (
                    name == "register" and isinstance(func, ast.Attribute) and is_registry(self.facts, func.value)
                ):
                    found.append(call)
        return found

    def _forwarded_spec_constructions(self, constructions: list[ast.Call]) -> list[tuple[ast.Call, ast.Call, bool]]:
        """Calls of a module function whose ``**kwargs`` only ever reach one spec construction
        as ``**kwargs`` (``def register(id, **kw): ... gym.register(id, **kw)``): each keyword
        such a call passes lands in that construction unchanged, so it is decided as if written
        there (the construction's own keywords count as given). Where the function also reads the
        mapping (``kw.pop``, ``kw["x"] = ...``), what reaches the construction is not the call's to
        say: not certain. Each triple is (call, construction, certain)."""
        found: list[tuple[ast.Call, ast.Call, bool]] = []
        for name, function in self.facts.functions.items():
            rest = function.args.kwarg
            named = {arg.arg for arg in (*function.args.posonlyargs, *function.args.args, *function.args.kwonlyargs)}
            if rest is None or named & (LEGACY_SPEC_KEYWORDS | {"max_episode_steps"}):
                continue  # a keyword the function names itself never reaches the construction
            reads = [
                node for node in ast.walk(function) if isinstance(node, ast.Name) and node.id == rest.arg
            ]
            spread = [
                call
                for call in constructions
                if self.facts.enclosing_function(call) is function
                and any(kw.arg is None and isinstance(kw.value, ast.Name) and kw.value.id == rest.arg for kw in call.keywords)
            ]
            if len(spread) != 1:
                continue
            # every read of the mapping is that one ``**`` spread: nothing reads, pops or adds a key
            certain = len(reads) == 1 and any(kw.value is reads[0] for kw in spread[0].keywords)
            for call in self.facts.calls_by_name.get(name, ()):
                bindings = self.facts.bindings_of(call.func) if isinstance(call.func, ast.Name) else []
                if bindings == [function] and self.facts.enclosing_function(call) is not function:
                    found.append((call, spread[0], certain))
        return found

    def _decide_legacy_spec_keywords(self, call: ast.Call, forwarded_to: ast.Call | None = None) -> None:
        """gym <= 0.9's ``timestep_limit=N`` and ``tags={"wrapper_config.TimeLimit.max_episode_steps": N}``
        were the spellings of ``max_episode_steps=N``; Gymnasium's ``register``/``EnvSpec`` take
        neither (TypeError where the module is imported), so the limit moves to
        ``max_episode_steps=`` where nothing else sets it. ``tags`` with other keys,
        ``trials`` and ``local_only`` are dropped (below); what is left (``max_episode_seconds``,
        a second limit, a value that runs code, a call with ``**kwargs``) is reported, one item
        per call."""
        legacy = [kw for kw in call.keywords if kw.arg in LEGACY_SPEC_KEYWORDS]
        if not legacy:
            return
        # ``timestep_limit=None`` set no limit on any gym (None was its default, and only a
        # value overrode ``max_episode_steps``): dropping it is exact, whatever else is given.
        unset = [kw for kw in legacy if kw.arg == "timestep_limit" and isinstance(kw.value, ast.Constant) and kw.value.value is None]
        legacy = [kw for kw in legacy if kw not in unset]
        given = {kw.arg for kw in call.keywords}
        # ``**kwargs`` may set the limit too, and positional arguments past the entry point
        # meant other parameters in gym 0.9: then the limit's spelling is not the call's to settle.
        open_call = None in given or len(call.args) > 2 or any(isinstance(arg, ast.Starred) for arg in call.args)
        if forwarded_to is not None:
            # the keywords land in the construction: what it gives itself is given too, and its
            # positional arguments are the function's, not this call's
            given |= {kw.arg for kw in forwarded_to.keywords if kw.arg is not None}
            open_call = None in {kw.arg for kw in call.keywords} or any(isinstance(arg, ast.Starred) for arg in call.args)
            open_call = open_call or len(forwarded_to.args) > 2 or any(isinstance(arg, ast.Starred) for arg in forwarded_to.args)
        what = "`register(...)`" if E.called_name(forwarded_to or call) == "register" else "`EnvSpec(...)`"
        if unset:
            self.plan.replace(call, lambda node: E.without_keywords(node, ("timestep_limit",)))
            self.report(
                call,
                "GM806",
                f"`timestep_limit=None` dropped: None set no limit in gym (its default); Gymnasium's {what} takes "
                "no such keyword (TypeError)",
            )
        limits = [kw for kw in legacy if kw.arg == "timestep_limit" or E.limit_tag(kw) is not None]
        renamed = limits[0] if len(limits) == 1 and "max_episode_steps" not in given and not open_call else None
        rest = [kw for kw in legacy if kw is not renamed]
        if renamed is not None:
            spelled = "`timestep_limit=`" if renamed.arg == "timestep_limit" else "the `wrapper_config.TimeLimit.max_episode_steps` tag"
            # the edit and its finding sit on the call: the keyword itself is no node an edit can replace
            self.plan.replace(call, lambda node, keyword=renamed.arg: E.limit_as_max_episode_steps(node, keyword))
            self.report(
                call,
                "GM806",
                f"{spelled} -> `max_episode_steps=`: gym 0.9's spelling of the same step limit; Gymnasium's {what} "
                "takes no such keyword (TypeError)",
            )
        # Keywords whose value nothing in Gymnasium has a place for and that change nothing a
        # made env does (the scoreboard's ``trials``/``local_only``, ``tags`` other than the
        # limit's): kept, the register call raises TypeError; dropped, what is lost was never
        # read through Gymnasium (a ``spec.tags`` read fails either way and is reported apart).
        dropped = [
            kw.arg
            for kw in rest
            if kw.arg in DROPPED_SPEC_KEYWORDS and not open_call and not any(isinstance(n, ast.Call) for n in ast.walk(kw.value))
        ]  # a value that calls something runs code: what it does is not the keyword's to drop
        if dropped:
            self.plan.replace(call, lambda node, names=tuple(dropped): E.without_keywords(node, names))
            names = ", ".join(f"`{arg}=`" for arg in dict.fromkeys(dropped))
            self.report(
                call,
                "GM806",
                f"{names} dropped: Gymnasium's {what} takes no such keyword (TypeError) and keeps nothing of it "
                "(`env.spec` has no tags, trials or local_only)",
            )
            rest = [kw for kw in rest if kw.arg not in dropped]
        if rest:
            arguments = list(dict.fromkeys(kw.arg for kw in rest if kw.arg is not None))
            names = ", ".join(f"`{arg}=`" for arg in arguments)
            hints = "; ".join(_LEGACY_KEYWORD_HINTS[arg] for arg in arguments)
            self.report(
                call,
                "GM806",
                f"Gymnasium's {what} takes no {names} (TypeError where this runs): {hints}",
                FixKind.FLAG,
            )

    # -- GM807 -------------------------------------------------------------------------------

    def _decide_non_space_register(self, call: ast.Call) -> bool:
        if any(kw.arg is None for kw in call.keywords):
            return False  # maybe in ``**kwargs``
        entry = keyword(call, "entry_point")
        value = entry.value if entry is not None else (call.args[1] if len(call.args) > 1 else None)
        found = self._non_space_entry(value)
        if found is None:
            return False
        name, attribute, space, base = found
        self.report(
            call,
            "GM807",
            f"`{name}.{attribute}` is an instance of `{space}`, a `{base}` subclass, not a `gymnasium.spaces.Space`: the env checker "
            "that Gymnasium 1.x's make runs raises TypeError on it; registered with `disable_env_checker=True` "
            "(a `gymnasium.spaces.Tuple` of the per-agent spaces would let the checker run)",
        )
        self.plan.replace(call, lambda node: append_keyword(node, "disable_env_checker", cst.Name("True")))
        return True

    # -- GM808 -------------------------------------------------------------------------------

    def _decide_wrapper_stepper(self, call: ast.Call) -> bool:
        """``register(...)`` of a class whose reset steps the wrapper around it, or of an
        entry point the run cannot resolve (``register(id=id, **kwargs)`` in a helper, an
        entry point from a loop) in a run that has such a class: ``disable_env_checker=True``.
        Where ``**kwargs`` may carry the keyword too, it goes into a dict before them (a
        caller's own choice wins; a second keyword would be a TypeError)."""
        if any(isinstance(arg, ast.Starred) for arg in call.args):
            return False  # positional arguments the call does not show may reach the parameter
        starred = [kw for kw in call.keywords if kw.arg is None]
        if len(starred) > 1:
            return False
        entry = keyword(call, "entry_point")
        value = entry.value if entry is not None else (call.args[1] if len(call.args) > 1 else None)
        if value is None and not starred:
            return False  # no entry point: not a registration Gymnasium makes
        found = self._stepping_entry(value)
        if found is None:
            return False
        stepper, named = found
        if named is None and not self._entry_from_run(call, value):
            # nothing the module shows ties this entry point to the run: the checker stays on
            self.report(
                call,
                "GM808",
                f"this registers an entry point the run cannot resolve here; if it names `{stepper}` (or a subclass), "
                "whose reset steps an attribute that the run's wrappers set to themselves, Gymnasium 1.x's env checker "
                "raises TypeError inside that reset: then register it with `disable_env_checker=True`",
                FixKind.FLAG,
                question=("GM808 unresolved", stepper),
            )
            return True
        if named == stepper:
            what = f"`{stepper}`"
        elif named is not None:
            what = f"`{named}`, a subclass of `{stepper}` (its reset is that class's, or may call it)"
        else:
            what = f"an entry point the run cannot resolve here, which may name `{stepper}` or a subclass"
        self.report(
            call,
            "GM808",
            f"this registers {what}: `{stepper}`'s reset steps an attribute that the run's wrappers set to themselves "
            "(the outermost wrapper), so with `gymnasium.make` the env checker between those wrappers and the env sees a step "
            "before its own reset has returned, and Gymnasium 1.x's checker raises TypeError there (gym 0.24's passed it); "
            "registered with `disable_env_checker=True`, which loses only the checker's warnings",
            question=("GM808", stepper),
        )
        if starred:
            self.plan.replace(starred[0].value, E.checker_off_before)
        else:
            self.plan.replace(call, lambda node: append_keyword(node, "disable_env_checker", cst.Name("True")))
        return True

    # -- GM810 -------------------------------------------------------------------------------

    def _decide_bare_make(self, call: ast.Call) -> None:
        """``register(..., order_enforce=False)`` with no step limit: gym 0.21's make returned
        the env itself for it (no checker before 0.24, OrderEnforcing and TimeLimit turned off),
        Gymnasium 1.x's wraps it in PassiveEnvChecker, which forwards neither attributes nor
        reset keywords: ``disable_env_checker=True`` makes what legacy made. A ``**kwargs``
        of the enclosing def that the def gives ``kwargs["order_enforce"] = ...`` is decided at
        run time, from what the call then passes: a dict before them (a caller's own choice wins)."""
        if not self.context.profile.imports_gym:
            return  # written for Gymnasium: its make's checker is what the author chose
        if any(isinstance(arg, ast.Starred) for arg in call.args) or len(call.args) > 2:
            return  # positional arguments the call does not show (or gym 0.21's own order) may set the keywords
        starred = [kw for kw in call.keywords if kw.arg is None]
        if len(starred) > 1:
            return
        limit = keyword(call, "max_episode_steps")
        if limit is not None and not (isinstance(limit.value, ast.Constant) and limit.value.value is None):
            return  # made under TimeLimit on gym 0.21 too
        order = keyword(call, "order_enforce")
        if order is not None:
            if not (isinstance(order.value, ast.Constant) and order.value.value is False):
                return  # OrderEnforcing (or a choice the call does not show): today's behaviour stays
            set_order = False
        elif starred and self._sets_order_enforce(call, starred[0].value):
            set_order = True
        else:
            return  # gym 0.21 wrapped it in OrderEnforcing (order_enforce=True by default)
        if not starred:
            self.report(
                call,
                "GM810",
                "`order_enforce=False` and no step limit: gym 0.21's make returned the env itself for this id, Gymnasium 1.x's "
                "wraps it in the env checker, which forwards none of the env's own attributes or reset keywords; registered "
                "with `disable_env_checker=True`, so make returns the bare env as before",
            )
            self.plan.replace(call, lambda node: append_keyword(node, "disable_env_checker", cst.Name("True")))
            return
        held = starred[0].value
        if not isinstance(held, ast.Name):
            return  # the dict's test reads the keywords by a plain name
        self.report(
            call,
            "GM810",
            f"`{held.id}` may hold `order_enforce=False` and no step limit: gym 0.21's make returned the env itself for "
            "such an id, Gymnasium 1.x's wraps it in the env checker, which forwards none of the env's own attributes or "
            "reset keywords; the checker is turned off for exactly those registrations, so make returns the bare env as before",
        )
        self.plan.replace(held, lambda node: E.checker_off_when_bare(node, set_order))

    def _sets_order_enforce(self, call: ast.Call, held: ast.expr) -> bool:
        """``held`` is the enclosing def's own ``**kwargs``, and the def stores
        ``kwargs["order_enforce"] = <not a literal True>`` in it."""
        function = self.facts.enclosing_function(call)
        if function is None or not isinstance(held, ast.Name) or function.args.kwarg is None or function.args.kwarg.arg != held.id:
            return False
        for node in ast.walk(function):
            if isinstance(node, ast.Assign) and len(node.targets) == 1:
                target = node.targets[0]
                if (
                    isinstance(target, ast.Subscript)
                    and isinstance(target.value, ast.Name)
                    and target.value.id == held.id
                    and string_value(target.slice) == "order_enforce"
                ):
                    return not (isinstance(node.value, ast.Constant) and node.value.value is True)
        return False

    def _entry_from_run(self, call: ast.Call, value: ast.expr | None) -> bool:
        """The entry point the call does not resolve is still shown to be the run's (a string
        naming a module of the run, a class of the run flows into it: facts/entry_sources.py)."""
        project = self.receivers.project

        def names_run_module(module: str) -> bool:
            return module in ("", "__main__") or (project is not None and module in project.facts.modules)

        def is_run_class(name: ast.Name) -> bool:
            if self.receivers.local_class(name) is not None:
                return True
            qualified = self.facts.qualified_names(name)
            return any(names_run_module(q.rpartition(".")[0]) for q in qualified if "." in q) and project is not None

        return entry_from_run(self.facts, call, value, names_run_module, is_run_class)

    def _stepping_entry(self, value: ast.expr | None) -> tuple[str, str | None] | None:
        """(the class whose reset steps its wrapper, the class the entry point names: None
        where the run cannot tell) for an entry point the run resolves to such a class, or one it
        cannot resolve in a run that has such a class; None otherwise."""
        project = self.receivers.project
        local = self.facts.memo(("wrapper-steppers", 0), lambda: _local_wrapper_steppers(self.facts, self.receivers))
        target = string_value(value)
        if target is not None and target.count(":") == 1:
            module, _, name = target.partition(":")
        elif isinstance(value, ast.Name) and (classdef := self.receivers.local_class(value)) is not None:
            module, name = "", classdef.name
        elif isinstance(value, ast.Name) and (qualified := self.facts.qualified_names(value)):
            imported = project.wrapper_stepper_of(min(qualified)) if project is not None and len(qualified) == 1 else None
            return None if imported is None else (imported, value.id)  # else a class of another library
        elif target is not None or isinstance(value, (ast.Lambda, ast.Attribute)):
            return None  # ``"pkg.mod.Class"``, a callable of another library...
        else:
            anything = project.any_wrapper_stepper() if project is not None else min(local.values(), default=None)
            return None if anything is None else (anything, None)
        here = module in ("", "__main__") or (project is not None and project.facts.modules.get(module) == project.path)
        if project is not None:
            stepper = project.wrapper_stepper(module, name) if not here else project.wrapper_stepper_here(name)
        else:
            stepper = local.get(name) if here else None
        return None if stepper is None else (stepper, name)

    def _decide_entry_point_text(self, attribute: ast.Attribute) -> None:
        """``"gym.envs" in spec.entry_point`` / ``spec.entry_point.startswith(...)``: Gymnasium
        registers some ids with a callable entry point, on which a string test raises
        TypeError; the test is guarded with ``isinstance(..., str)``, and gym's own package
        name in it becomes gymnasium's."""
        parent = self.facts.parent(attribute)
        if isinstance(parent, ast.Compare) and len(parent.ops) == 1 and isinstance(parent.ops[0], (ast.Eq, ast.NotEq)):
            self._decide_entry_point_equality(parent, attribute)
            return
        if isinstance(parent, ast.Compare) and len(parent.ops) == 1 and isinstance(parent.ops[0], (ast.In, ast.NotIn)) and parent.comparators[0] is attribute:
            test: ast.expr = parent
            literal: ast.expr | None = parent.left
        elif (
            isinstance(parent, ast.Attribute)
            and parent.attr in ("startswith", "endswith")
            and isinstance(call := self.facts.parent(parent), ast.Call)
            and call.func is parent
        ):
            test = call
            literal = call.args[0] if call.args else None
        else:
            return
        if self._guarded(test):
            return
        spec = self.facts.segment(attribute.value)
        renamed = isinstance(literal, ast.Constant) and isinstance(literal.value, str) and literal.value.startswith("gym.envs")
        self.report(
            test,
            "GM806",
            "`EnvSpec.entry_point` may be a callable in Gymnasium 1.x (a string test on it raises TypeError): "
            "guarded with `isinstance(..., str)`" + ("; gym's `gym.envs` is `gymnasium.envs` there" if renamed else ""),
            FixKind.ASSIST,
        )

        def build(node: cst.BaseExpression, spec: str = spec, renamed: bool = renamed) -> cst.BaseExpression:
            if renamed:
                node = E.renamed_gym_envs(node)
            guarded = cst.parse_expression(f"isinstance({spec}.entry_point, str) and x")
            assert isinstance(guarded, cst.BooleanOperation)
            return guarded.with_changes(right=node)

        self.plan.replace(test, build)

    def _decide_entry_point_equality(self, compare: ast.Compare, attribute: ast.Attribute) -> None:
        """``spec.entry_point == "gym.envs.atari:AtariEnv"``: that string names a gym module;
        the spec of the same id names ale-py's class now, so the test would always be False.
        The literal becomes the entry point Gymnasium's spec holds (an equality test on a
        callable entry point is False, not an error: no guard)."""
        other = compare.comparators[0] if compare.left is attribute else compare.left
        value = string_value(other)
        moved = _MOVED_ENTRY_POINTS.get(value) if value is not None else None
        if moved is None:
            return
        self.report(
            other,
            "GM806",
            f'"{value}" -> "{moved}": the spec of a Gymnasium id names the class that makes its env, and gym\'s '
            "Atari envs are ale-py's now",
        )
        self.plan.replace(other, lambda node, moved=moved: E.with_string(node, moved))

    def _guarded(self, test: ast.expr) -> bool:
        """The test already follows ``isinstance(<...>.entry_point, str) and``."""
        parent = self.facts.parent(test)
        if not (isinstance(parent, ast.BoolOp) and isinstance(parent.op, ast.And)):
            return False
        before = parent.values[: parent.values.index(test)]
        return any(
            isinstance(value, ast.Call)
            and isinstance(value.func, ast.Name)
            and value.func.id == "isinstance"
            and len(value.args) == 2
            and isinstance(value.args[0], ast.Attribute)
            and value.args[0].attr == "entry_point"
            for value in before
        )

    def _decide_rootless_register(self, call: ast.Call) -> bool:
        """``register(entry_point="pkg.hop:Hop")`` of a class of the run none of whose bases,
        at any depth, is a library's: built on a copy of another gym's ``Env`` (a plain
        class), it is no gymnasium.Env, and ``gymnasium.make`` raises TypeError before its
        env checker runs. Reported: ``disable_env_checker`` would claim a fix that is none."""
        entry = keyword(call, "entry_point")
        value = entry.value if entry is not None else (call.args[1] if len(call.args) > 1 else None)
        target = string_value(value)
        project = self.receivers.project
        if project is None:
            return False
        factory = self._rootless_factory(value, target)
        if factory is not None:
            function, returned, (base, module) = factory
            self.report(
                call,
                "GM807",
                f"`{function}` returns a `{returned}`, which derives from no gymnasium.Env: its bases end in `{base}` "
                f"of `{module}`, a plain class of the run, so gymnasium.make raises TypeError (the environment must "
                "inherit from gymnasium.Env) before any env checker runs; make the class a gymnasium.Env (a "
                "gymnasium.Wrapper around the env it holds), or build it without make",
                FixKind.FLAG,
            )
            return True
        if target is None or target.count(":") != 1:
            return False
        module, _, name = target.partition(":")
        root = project.rootless_env(module, name)
        if root is None:
            return False
        self.report(
            call,
            "GM807",
            f"`{name}` derives from no gymnasium.Env: its bases end in `{root[0]}` of `{root[1]}`, a plain class of the run "
            "(a copy of another gym's Env), so gymnasium.make raises TypeError (the environment must inherit from "
            "gymnasium.Env) before any env checker runs, and disable_env_checker does not help; port the class onto "
            "gymnasium.Env and gymnasium.spaces, or build it without make",
            FixKind.FLAG,
        )
        return True

    def _rootless_factory(self, value: ast.expr | None, target: str | None) -> tuple[str, str, tuple[str, str]] | None:
        """(def, class, its plain root) where the entry point is a def of this module
        (``entry_point=flat_board``, or a string naming it here) whose every return is an
        instance of one class of the run none of whose bases is a library's: what ``make``
        builds is that object, which is no gymnasium.Env."""
        project = self.receivers.project
        assert project is not None
        function = self.receivers.local_function(value) if isinstance(value, ast.Name) else None
        if function is None and target is not None and target.count(":") == 1:
            module, _, name = target.partition(":")
            if project.facts.modules.get(module) == project.path:
                function = self.facts.functions.get(name)
        if function is None:
            return None
        returns = own_returns(function)
        classes: set[str] = set()
        for returned in returns:
            for made in self._returned_values(returned.value):
                if not isinstance(made, ast.Call):
                    return None
                local = self.receivers.local_class(made.func)
                qualified = [local.name] if local is not None else [q for q in self.facts.qualified_names(made.func) if not N.is_library(q)]
                if len(qualified) != 1:
                    return None
                classes.add(qualified[0])
        if len(classes) != 1:
            return None
        returned_class = classes.pop()
        root = project.rootless_class(returned_class)
        return None if root is None else (function.name, returned_class.rsplit(".", 1)[-1], root)

    def _returned_values(self, value: ast.expr | None) -> list[ast.expr | None]:
        """What a return hands back: the value, or for a name the values of the assignments
        that reach it (``env = Flatten(env)`` then ``return env``); ``[None]`` where that is not shown."""
        if not isinstance(value, ast.Name):
            return [value]
        reaching = Flow.of(self.facts).reaching(value)
        if not reaching:
            return [None]
        values: list[ast.expr | None] = []
        for binding in reaching:
            statement = self.facts.parent(binding)
            values.append(statement.value if isinstance(statement, ast.Assign) and statement.targets == [binding] else None)
        return values

    def _non_space_entry(self, value: ast.expr | None) -> tuple[str, str, str, str] | None:
        """(class, space attribute, space class, its bases) when the entry point names a
        class whose space is an instance of a class that certainly is not a ``Space``: a
        class of this file (``entry_point=Relay``, ``"__main__:Relay"``, ``"<this module>:Relay"``)
        or, in a run of several files, of the run."""
        target = string_value(value)
        if isinstance(value, ast.Name):
            module, name = "", value.id
        elif target is not None and target.count(":") == 1:
            module, _, name = target.partition(":")
        else:
            return None
        project = self.receivers.project
        here = module in ("", "__main__") or (project is not None and project.facts.modules.get(module) == project.path)
        if here:
            classdef = self.facts.classes.get(name)
            if classdef is None or (isinstance(value, ast.Name) and self.receivers.local_class(value) is not classdef):
                return None
            plain = self.facts.memo(("plain-classes", 0), lambda: plain_classes(self.facts))
            for attribute, callee in space_calls(self.facts, self.receivers).get(name, ()):
                base = plain.get(callee[1:]) if callee.startswith("@") else None
                if base is not None:
                    return name, attribute, callee[1:], base
        if project is None:
            return None
        found = project.non_space_env(module, name)
        return None if found is None else (name, *found)

    # -- GM802 -------------------------------------------------------------------------------

    def _decide_registry_call(self, call: ast.Call, method: str) -> None:
        func = call.func
        assert isinstance(func, ast.Attribute)
        if method == "all":
            if call.args or call.keywords:
                return
            self.report(call, "GM802", "`registry.all()` -> `registry.values()`: the registry is a plain dict")
            owner = self._current_registry_build(func.value, lambda node: node.func.value)
            self.plan.replace(call, lambda node: node.with_changes(func=node.func.with_changes(value=owner(node), attr=cst.Name("values"))))
            return
        self.report(call, "GM802", f"`registry.{method}(...)` -> `gym.{method}(...)`: the registry is a plain dict")
        module = self._gym_module_name()
        self.plan.replace(call, lambda node: node.with_changes(func=cst.Attribute(value=cst.Name(module), attr=cst.Name(method))))

    def _current_registry_build(self, registry: ast.expr, current):
        """``gym.envs.registry`` / ``gym.envs.registration.registry`` -> ``gym.registry``;
        any other spelling of the registry stays as written (``current(node)``)."""
        parts = (full_name(registry) or "").split(".")
        if len(parts) >= 3 and parts[1] == "envs" and parts[-1] == "registry" and parts[0] == self._gym_alias:
            alias = parts[0]
            return lambda node: cst.Attribute(value=cst.Name(alias), attr=cst.Name("registry"))
        return current

    def _gym_module_name(self) -> str:
        if self._gym_alias is not None:
            return self._gym_alias
        if not self.notes.gymnasium_imported:
            self.plan.add_import("import gymnasium")
        return "gymnasium"


def _local_wrapper_steppers(facts: ModuleFacts, receivers: Receivers) -> dict[str, str]:
    """In a run of one file: its classes whose reset steps the wrapper around them, with
    their subclasses in the file (class -> the class that defines that reset)."""
    handoffs = self_handoffs(facts, receivers)
    own = {name for name, classdef in facts.classes.items() if steps_its_wrapper(reset_steps(classdef), handoffs)}
    found: dict[str, str] = {name: name for name in own}
    changed = True
    while changed:
        changed = False
        for name, classdef in facts.classes.items():
            if name in found:
                continue
            for base in classdef.bases:
                if isinstance(base, ast.Name) and base.id in found:
                    found[name] = found[base.id]
                    changed = True
                    break
    return found


def _checker_chosen(call: ast.Call) -> bool:
    """The registration says itself whether make's env checker runs: nothing to add."""
    return any(kw.arg == "disable_env_checker" or E.sets_checker(kw) for kw in call.keywords)
