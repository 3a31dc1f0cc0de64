"""What one rule family tells another about the same file, typed.

Every family decides on the same original module; where one family's change implies
another's (the step unpack's new names read by a wrapper's ``step``, the ``render_mode``
one make gets whichever family adds it), the first records it here and the reader
declares ``after = ("Writer",)`` so the pipeline runs it later (``rules/__init__.py``).
One ``FamilyNotes`` per file, in ``FileContext.notes``.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from gymmigrate.rules.step_done.common import StepUnpack


@dataclass
class FamilyNotes:
    # StepDone -> WrapperClasses: every four-target step unpack StepDone rewrites. The
    # wrappers family returns the new flags from a wrapper's ``step`` and may withdraw the
    # inserted ``done = ...`` line once its return no longer reads ``done``.
    step_unpacks: dict[ast.Assign, StepUnpack] = field(default_factory=dict)
    # Imports -> EnvIds: ``import gym`` stays on gym, because every env the file makes goes
    # to a library still on gym (baselines): the stack's name. Its ids stay gym's too.
    gym_kept_for: str | None = None
    # Imports -> the engine: every env the module makes comes from a Gym-only plugin (its
    # name), so the module stays on gym as it is: no later family decides anything in it.
    module_kept_for: str | None = None
    # EnvIds -> RegistryApi: the registration block already imports gymnasium.
    gymnasium_imported: bool = False
    # WrapperRenames <-> Rendering: the ``render_mode`` added to a make (id of the call ->
    # mode), so that one make gets one, whichever family adds it first.
    render_modes_added: dict[int, str] = field(default_factory=dict)
    # Rendering -> EnvClassFamily: render calls that still pass a mode after this run; a
    # local env class whose render(mode) they may reach keeps its signature.
    render_mode_calls_left: list[ast.Call] = field(default_factory=list)
    # PettingZoo families -> SpacesAndMake: some PettingZoo call or class was edited.
    pettingzoo_edited: bool = False
    # ResetSeed -> WrapperClasses: the info name a wrapper's inner reset was unpacked into,
    # by ``"Class.method"``.
    reset_info_names: dict[str, str] = field(default_factory=dict)
    # EnvClassFamily -> GeneratorApi: statements of a removed seed() that go with it (not
    # moved into reset() or __init__): a removed seeding helper there needs no decision.
    dropped_statements: set[ast.stmt] = field(default_factory=set)
    # EnvClassFamily -> GeneratorApi: dead lines of a seed() left for a port by hand (its
    # GM503 item asks for it) that only compute a value with a removed seeding helper: that
    # item covers them (the port drops them), no second decision.
    dead_in_hand_ported_seed: set[ast.stmt] = field(default_factory=set)
