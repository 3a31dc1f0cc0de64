"""PettingZoo (PZ101-PZ112): the multi-agent AEC and parallel APIs, pre-1.21 to 1.27, and the env modules that moved.

    PZ108, PZ103-PZ107 in classes  custom AEC/parallel envs ... env_classes.py [41]
    PZ101-PZ103                    AEC loops, ``env.dones`` .... aec_loop.py    [56]
    PZ104, PZ105                   parallel step and reset ..... parallel.py    [57]
    PZ106, PZ107                   seed and render calls ....... seed_render.py [58]
    PZ109, PZ110                   spaces, ``pettingzoo.make`` . spaces_make.py [90]
    PZ111                          moved and bumped env modules  env_modules.py
    PZ112                          wrappers' copied env state .. wrapper_state.py

``env_classes.py`` finds the custom env classes and plans their ``self.dones``; their own
``step``, ``reset`` and ``render`` are planned in ``class_step.py`` (PZ104),
``class_reset.py`` (PZ105, PZ106) and ``class_render.py`` (PZ107).
``endings.py`` traces why a custom env's ``dones`` value is True (a game over or a
step limit) for PZ104 and PZ108, with the single-agent step-limit test (GM504's);
``dones_split.py`` sends each store of a custom env's ``dones`` where that says.
``inner_dones.py`` decides a parallel env's ``dones`` unpacked from the step of a simulation
it holds. ``renamed_names.py`` holds the names of ``pettingzoo.utils`` that current PettingZoo spells
differently (PZ108 renames them).

Every family asks ``facts.multi_agent`` what a receiver is: the PettingZoo rules act
only on PettingZoo envs, and the Gym rules leave them alone (their kinds are guards).
SuperSuit's vector conversions (``concat_vec_envs_v1``...) make VecEnvs, which keep
their own API. Nothing here imports PettingZoo.
"""

from gymmigrate.rules.pettingzoo import (  # noqa: F401
    aec_loop,
    env_classes,
    env_modules,
    parallel,
    seed_render,
    spaces_make,
    wrapper_state,
)
