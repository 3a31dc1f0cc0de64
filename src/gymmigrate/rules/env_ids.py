"""Environment ids, third-party registration and the registry API (GM106, GM802-GM806).

* GM803 retired ids are bumped to the id Gymnasium 1.4 registers (``Pendulum-v0`` ->
  ``Pendulum-v1``; ``LunarLander-v2`` -> ``LunarLander-v3``...), from one table,
  ``RETIRED_IDS``. Only strings in an env-id position are touched: the id argument of
  ``make`` / ``make_vec`` / ``vector.make`` / ``spec`` / the legacy registry methods /
  SB3's ``make_vec_env`` and ``make_atari_env``, a constant that is only ever assigned
  one literal and is passed there, and the ``default=`` of an ``--env...`` argparse
  option. Gymnasium raises ``DeprecatedEnv`` for every retired id. ``CartPole-v0`` is
  still registered (200 steps, threshold 195; v1 has 500 / 475), so it is never bumped.
* MuJoCo ``-v2`` / ``-v3`` (mujoco-py) raise ``ImportError`` since Gymnasium 1.2. They
  become ``-v4``: v4 is the same model and reward on the ``mujoco`` bindings, while v5
  changes rewards, observations and ``reset`` info (see each env's Version History), which
  would silently change a tuned experiment. ASSIST, and the message names v5.
* GM804 Atari ids removed in ale-py 0.11.1 (``*Deterministic*``, ``*-ram*``) become the
  base id plus ``frameskip=`` / ``obs_type="ram"``; ``NoFrameskip-v4`` is never turned
  into ``ALE/...-v5`` (sticky actions and frame skip differ).
* GM106 Gymnasium 1.0 removed plugin auto-registration: a module that makes an Atari id
  gets ``import ale_py`` + ``gym.register_envs(ale_py)`` (AUTO); MiniGrid and
  highway-env ids get their package import (ASSIST).
* GM805 ids of removed families (robotics ``Fetch*``/``Hand*``, ``Striker``/``Thrower``,
  the unittest envs) are reported.
* GM802 the gym 0.21 ``EnvRegistry`` API (``env_specs``, ``all()``, ``spec()``,
  ``make()``, ``register()``) becomes the plain dict ``gym.registry`` and the module
  functions. GM806 ``EnvSpec._kwargs`` / ``_env_name`` become ``kwargs`` / ``name``.

Sources: Gymnasium ``envs/__init__.py`` and each env's Version History (1.4.0);
ale-py 0.12.1 ``registration.py``; gym 0.21 ``envs/registration.py``.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass, field

import libcst as cst
import libcst.matchers as m
from libcst.codemod.visitors import AddImportsVisitor
from libcst.helpers import get_full_name_for_node
from libcst.metadata import Assignment, PositionProvider, ScopeProvider

from gymmigrate.analysis import names as N
from gymmigrate.analysis.receivers import METADATA, ReceiverAnalysis
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileProfile, Rule, RulePass

RULES = (
    Rule(
        "GM106",
        "register third-party env packages",
        FixKind.ASSIST,
        "Atari ids get `import ale_py` + `gym.register_envs(ale_py)`; MiniGrid/highway ids get their package import.",
    ),
    Rule("GM802", "registry API", FixKind.AUTO, "`registry.env_specs/all()/spec()/make()` become `gym.registry` and `gym.spec/make`."),
    Rule("GM803", "retired env ids", FixKind.AUTO, "Retired env ids are bumped to the version Gymnasium 1.4 registers."),
    Rule("GM804", "Atari ids", FixKind.ASSIST, "Removed `*Deterministic*` / `*-ram*` Atari ids become the base id plus keywords."),
    Rule("GM805", "removed env families", FixKind.FLAG, "Ids of env families Gymnasium removed are reported."),
    Rule("GM806", "EnvSpec attributes", FixKind.AUTO, "`spec._kwargs` / `spec._env_name` become `spec.kwargs` / `spec.name`."),
)


@dataclass(frozen=True)
class IdMigration:
    """What a retired id becomes: the new id, keywords the env needs to stay the same env."""

    new_id: str
    kind: FixKind
    reason: str
    kwargs: tuple[tuple[str, str], ...] = ()  # (keyword, Python source of its value)
    rule: str = "GM803"


_SAME = "the same environment under its current version"
_LANDER = "v3 resets wind each episode and widens the observation bounds; saved policies and normalisers may not transfer"
_CAR = "v3 ends a finished lap with termination instead of truncation and changed the track-completion logic (0.24)"
_MUJOCO = (
    "mujoco-py envs raise ImportError since Gymnasium 1.2; v4 keeps the model and reward on the mujoco bindings "
    "(v5 is maintained but changes rewards and observations)"
)
_MUJOCO_IDS = {
    "v2": (
        "Ant", "HalfCheetah", "Hopper", "Humanoid", "HumanoidStandup", "InvertedDoublePendulum",
        "InvertedPendulum", "Pusher", "Reacher", "Swimmer", "Walker2d",
    ),
    "v3": ("Ant", "HalfCheetah", "Hopper", "Humanoid", "Swimmer", "Walker2d"),
}  # fmt: skip

# Every legacy id Gymnasium 1.4 no longer makes, and what it becomes (tests check that
# each target is registered and not a stub that raises).
RETIRED_IDS: dict[str, IdMigration] = {
    "Pendulum-v0": IdMigration("Pendulum-v1", FixKind.AUTO, "v1 only simplified the equations, same behaviour"),
    "FrozenLake-v0": IdMigration("FrozenLake-v1", FixKind.AUTO, _SAME),
    "FrozenLake8x8-v0": IdMigration("FrozenLake8x8-v1", FixKind.AUTO, _SAME),
    "Blackjack-v0": IdMigration("Blackjack-v1", FixKind.AUTO, "v1 fixed `natural=True` handling; the defaults are unchanged"),
    "Taxi-v3": IdMigration("Taxi-v4", FixKind.AUTO, "v4 only fixed the optional rainy/fickle modes; the defaults are unchanged"),
    "Taxi-v2": IdMigration("Taxi-v4", FixKind.ASSIST, "v3 corrected the map, so episodes differ from v2"),
    "CliffWalking-v0": IdMigration("CliffWalking-v1", FixKind.AUTO, "v1 only added the optional slippery variant"),
    "LunarLander-v2": IdMigration("LunarLander-v3", FixKind.ASSIST, _LANDER),
    "LunarLanderContinuous-v2": IdMigration("LunarLanderContinuous-v3", FixKind.ASSIST, _LANDER),
    "CarRacing-v0": IdMigration("CarRacing-v3", FixKind.ASSIST, _CAR),
    "CarRacing-v1": IdMigration("CarRacing-v3", FixKind.ASSIST, _CAR),
    "CarRacing-v2": IdMigration("CarRacing-v3", FixKind.ASSIST, "v3 ends a finished lap with termination instead of truncation"),
    "CarRacingDiscrete-v1": IdMigration("CarRacing-v3", FixKind.ASSIST, _CAR, (("continuous", "False"),)),
    "CarRacingDomainRandomize-v1": IdMigration("CarRacing-v3", FixKind.ASSIST, _CAR, (("domain_randomize", "True"),)),
    "CarRacingDomainRandomizeDiscrete-v1": IdMigration(
        "CarRacing-v3", FixKind.ASSIST, _CAR, (("continuous", "False"), ("domain_randomize", "True"))
    ),
    **{
        f"{name}-{version}": IdMigration(f"{name}-v4", FixKind.ASSIST, _MUJOCO)
        for version, env_names in _MUJOCO_IDS.items()
        for name in env_names
    },
}

# GM805: families that are gone from Gymnasium, with what to do instead.
REMOVED_FAMILIES: tuple[tuple[re.Pattern[str], str], ...] = (
    (
        re.compile(r"^(Fetch(Slide|PickAndPlace|Reach|Push)|HandReach|HandManipulate(Block|Egg|Pen)[A-Za-z]*)(Dense)?-v\d+$"),
        "robotics envs moved to gymnasium_robotics: install it, `gym.register_envs(gymnasium_robotics)` and use its current id",
    ),
    (re.compile(r"^(Striker|Thrower)-v\d+$"), "Striker/Thrower were removed in gym 0.23 (archived in Gym-Mujoco-Archive)"),
    (
        re.compile(r"^(CubeCrash(Sparse|ScreenBecomesBlack)?|MemorizeDigits)-v\d+$"),
        "the gym unittest envs were removed in gym 0.22; vendor the env or pick another",
    ),
)

# Atari games whose ``<Game>-v0/v4`` and ``NoFrameskip`` ids ale-py still registers
# (ale-py 0.12.1 ``register_v0_v4_envs``); the ``ALE/`` namespace has every ROM.
LEGACY_ATARI_GAMES = frozenset(
    {
        "Adventure", "AirRaid", "Alien", "Amidar", "Assault", "Asterix", "Asteroids", "Atlantis",
        "BankHeist", "BattleZone", "BeamRider", "Berzerk", "Bowling", "Boxing", "Breakout", "Carnival",
        "Centipede", "ChopperCommand", "CrazyClimber", "Defender", "DemonAttack", "DoubleDunk",
        "ElevatorAction", "Enduro", "FishingDerby", "Freeway", "Frostbite", "Gopher", "Gravitar", "Hero",
        "IceHockey", "Jamesbond", "JourneyEscape", "Kangaroo", "Krull", "KungFuMaster",
        "MontezumaRevenge", "MsPacman", "NameThisGame", "Phoenix", "Pitfall", "Pong", "Pooyan",
        "PrivateEye", "Qbert", "Riverraid", "RoadRunner", "Robotank", "Seaquest", "Skiing", "Solaris",
        "SpaceInvaders", "StarGunner", "Tennis", "TimePilot", "Tutankham", "UpNDown", "Venture",
        "VideoPinball", "WizardOfWor", "YarsRevenge", "Zaxxon",
    }
)  # fmt: skip
_ATARI_ID = re.compile(
    r"^(?P<namespace>ALE/)?(?P<game>[A-Z][A-Za-z0-9]*?)(?P<ram>-ram)?(?P<mode>Deterministic|NoFrameskip)?-v(?P<version>\d+)$"
)


@dataclass(frozen=True)
class EnvPackage:
    """A third-party package whose ids need an import since Gymnasium 1.0 (GM106)."""

    module: str
    kind: FixKind
    legacy_module: str | None = None  # its gym-era name, which does not work with Gymnasium


ALE = EnvPackage("ale_py", FixKind.AUTO)
MINIGRID = EnvPackage("minigrid", FixKind.ASSIST, legacy_module="gym_minigrid")
HIGHWAY = EnvPackage("highway_env", FixKind.ASSIST)


def atari_migration(env_id: str) -> IdMigration | None:
    """Removed ``Deterministic`` / ``-ram`` ids -> base id + keywords (None: keep the id)."""
    match = _ATARI_ID.match(env_id)
    if match is None or not is_atari_id(env_id):
        return None
    game, ram, mode, version = match["game"], match["ram"], match["mode"], match["version"]
    if not ram and mode != "Deterministic":
        return None
    kwargs: list[tuple[str, str]] = []
    if mode == "Deterministic":
        kwargs.append(("frameskip", "3" if game == "SpaceInvaders" else "4"))
    if ram:
        kwargs.append(("obs_type", '"ram"'))
    base = f"{match['namespace'] or ''}{game}{'NoFrameskip' if mode == 'NoFrameskip' else ''}-v{version}"
    removed = "Deterministic and -ram ids" if ram and mode == "Deterministic" else "-ram ids" if ram else "Deterministic ids"
    if match["namespace"]:
        # ale-py registered ALE/<Game>-ram-v5 as ALE/<Game>-v5 with obs_type="ram": the same env.
        return IdMigration(base, FixKind.AUTO, f"ale-py 0.11.1 removed {removed}; the keyword selects the same env", tuple(kwargs), "GM804")
    reason = f"ale-py 0.11.1 removed {removed}; episodes are now capped at 108000 frames by ale-py instead of gym's TimeLimit"
    return IdMigration(base, FixKind.ASSIST, reason, tuple(kwargs), rule="GM804")


def is_atari_id(env_id: str) -> bool:
    match = _ATARI_ID.match(env_id)
    if match is None:
        return False
    if match["namespace"]:
        return True
    return match["game"] in LEGACY_ATARI_GAMES and match["version"] in ("0", "4")


def env_package(env_id: str) -> EnvPackage | None:
    if is_atari_id(env_id):
        return ALE
    if env_id.startswith("MiniGrid-"):
        return MINIGRID
    if env_id.startswith("highway-"):
        return HIGHWAY
    return None


def migration_for(env_id: str) -> IdMigration | None:
    return RETIRED_IDS.get(env_id) or atari_migration(env_id)


def removed_family(env_id: str) -> str | None:
    for pattern, hint in REMOVED_FAMILIES:
        if pattern.match(env_id):
            return hint
    return None


# -- where env ids are -------------------------------------------------------------

# Functions under gym/gymnasium whose first argument (or ``id=``) is an env id.
_ID_FUNCTIONS = frozenset({"make", "make_vec", "vector.make", "spec", "envs.make", "envs.spec", "envs.registration.make", "envs.registration.spec"})
# Functions whose result is made with ``**kwargs`` forwarded to the env constructor.
_FORWARDS_KWARGS = frozenset({"make", "make_vec", "vector.make", "envs.make", "envs.registration.make"})
# Stable-Baselines3 helpers that call gym.make(env_id) themselves.
_SB3_ID_FUNCTIONS = frozenset(
    {
        "stable_baselines3.common.env_util.make_vec_env",
        "stable_baselines3.common.env_util.make_atari_env",
        "stable_baselines3.common.cmd_util.make_vec_env",
        "stable_baselines3.common.cmd_util.make_atari_env",
    }
)
_REGISTRY_NAMES = frozenset({"registry", "envs.registry", "envs.registration.registry"})
_REGISTRY_METHODS = frozenset({"spec", "make", "register"})
_ID_KEYWORDS = ("id", "env_id")
_ENV_OPTION = re.compile(r"^--?env", re.IGNORECASE)


@dataclass
class IdSite:
    """One string literal used as an env id, and the call that receives it (if known)."""

    string: cst.SimpleString
    env_id: str
    module_prefix: str  # "ale_py:" in "ale_py:ALE/Pong-v5"
    call: cst.Call | None
    forwards_kwargs: bool
    via: str = ""  # how the string reaches the call ("the constant ENV_ID"), for messages
    conditional: bool = False  # one branch of ``a if c else b``: keywords would hit both


@dataclass
class _Plan:
    new_strings: dict[cst.SimpleString, str] = field(default_factory=dict)  # original string -> new id
    new_kwargs: dict[cst.Call, list[tuple[str, str]]] = field(default_factory=dict)  # original call -> keywords
    packages: dict[str, tuple[EnvPackage, cst.SimpleString]] = field(default_factory=dict)


def string_value(node: cst.BaseExpression) -> str | None:
    """The text of a plain string literal without escapes (None for anything else)."""
    if not isinstance(node, cst.SimpleString) or "b" in node.prefix.lower():
        return None
    raw = node.value[len(node.prefix) + len(node.quote) : -len(node.quote)]
    value = node.evaluated_value
    return value if isinstance(value, str) and value == raw else None


def with_string_value(node: cst.SimpleString, text: str) -> cst.SimpleString:
    return node.with_changes(value=f"{node.prefix}{node.quote}{text}{node.quote}")


def _split_module_prefix(text: str) -> tuple[str, str]:
    if ":" in text:
        module, env_id = text.split(":", 1)
        return module + ":", env_id
    return "", text


def _id_argument(call: cst.Call) -> cst.Arg | None:
    for arg in call.args:
        if arg.keyword is not None and arg.keyword.value in _ID_KEYWORDS:
            return arg
    positional = [a for a in call.args if a.keyword is None and not a.star]
    return positional[0] if positional else None


def _append_keywords(call: cst.Call, keywords: list[tuple[str, str]]) -> cst.Call:
    """Add ``name=value`` arguments at the end, following the call's comma style."""
    args = list(call.args)
    new_args = [
        cst.Arg(
            keyword=cst.Name(name),
            value=cst.parse_expression(value),
            equal=cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace("")),
        )
        for name, value in keywords
    ]
    if not args:
        return call.with_changes(args=new_args)
    last = args[-1]
    separator = cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
    if isinstance(last.comma, cst.Comma):
        # Trailing-comma style (often one argument per line): copy the separator of the
        # previous argument so new arguments land on their own lines.
        if len(args) > 1 and isinstance(args[-2].comma, cst.Comma):
            between = args[-2].comma
        elif isinstance(call.whitespace_before_args, cst.ParenthesizedWhitespace):
            between = cst.Comma(whitespace_after=call.whitespace_before_args)  # the line break after "("
        else:
            between = separator
        args[-1] = last.with_changes(comma=between)
        new_args = [a.with_changes(comma=between) for a in new_args[:-1]] + [new_args[-1].with_changes(comma=last.comma)]
    else:
        args[-1] = last.with_changes(comma=separator)
        new_args = [a.with_changes(comma=separator) for a in new_args[:-1]] + [new_args[-1]]
    return call.with_changes(args=args + new_args)


class EnvIdsPass(RulePass):
    RULES = RULES
    ORDER = 20
    METADATA_DEPENDENCIES = (PositionProvider, *METADATA)

    @classmethod
    def applies_to(cls, source: str, profile: FileProfile) -> bool:
        return "-v" in source or "registry" in source or "_kwargs" in source or "_env_name" in source

    def visit_Module(self, node: cst.Module) -> None:
        self.analysis = ReceiverAnalysis(node, self.metadata)
        self._plan = _Plan()
        self._planned: set[cst.SimpleString] = set()
        self._imported_modules = _imported_modules(node)
        self._gym_alias = _module_alias(node, "gymnasium") or _module_alias(node, "gym")
        for site in self._id_sites(node):
            self._plan_site(site)

    # -- GM803 / GM804 / GM805 / GM106: planning ------------------------------------

    def _id_sites(self, module: cst.Module) -> Iterator[IdSite]:
        for call in m.findall(module, m.Call()):
            assert isinstance(call, cst.Call)
            forwards = self._id_call(call)
            if forwards is None:
                yield from self._argparse_default(call)
                continue
            arg = _id_argument(call)
            if arg is None:
                continue
            # ``gym.make("A-v0" if continuous else "B-v0")``: both branches are ids.
            branches = [arg.value.body, arg.value.orelse] if isinstance(arg.value, cst.IfExp) else [arg.value]
            for branch in branches:
                if isinstance(branch, cst.SimpleString):
                    site = self._site(branch, call, forwards)
                    if site is not None:
                        site.conditional = len(branches) > 1
                        yield site
            if isinstance(arg.value, cst.Name):
                for literal in self._single_literal_constant(arg.value):
                    site = self._site(literal, None, False, via=f"the constant `{arg.value.value}`")
                    if site is not None:
                        yield site

    def _site(self, string: cst.SimpleString, call: cst.Call | None, forwards: bool, via: str = "") -> IdSite | None:
        text = string_value(string)
        if text is None:
            return None
        prefix, env_id = _split_module_prefix(text)
        return IdSite(string, env_id, prefix, call, forwards, via)

    def _id_call(self, call: cst.Call) -> bool | None:
        """Does ``call`` take an env id? True if it also forwards keywords to the env, None if no id."""
        for qualified in self.analysis.qualified_names(call.func):
            rest = N.strip_gym_prefix(qualified)
            if rest in _ID_FUNCTIONS:
                return rest in _FORWARDS_KWARGS
            if qualified in _SB3_ID_FUNCTIONS:
                return False
        if isinstance(call.func, cst.Attribute) and call.func.attr.value in ("spec", "make"):
            if self._is_registry(call.func.value):
                return call.func.attr.value == "make"
        return None

    def _argparse_default(self, call: cst.Call) -> Iterator[IdSite]:
        """``parser.add_argument("--env-id", default="LunarLander-v2")``: the default is an id."""
        if not (isinstance(call.func, cst.Attribute) and call.func.attr.value == "add_argument"):
            return
        flags = [string_value(a.value) for a in call.args if a.keyword is None]
        if not any(flag and _ENV_OPTION.match(flag) for flag in flags):
            return
        for arg in call.args:
            if arg.keyword is not None and arg.keyword.value == "default" and isinstance(arg.value, cst.SimpleString):
                site = self._site(arg.value, None, False, via="this argparse default")
                if site is not None:
                    yield site

    def _single_literal_constant(self, name: cst.Name) -> list[cst.SimpleString]:
        """The literal of ``ENV_ID = "..."`` when that is the name's only assignment."""
        scope = self.get_metadata(ScopeProvider, name, None)
        if scope is None:
            return []
        assignments = list(scope[name.value])
        if len(assignments) != 1 or not isinstance(assignments[0], Assignment):
            return []
        target = assignments[0].node
        holder = self.analysis.parent(target)
        statement = self.analysis.parent(holder) if isinstance(holder, cst.AssignTarget) else holder
        if isinstance(statement, cst.Assign) and len(statement.targets) == 1:
            value = statement.value
        elif isinstance(statement, cst.AnnAssign) and statement.target is target:
            value = statement.value
        else:
            return []
        return [value] if isinstance(value, cst.SimpleString) else []

    def _plan_site(self, site: IdSite) -> None:
        if site.string in self._planned:  # a constant passed to several calls
            return
        self._planned.add(site.string)
        migration = migration_for(site.env_id)
        if migration is not None:
            self._plan_migration(site, migration)
        hint = removed_family(site.env_id)
        if hint is not None:
            self.report(site.string, "GM805", f"`{site.env_id}` no longer exists: {hint}")
        final_id = migration.new_id if migration is not None else site.env_id
        package = env_package(final_id)
        if package is not None and not site.module_prefix and package.module not in self._plan.packages:
            self._plan.packages[package.module] = (package, site.string)

    def _plan_migration(self, site: IdSite, migration: IdMigration) -> None:
        old, new = site.env_id, migration.new_id
        where = f" ({site.via})" if site.via else ""
        if migration.kwargs:
            keywords = ", ".join(f"{k}={v}" for k, v in migration.kwargs)
            taken = {a.keyword.value for a in site.call.args if a.keyword is not None} if site.call else set()
            clash = [k for k, _ in migration.kwargs if k in taken]
            if not site.forwards_kwargs or clash or site.call is None or site.conditional:
                if clash:
                    why = f"the call already passes {', '.join(clash)}"
                elif site.via:
                    why = f"the id comes from {site.via}"
                elif site.conditional:
                    why = "the id is one branch of a conditional"
                else:
                    why = "this call cannot pass keywords to the env"
                self.report(
                    site.string,
                    migration.rule,
                    f"`{old}` no longer exists: make `{new}` with {keywords} ({why}); {migration.reason}",
                    kind=FixKind.FLAG,
                )
                return
            planned = self._plan.new_kwargs.setdefault(site.call, [])
            planned.extend(k for k in migration.kwargs if k not in planned)
            new_text = f"`{new}` with {keywords}"
        else:
            new_text = f"`{new}`"
        self._plan.new_strings[site.string] = site.module_prefix + new
        self.report(site.string, migration.rule, f"`{old}` -> {new_text}{where}: {migration.reason}", kind=migration.kind)

    # -- GM803 / GM804: rewriting ------------------------------------------------------

    def leave_SimpleString(self, original_node: cst.SimpleString, updated_node: cst.SimpleString) -> cst.SimpleString:
        new_id = self._plan.new_strings.get(original_node)
        return with_string_value(updated_node, new_id) if new_id is not None else updated_node

    # -- GM802: registry API --------------------------------------------------------

    def _is_registry(self, expr: cst.BaseExpression) -> bool:
        return any(N.strip_gym_prefix(q) in _REGISTRY_NAMES for q in self.analysis.qualified_names(expr))

    def _current_registry(self, expr: cst.BaseExpression) -> cst.BaseExpression:
        """``gym.envs.registry`` / ``gym.envs.registration.registry`` -> ``gym.registry``."""
        dotted = get_full_name_for_node(expr) or ""
        parts = dotted.split(".")
        if len(parts) >= 3 and parts[1] == "envs" and parts[-1] == "registry" and parts[0] == self._gym_alias:
            return cst.Attribute(value=cst.Name(parts[0]), attr=cst.Name("registry"))
        return expr

    def leave_Attribute(self, original_node: cst.Attribute, updated_node: cst.Attribute) -> cst.BaseExpression:
        attr = original_node.attr.value
        if attr == "env_specs" and self._is_registry(original_node.value):
            self.report(original_node, "GM802", "`registry.env_specs` -> the registry itself: `gym.registry` is a plain dict of EnvSpec")
            return self._current_registry(updated_node.value)
        if attr in _SPEC_ATTRIBUTES and self._is_env_spec(original_node.value):
            new = _SPEC_ATTRIBUTES[attr]
            self.report(original_node, "GM806", f"`EnvSpec.{attr}` -> `EnvSpec.{new}`: the private attribute was made public")
            return updated_node.with_changes(attr=cst.Name(new))
        return updated_node

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.BaseExpression:
        func = original_node.func
        if isinstance(func, cst.Attribute) and isinstance(updated_node.func, cst.Attribute):
            method = func.attr.value
            if self._is_registry(func.value) and method == "all" and not original_node.args:
                self.report(original_node, "GM802", "`registry.all()` -> `registry.values()`: the registry is a plain dict")
                updated_node = updated_node.with_changes(
                    func=updated_node.func.with_changes(value=self._current_registry(updated_node.func.value), attr=cst.Name("values"))
                )
            elif self._is_registry(func.value) and method in _REGISTRY_METHODS:
                self.report(original_node, "GM802", f"`registry.{method}(...)` -> `gym.{method}(...)`: the registry is a plain dict")
                updated_node = updated_node.with_changes(func=cst.Attribute(value=self._gym_module_name(), attr=cst.Name(method)))
        keywords = self._plan.new_kwargs.get(original_node)
        if keywords:
            updated_node = _append_keywords(updated_node, keywords)
        return updated_node

    def _gym_module_name(self) -> cst.Name:
        if self._gym_alias is None:
            AddImportsVisitor.add_needed_import(self.context.codemod, "gymnasium")
            return cst.Name("gymnasium")
        return cst.Name(self._gym_alias)

    # -- GM806: EnvSpec attributes -----------------------------------------------------

    def _is_env_spec(self, expr: cst.BaseExpression, depth: int = 0) -> bool:
        if depth > 3:
            return False
        if isinstance(expr, cst.Attribute) and expr.attr.value == "spec":
            return True  # env.spec, self.spec, gym.make(...).spec
        if isinstance(expr, cst.Call):
            if any(N.strip_gym_prefix(q) in ("spec", "envs.spec", "envs.registration.spec") for q in self.analysis.qualified_names(expr.func)):
                return True
            return isinstance(expr.func, cst.Attribute) and expr.func.attr.value == "spec" and self._is_registry(expr.func.value)
        if isinstance(expr, cst.Subscript):
            return self._is_registry(expr.value) or self._is_env_specs_dict(expr.value)
        if isinstance(expr, cst.Name):
            return self._name_is_env_spec(expr, depth)
        return False

    def _is_env_specs_dict(self, expr: cst.BaseExpression) -> bool:
        return isinstance(expr, cst.Attribute) and expr.attr.value == "env_specs" and self._is_registry(expr.value)

    def _iterates_specs(self, iterable: cst.BaseExpression) -> bool:
        """``registry.all()``, ``registry.values()``, ``registry.env_specs.values()``."""
        if not (isinstance(iterable, cst.Call) and isinstance(iterable.func, cst.Attribute)):
            return False
        owner = iterable.func.value
        return iterable.func.attr.value in ("all", "values") and (self._is_registry(owner) or self._is_env_specs_dict(owner))

    def _name_is_env_spec(self, name: cst.Name, depth: int) -> bool:
        scope = self.get_metadata(ScopeProvider, name, None)
        if scope is None:
            return False
        assignments = list(scope[name.value])
        if not assignments:
            return False
        for assignment in assignments:
            if not isinstance(assignment, Assignment):
                return False
            target = assignment.node
            parent = self.analysis.parent(target)
            if isinstance(parent, cst.AssignTarget):
                statement = self.analysis.parent(parent)
                if not (isinstance(statement, cst.Assign) and self._is_env_spec(statement.value, depth + 1)):
                    return False
            elif isinstance(parent, (cst.For, cst.CompFor)) and parent.target is target:
                if not self._iterates_specs(parent.iter):
                    return False
            else:
                return False
        return True

    # -- GM106: registration imports ----------------------------------------------------

    def leave_Module(self, original_node: cst.Module, updated_node: cst.Module) -> cst.Module:
        needed = []
        for package, string in self._plan.packages.values():
            if package.module in self._imported_modules:
                continue
            if package.legacy_module and package.legacy_module in self._imported_modules:
                self.report(
                    string,
                    "GM106",
                    f"`{package.legacy_module}` is the gym-era package: import `{package.module}` instead and call "
                    f"`gym.register_envs({package.module})`",
                    kind=FixKind.FLAG,
                )
                continue
            needed.append(package)
            self.report(string, "GM106", _registration_message(package), kind=package.kind)
        if not needed:
            return updated_node
        first_use = _first_statement_using(original_node, {string for _, string in self._plan.packages.values()})
        return _insert_registration(updated_node, [p.module for p in needed], self._gym_alias, first_use)


_SPEC_ATTRIBUTES = {"_kwargs": "kwargs", "_env_name": "name"}


def _registration_message(package: EnvPackage) -> str:
    if package is ALE:
        return "Atari ids need `import ale_py` since Gymnasium 1.0 removed plugin auto-registration; added it with `register_envs(ale_py)`"
    return (
        f"these ids need `import {package.module}` since Gymnasium 1.0 removed plugin auto-registration; "
        f"added it: check the package is installed and registers the ids on import"
    )


def _imported_modules(module: cst.Module) -> set[str]:
    found: set[str] = set()
    for node in m.findall(module, m.Import() | m.ImportFrom()):
        if isinstance(node, cst.Import):
            found.update((get_full_name_for_node(a.name) or "").split(".")[0] for a in node.names)
        elif isinstance(node, cst.ImportFrom) and node.module is not None and not node.relative:
            found.add((get_full_name_for_node(node.module) or "").split(".")[0])
    return found


def _module_alias(module: cst.Module, package: str) -> str | None:
    """The name a top-level ``import gymnasium [as gym]`` binds."""
    for statement in module.body:
        if not isinstance(statement, cst.SimpleStatementLine):
            continue
        for small in statement.body:
            if isinstance(small, cst.Import):
                for alias in small.names:
                    if get_full_name_for_node(alias.name) == package:
                        return alias.asname.name.value if alias.asname else package  # type: ignore[union-attr]
    return None


def _is_import_line(statement: cst.BaseStatement) -> bool:
    return isinstance(statement, cst.SimpleStatementLine) and any(
        isinstance(small, (cst.Import, cst.ImportFrom)) for small in statement.body
    )


def _first_statement_using(module: cst.Module, strings: set[cst.SimpleString]) -> int:
    """Index of the first top-level statement that holds one of ``strings``."""
    for index, statement in enumerate(module.body):
        if any(found in strings for found in m.findall(statement, m.SimpleString())):
            return index
    return len(module.body)


def _insert_registration(module: cst.Module, packages: list[str], gym_alias: str | None, first_use: int) -> cst.Module:
    """``import ale_py`` after the last top-level import that comes before the first use of
    an id, then ``gym.register_envs(ale_py)``.

    ``register_envs`` is a no-op that keeps linters and isort from deleting an import that
    looks unused (and with it the registration).
    """
    config = module.config_for_parsing
    body = list(module.body)
    last_import = max((i for i, s in enumerate(body[:first_use]) if _is_import_line(s)), default=-1)
    lines = []
    if gym_alias is None:
        gym_alias = "gymnasium"
        lines.append(cst.parse_statement("import gymnasium", config=config))
    lines += [cst.parse_statement(f"import {package}", config=config) for package in packages]
    calls = [cst.parse_statement(f"{gym_alias}.register_envs({package})", config=config) for package in packages]
    calls[0] = calls[0].with_changes(leading_lines=[cst.EmptyLine()])
    if last_import == -1:
        # No imports: put them after a module docstring, if any.
        docstring = 1 if body and m.matches(body[0], m.SimpleStatementLine([m.Expr(m.SimpleString())])) else 0
        if docstring == 0 and body:
            # Keep the module's header comments above the new lines.
            lines[0] = lines[0].with_changes(leading_lines=body[0].leading_lines)
            body[0] = body[0].with_changes(leading_lines=[cst.EmptyLine()])
        last_import = docstring - 1
    body[last_import + 1 : last_import + 1] = [*lines, *calls]
    return module.with_changes(body=body)
