"""Rule families, one module each, loaded on first use (``PIPELINE`` below).

Where a rule lives (families decide in the order of ``PIPELINE`` below):

    GM101-GM105, GM107, GM108  imports ......................... imports/
    GM106, GM803-GM805         env ids, Atari registration ..... env_ids/ids.py
    GM112                      renamed env packages (gym_minigrid) renamed_packages.py
    GM802, GM806-GM808, GM810 registry API, EnvSpec ........... env_ids/registry.py
    GM809                      ids built from parts ............ env_ids/composed.py
    GM305, GM801               removed make() keywords ......... make_kwargs.py
    GM608-GM615                renamed/removed wrappers ........ wrapper_usage/
    GM401-GM403, GM406, GM407  rendering at call sites ......... rendering/
    GM701, GM702, GM705-GM708  vector envs ..................... vector/
    GM404, GM405, GM501-GM509  custom Env subclasses ........... custom_env/
    GM511                      spaces unset or lists ........... custom_env/spaces.py
    GM505, GM506, GM901        np_random Generator API ......... rng.py
    GM510                      stdlib random in env methods .... stdlib_random.py
    GM201-GM208, GM704         reset and seeding at call sites . reset_seed/
    GM301-GM304, GM703         step and done at call sites ..... step_done/
    GM209                      step or render before reset ..... reset_order.py
    GM601-GM603, GM617, GM618  wrapper subclasses .............. wrappers/
    GM604-GM606                attribute forwarding ............ wrapper_usage/
    GM616                      gym < 0.9 wrapper hooks ......... legacy_hooks.py
    GM902, GM904, GM906-GM908  spaces, logger, errors, utils ... spaces_logger.py
    GM903, GM905, GM909, GM910 space drift (ints, dicts, sizes, ==) spaces/
    GM914                      NumPy names removed in 1.24/2.0 . numpy_removed.py
    PZ101-PZ112                PettingZoo APIs and env modules . pettingzoo/
    GM109, GM110, SB110        dependency declarations ......... dependency_files.py (carried
                               out by gymmigrate.dependencies, not a family)
    GM111                      gym.envs plugin entry points .... dependency_files.py; the module
                               they name gets its call from env_ids/plugins.py

Not rules (catalog entries that are information only, or that cannot be told apart
from correct code by syntax): GM306, GM307, GM607.

Guards (SB102-SB104: Stable-Baselines3 VecEnvs keep their API) are not a pass: every
call-site rule asks ``gymmigrate.facts`` what the receiver is and leaves SB3
VecEnvs, PettingZoo envs and unrelated objects alone (PettingZoo envs get their own
rules, PZ101-PZ110, which leave Gym envs alone in turn).
"""

from gymmigrate.rules import dependency_files  # noqa: F401  (declares GM109, GM110, SB110)
from gymmigrate.rules.base import (
    FamilySpec,
    Rule,
    RuleFamily,
    families_for,
    registered_families,
    set_pipeline,
    standalone_rules,
)

_PZ = ("pettingzoo", "supersuit", "agent_iter")  # a PettingZoo import, or an agent_iter() loop

# The order families decide in, each with where it lives and the words without which it
# cannot fire (its module loads only for a file that spells one). Each decides on the same
# original module, so the order matters only where a family reads another's notes
# (``after``, checked against this list) and for edits several families make to one node
# (applied in this order).
PIPELINE = (
    FamilySpec("Imports", "gymmigrate.rules.imports"),
    FamilySpec("RenamedEnvPackages", "gymmigrate.rules.renamed_packages", ("gym_minigrid",)),
    FamilySpec("EnvIds", "gymmigrate.rules.env_ids.ids", ("-v", "ale.lives", ".ale", "NoFrameskip", "get_action_meanings", "Atari", "atari", "dm2gym:", "procgen:", "slimevolleygym:"), follows_the_run=True),
    FamilySpec("EnvPlugins", "gymmigrate.rules.env_ids.plugins", (), follows_the_run=True),
    FamilySpec("ComposedIds", "gymmigrate.rules.env_ids.composed", ("make", "-v")),
    FamilySpec(
        "RegistryApi",
        "gymmigrate.rules.env_ids.registry",
        ("registry", "_kwargs", "_env_name", "entry_point", "order_enforce", "timestep_limit", "trials", "tags", "max_episode_seconds", "local_only"),
    ),
    FamilySpec("MakeKeywords", "gymmigrate.rules.make_kwargs", ("new_step_api", "autoreset", "apply_api_compatibility", "return_info")),
    FamilySpec("WrapperRenames", "gymmigrate.rules.wrapper_usage.renames", ("wrappers", '"Monitor"', "'Monitor'")),
    # In a run, an env made here may be drawn by a wrapper of another module (its make is reported).
    FamilySpec(
        "Rendering", "gymmigrate.rules.rendering", ("render", "single_rgb_array", "RecordVideo", "play", "VecVideoRecorder", "Monitor"), True
    ),
    FamilySpec("VectorEnvs", "gymmigrate.rules.vector", ("vector", "VectorEnv", "final_", "terminal_observation")),
    FamilySpec("EnvClassFamily", "gymmigrate.rules.custom_env.env_class", ("class",)),
    FamilySpec("MetadataKeys", "gymmigrate.rules.custom_env.metadata", ("render.modes", "video.frames_per_second")),
    FamilySpec("RewardRange", "gymmigrate.rules.custom_env.reward_range", ("reward_range",)),
    FamilySpec("EnvClasses", "gymmigrate.rules.pettingzoo.env_classes", _PZ, follows_the_run=True),
    FamilySpec("GeneratorApi", "gymmigrate.rules.rng", ("np_random", "seeding")),
    FamilySpec("StdlibRandom", "gymmigrate.rules.stdlib_random", ("random",)),
    FamilySpec("ResetSeed", "gymmigrate.rules.reset_seed", ("reset", "seed")),
    FamilySpec("StepDone", "gymmigrate.rules.step_done.family", ("step", "TimeLimit.truncated")),
    FamilySpec("ResetOrder", "gymmigrate.rules.reset_order", ("make",)),
    FamilySpec("AecLoop", "gymmigrate.rules.pettingzoo.aec_loop", _PZ, follows_the_run=True),
    FamilySpec("ParallelCalls", "gymmigrate.rules.pettingzoo.parallel", _PZ, follows_the_run=True),
    FamilySpec("SeedRender", "gymmigrate.rules.pettingzoo.seed_render", _PZ, follows_the_run=True),
    FamilySpec("WrapperState", "gymmigrate.rules.pettingzoo.wrapper_state", _PZ, follows_the_run=True),
    FamilySpec("WrapperClasses", "gymmigrate.rules.wrappers.family", ("Wrapper", "wrappers", "self.env", "def step")),
    FamilySpec("WrapperConstructorArgs", "gymmigrate.rules.wrappers.constructor_args", ("Wrapper", "wrappers")),
    # gym's AtariEnv's methods (``wrapper_usage.atari_api.ATARI_METHOD_WORDS``) on an env of another module
    FamilySpec(
        "WrapperForwarding",
        "gymmigrate.rules.wrapper_usage.forwarding",
        ("gym", "._get_image(", "._get_ram(", ".clone_full_state(", ".restore_full_state(", ".unwrapped.seed("),
        follows_the_run=True,
    ),
    FamilySpec("LegacyWrapperHooks", "gymmigrate.rules.legacy_hooks", ("def _",)),
    FamilySpec("SpacesLogger", "gymmigrate.rules.spaces_logger", ("logger", "error", "check_env", "Box", "seed")),
    FamilySpec(
        "SpaceDrift",
        "gymmigrate.rules.spaces.drift",
        ("isinstance", "type(", "json", "==", "space.shape", "Box", "Discrete", "MultiBinary", "MultiDiscrete", "Space", "Tuple", "Dict", "Text", "Graph", "Sequence", "OneOf"),
    ),
    FamilySpec("NumpyRemoved", "gymmigrate.rules.numpy_removed", ("numpy",)),
    FamilySpec("EnvModules", "gymmigrate.rules.pettingzoo.env_modules", ("pettingzoo",)),
    FamilySpec("SpacesAndMake", "gymmigrate.rules.pettingzoo.spaces_make", _PZ, follows_the_run=True),
)
set_pipeline(PIPELINE)


def all_rules() -> list[Rule]:
    """Every rule: those of every family (which loads them all) and the standalone ones."""
    rules = [rule for family in registered_families() for rule in family.RULES] + standalone_rules()
    return sorted(rules, key=lambda rule: rule.code)


__all__ = ["PIPELINE", "FamilySpec", "Rule", "RuleFamily", "all_rules", "families_for", "registered_families"]
