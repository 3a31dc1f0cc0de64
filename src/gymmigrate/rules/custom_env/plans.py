"""What the custom-env family decides for one class, taken on ``ast`` and carried out by
the build in ``rebuild.py``; plus the words both sides read. No LibCST here: deciding
never loads it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

# Identifiers that count steps or time (``self.steps >= self.max_steps``, ``self.t > 200``),
# shared with the builds.
from gymmigrate.facts.limit_tests import STEP_LIMIT_WORD

SUPER_RESET = "super().reset(seed=seed)"

__all__ = [
    "BATCHED_STEP_QUESTION",
    "STEP_LIMIT_WORD",
    "SUPER_RESET",
    "ClassPlan",
    "SeedPlan",
    "batched_step_message",
    "truncated_false_message",
]


@dataclass
class SeedPlan:
    """``seed()`` is removed: statements (by index in its body) that move elsewhere."""

    moved: list[int] = field(default_factory=list)  # into reset(), under ``if seed is not None:``
    setup: list[int] = field(default_factory=list)  # into __init__, where self.seed() was called
    # no self.seed() call in the class: the set-up goes to the end of __init__ instead
    setup_at_init_end: bool = False
    renames: dict[str, str] = field(default_factory=dict)  # the seed's other names -> ``seed``
    callers: set[str] = field(default_factory=set)  # methods that call self.seed()
    keep: bool = False  # seed() stays a method; reset() calls it when given a seed
    # the class has no seed(): its ``self.seed()`` calls reached gym's Env.seed, gone in
    # Gymnasium, and only they are dropped
    base_calls_only: bool = False
    # ``self.seed(s)`` calls that pass a seed become this statement (``{}``: the seed as
    # written), ``self.np_random, _ = seeding.np_random(s)``: the generator the removed
    # canonical seed() built from that seed, built in place (the seed's parameter name, the
    # statement)
    reseed: tuple[str, str] | None = None


@dataclass
class ClassPlan:
    renamed: dict[str, str] = field(default_factory=dict)  # new name -> gym < 0.9 name
    dropped: set[str] = field(default_factory=set)  # public methods that only forwarded to a renamed one
    # ``reset = _reset`` and the like in the class body: public name -> the hook it names;
    # the hooks keep their names (subclasses call them)
    published: dict[str, str] = field(default_factory=dict)
    # the ``reset = <hook>`` alias becomes a reset taking seed and options that calls the
    # hook: (hook, seed hook or None, whether it calls super().reset(seed=seed) first)
    reset_alias: tuple[str, str | None, bool] | None = None
    # a subclass's reset that calls its base's private reset hook (``Base._reset(self)``):
    # the base's seed hook it calls when given a seed, as legacy ``seed(n); reset()`` did
    reset_seed_hook: str | None = None
    # bases named plainly: ``Base.reset(self)`` in reset is handled like ``super().reset()``
    reset_bases: frozenset[str] = frozenset()
    seed: SeedPlan | None = None
    # returns of a reset with ``return_info`` that no ``return_info`` test guards (the
    # other mode of a two-mode env): they return ``(obs, {})`` like the kept branches
    reset_pairs_untested: bool = False
    reset_forwards_keywords: bool = False  # reset(**kwargs) passes seed/options to super().reset(**kwargs)
    # the base reset the class's reset calls stays as it was (no seed/options, its old
    # return): the call is left as written
    reset_base_kept: bool = False
    reset_super_seeds: bool = True  # super().reset(seed=seed) may be called (else only reported)
    # where super().reset() would run a base's own reset (abstract, or one of another
    # contract): the name the module calls Gymnasium by, for ``<name>.Env.reset(self, seed=seed)``,
    # which seeds np_random as the base Env does and nothing else
    reset_env_seeds: str | None = None
    # ``self.scene.np_random = self.np_random`` of __init__ (source): reset repeats it after
    # super().reset(seed=seed), which replaces self.np_random
    reset_rehands: list[str] = field(default_factory=list)
    render: bool = False
    pass_render_mode: bool = False  # a subclass __init__ takes render_mode and passes it to the base
    render_helper: str | None = None  # keeps the old render(mode) body for the class's own mode calls
    # render(mode) kept as it is (set-up the class runs itself); __init__ still takes render_mode
    render_init_only: bool = False
    render_keeps_mode: bool = False  # render(self, mode=None, ...): a mode passed wins, else self.render_mode
    render_helper_callers: set[str] = field(default_factory=set)  # methods that call self.render(mode)
    render_helper_default: str | None = None  # the old default mode, for the class's own bare self.render()
    # objects of the project's own (as written: ``self._engine``) whose render(mode) render()
    # keeps handing the mode to, as self.render_mode
    render_mode_receivers: set[str] = field(default_factory=set)
    # the modes the ported render draws, declared as ``metadata = {"render_modes": [...]}``:
    # gymnasium.make's env checker asserts render_mode is None where none are declared
    declare_render_modes: tuple[str, ...] = ()
    info_helper: bool = False  # reset returns self._get_info() (it takes no arguments)
    local_env_base: bool = False  # __init__ comes from a base (of the module, or a library): none is added
    unpack_self_reset: bool = False
    # Methods that call a gym < 0.9 name or assign self.reset(): only those are visited,
    # so a class of fifty methods costs what its few affected methods cost.
    rename_callers: set[str] = field(default_factory=set)
    reset_callers: set[str] = field(default_factory=set)
    reset: bool = False  # reset() changes (signature, returns, super().reset(seed=seed))
    # the class keeps its own four-field step (a batch, per-agent lists): reset stays as it is
    reset_kept: bool = False
    step: bool = False  # step() returns four values somewhere
    # step() returns stacked per-env flags (a batch of envs): its returns keep four fields
    batched_step: bool = False
    step_helpers: list[str] = field(default_factory=list)  # what step() returns the result of
    # Method (source name) -> positions among its returns whose done is only a step limit:
    # they return ``False, <done>`` (terminated, truncated).
    truncating_returns: dict[str, set[int]] = field(default_factory=dict)
    # The class's tests that name a counter but are no step limit (whitespace-free source):
    # the end of its data (``self.day == self.max_step``, max_step = len(data) - 1) and a run
    # of consecutive steps (``self.landed_ticks == FPS``); never truncated when the rewrite
    # splits a done.
    non_limit_tests: frozenset[str] = frozenset()
    # method -> positions of returns that hand on an inner step's terminated and truncated
    passthrough_returns: dict[str, set[int]] = field(default_factory=dict)
    # method -> positions of returns whose done comes from a step that is no Gym step (two
    # actions): ``<done>, False``, the name kept as the unpack left as it is binds it
    foreign_returns: dict[str, set[int]] = field(default_factory=dict)
    # method -> position -> (name, terminated, truncated): a done assigned once from the
    # per-agent dones of a PettingZoo parallel step, built again from each of its two dicts
    per_agent_returns: dict[str, dict[int, tuple[str, str, str]]] = field(default_factory=dict)
    # method -> positions of returns whose done is an inner step's or'ed with the class's own
    # end of the task: ``bool(done) and not truncated, truncated``
    task_end_returns: dict[str, set[int]] = field(default_factory=dict)
    # method -> positions of returns left as they are (the done of a base's step the run
    # cannot show migrated): reported, not rewritten
    kept_returns: dict[str, set[int]] = field(default_factory=dict)
    # method -> positions of returns whose done last took ``done = done or <step limit>``
    # right before them: that line becomes ``truncated = bool(<step limit>)``
    accumulated_returns: dict[str, set[int]] = field(default_factory=dict)
    # method -> positions of returns whose done is a flag set True by one ``if <step limit>:``
    # of the body and by the task's own ends: that ``if`` becomes ``truncated = bool(<limit>)``
    flagged_limit_returns: dict[str, set[int]] = field(default_factory=dict)
    # method -> position of ``return self._observe()`` (a helper of four values that other
    # code reads too) -> the names it is unpacked into before returning five
    unpacked_helper_returns: dict[str, dict[int, tuple[str, ...]]] = field(default_factory=dict)
    # method -> locals returned as the info whose every binding is ``name = None``: they
    # become ``name = {}`` (Gymnasium's env checker asserts a dict)
    none_infos: dict[str, set[str]] = field(default_factory=dict)
    none_infos_asked: set[tuple[str, str]] = field(default_factory=set)  # (method, local) reported instead
    reset_helpers: list[str] = field(default_factory=list)  # likewise for reset()
    # ``return self.env.reset()`` of an env the class holds: the call-site rule passes the
    # inner (obs, info) through, so these receivers' resets are not paired again.
    inner_reset_receivers: set[str] = field(default_factory=set)
    # Every return of reset() already gives (obs, info) (gym 0.26's shape, without
    # ``options``): only the signature changes, the returns are not paired again.
    reset_returns_pairs: bool = False


def truncated_false_message(limit_hint: str | None) -> str:
    if limit_hint:
        return f"step returns truncated=False, but `{limit_hint}` looks like a step limit: return it as truncated, not terminated"
    return "step returns terminated (the old done) and truncated=False; set truncated if the env stops episodes on a step limit"


# The batches of envs of one module (a batch, its batch of one, its process-pool variant)
# are one decision, to port together or keep together: one review item names them all.
BATCHED_STEP_QUESTION = "batches of envs of this module"


def batched_step_message(class_name: str, keeps_reset: bool = False, keeps_render: bool = False) -> str:
    """The one item on a batch of envs whose step returns stacked per-env flags (GM504 on an
    env class, GM602 on a wrapper), whose contract the run keeps; an env class keeps its
    reset (``keeps_reset``) and its ``render(mode)`` (``keeps_render``) with it, so the item
    names them."""
    if keeps_reset:
        own = "its reset its bare observations (no seed/options)"
        if keeps_render:
            own += ", its render its mode argument"
        kept = f"its step keeps its own four fields and {own}"
        calls = "the calls of them"
        api = "return stacked terminated and truncated arrays from step and (obs, info) from reset"
    else:
        kept, calls, api = "its step keeps its own four fields", "the calls of it", "return stacked terminated and truncated arrays"
    return (
        f"`{class_name}` is a batch of envs (its step returns one stacked done per env): {kept}, and so do {calls} "
        "and the wrappers around it this run can trace; only its calls on the envs inside were migrated (each "
        "env's done is their `terminated or truncated`, so a time-limit cut still counts as an end). To give it "
        f"Gymnasium's API, {api}, together with its callers and the wrappers put on it (Gymnasium's own, such as "
        "RewardWrapper, unpack five values)"
    )
