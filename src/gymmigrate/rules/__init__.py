"""Rule families, one module each. Importing a module registers its pass.

Where a rule lives (families decide in the order of ``PIPELINE`` below):

    GM101-GM105, GM108         imports ......................... imports.py
    GM106, GM803-GM805         env ids, Atari registration ..... env_ids/ids.py
    GM802, GM806               registry API, EnvSpec ........... env_ids/registry.py
    GM305, GM801               removed make() keywords ......... make_kwargs.py
    GM608-GM615                renamed/removed wrappers ........ wrapper_usage/
    GM401-GM403, GM406, GM407  rendering at call sites ......... rendering.py
    GM701, GM702, GM705-GM708  vector envs ..................... vector/
    GM404, GM405, GM501-GM509  custom Env subclasses ........... custom_env/
    GM505, GM506, GM901        np_random Generator API ......... rng.py
    GM201-GM208, GM704         reset and seeding at call sites . reset_seed/
    GM301-GM304, GM703         step and done at call sites ..... step_done/
    GM601-GM603                wrapper subclasses .............. wrappers/
    GM604-GM606                attribute forwarding ............ wrapper_usage/
    GM616                      gym < 0.9 wrapper hooks ......... legacy_hooks.py
    GM902, GM904, GM906-GM908  spaces, logger, errors, utils ... spaces_logger.py
    GM903, GM905, GM909, GM910 space drift (ints, dicts, sizes, ==) spaces/drift.py
    PZ101-PZ110                PettingZoo AEC and parallel APIs  pettingzoo/
    GM109, GM110, SB110        dependency declarations ......... dependency_files.py (carried
                               out by gymmigrate.dependencies, not a family)

Not rules (catalog entries that are information only, or that cannot be told apart
from correct code by syntax): GM306, GM307, GM607.

Guards (SB102-SB104: Stable-Baselines3 VecEnvs keep their API) are not a pass: every
call-site rule asks ``gymmigrate.facts`` what the receiver is and leaves SB3
VecEnvs, PettingZoo envs and unrelated objects alone (PettingZoo envs get their own
rules, PZ101-PZ110, which leave Gym envs alone in turn).
"""

from gymmigrate.rules import (  # noqa: F401  (imported to register their passes)
    custom_env,
    dependency_files,
    env_ids,
    imports,
    legacy_hooks,
    make_kwargs,
    pettingzoo,
    rendering,
    reset_seed,
    rng,
    spaces,
    spaces_logger,
    step_done,
    vector,
    wrapper_usage,
    wrappers,
)
from gymmigrate.rules.base import Rule, RuleFamily, all_rules, registered_families, set_pipeline

# The order families decide in. Each decides on the same original module, so the order
# matters only where a family reads another's notes (``after``, checked against this
# list) and for edits several families make to one node (applied in this order).
PIPELINE = (
    "Imports",
    "EnvIds",
    "RegistryApi",
    "MakeKeywords",
    "WrapperRenames",
    "Rendering",
    "VectorEnvs",
    "EnvClassFamily",
    "MetadataKeys",
    "RewardRange",
    "EnvClasses",
    "GeneratorApi",
    "ResetSeed",
    "StepDone",
    "AecLoop",
    "ParallelCalls",
    "SeedRender",
    "WrapperClasses",
    "WrapperForwarding",
    "LegacyWrapperHooks",
    "SpacesLogger",
    "SpaceDrift",
    "SpacesAndMake",
)
set_pipeline(PIPELINE)

__all__ = ["PIPELINE", "Rule", "RuleFamily", "all_rules", "registered_families"]
