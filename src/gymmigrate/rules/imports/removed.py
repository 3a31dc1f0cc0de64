"""GM105 on reads through the gym module: a removed module (``gym.envs.atari.AtariEnv``,
``gym.spaces.prng``) or a name Gymnasium lacks (``gym.utils.reraise``) read as an
attribute of ``gym``, reported as its import would be. Imports of them are reported by
``statements.py``."""

from __future__ import annotations

import ast
import re

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.module import walk
from gymmigrate.findings import FixKind, Tier, removed_helper_question
from gymmigrate.rules.imports.common import ImportsBase
from gymmigrate.rules.imports.table import (
    LEGACY_WRAPPER_MODULES,
    REMOVED_MODULES,
    REMOVED_NAMES,
    missing_name_hint,
    removed_module_hint,
    removed_name_hint,
    under_gym,
)

# ``"gym.envs.mujoco.swimmer_v3:SwimmerEnv"``: an entry point naming a module of gym.
_GYM_ENTRY_POINT = re.compile(r"gym\.([\w.]+):(\w+)")


class RemovedAttributes(ImportsBase):
    """GM105 on attribute reads (mixed into the family)."""

    def _removed_module_attributes(self) -> None:
        """GM105 on ``gym.envs.atari.atari_env.AtariEnv`` or ``gym.spaces.prng.seed(s)`` read as
        attributes of the gym module (often behind ``hasattr(gym.envs, "atari")``, which is False
        on Gymnasium: the branch dies silently)."""
        if not self._gym_names:
            return
        found: dict[ast.Attribute, str] = {}
        for removed in REMOVED_MODULES:
            for node in self.facts.attributes.get(removed.rsplit(".", 1)[-1], []):
                if any(under_gym(q) == removed for q in self.facts.qualified_names(node)):
                    found[node] = removed
        for node, removed in sorted(found.items(), key=lambda item: (item[0].lineno, item[0].col_offset)):
            # one item per chain: ``gym.wrappers.monitoring.video_recorder.X`` names the
            # shortest removed module only, not each removed module along it
            inner = node.value
            while isinstance(inner, ast.Attribute) and inner not in found:
                inner = inner.value
            if isinstance(inner, ast.Attribute):
                continue
            hint = REMOVED_MODULES[removed]
            self._report_removed(node, f"`gym.{removed}` was removed: {hint}", hint)  # type: ignore[arg-type]

    def _remove_no_op_call(self, node: ast.Attribute) -> bool:
        """``gym.undo_logger_setup()`` as a statement: gym stopped installing a log
        handler and kept this as a no-op (later removed); Gymnasium installs none, so deleting
        the statement is the whole port. Inside an expression its value is used: reported."""
        call = self.facts.parent(node)
        statement = self.facts.parent(call) if isinstance(call, ast.Call) and call.func is node else None
        if not (isinstance(statement, ast.Expr) and not call.args and not call.keywords):  # type: ignore[union-attr]
            return False
        block = self.facts.parent(statement)
        alone = not isinstance(block, ast.Module) and any(
            getattr(block, field, None) == [statement] for field in ("body", "orelse", "finalbody")
        )
        if alone:
            # the only statement of its block: ``pass`` takes its place, under its comments
            self.plan.replace(statement, lambda _: cst.Pass())
        else:
            self.plan.remove(statement, keep_comments=True)
        self.report(
            call,  # type: ignore[arg-type]
            "GM105",
            "`gym.undo_logger_setup()` removed: later gym releases kept it only as a deprecated no-op (gym stopped configuring logging), and Gymnasium installs no log handler",
            FixKind.AUTO,
            tier=Tier.NOTE,
        )
        return True

    def _missing_module_attributes(self) -> None:
        """GM105 on ``gym.utils.reraise(...)`` read through the gym module: after ``import gym``
        becomes ``import gymnasium as gym`` the read raises AttributeError, so the name is
        reported as its import would be (the code is left as it is)."""
        if not self._gym_names:
            return
        for attr, nodes in self.facts.attributes.items():
            for node in nodes:
                for module in self.facts.qualified_names(node.value):
                    rest = under_gym(module)
                    if rest is None or (rest == "wrappers" and attr in LEGACY_WRAPPER_MODULES):
                        continue  # the legacy wrapper modules: GM104's business
                    path = f"{rest}.{attr}" if rest else attr
                    if removed_module_hint(path, unknown=False) is not None:
                        continue  # reported as a removed module
                    if (rest, attr) in REMOVED_NAMES:
                        # a removed class read through the module (``class G(gym.GoalEnv)``):
                        # its import would be reported, and this read fails the same way
                        advice = REMOVED_NAMES[(rest, attr)]
                        self._report_removed(node, f"`{module}.{attr}` does not exist in Gymnasium: {advice}", advice)  # type: ignore[arg-type]
                        break
                    if rest == "" and attr == "undo_logger_setup" and self._remove_no_op_call(node):
                        break
                    hint = missing_name_hint(rest, attr, renamed_elsewhere=True)
                    if hint is not None:
                        # the name's import, if the file has one, asks the same: what replaces it
                        question = removed_helper_question(rest, attr)
                        self._report_removed(node, f"`{module}.{attr}` does not exist in Gymnasium: {hint}", hint, question)  # type: ignore[arg-type]
                        break

    def _removed_entry_points(self) -> None:
        """GM105 on an entry point string naming a gym module Gymnasium lacks, given to a
        register call (``entry_point="gym.envs.mujoco.swimmer_v3:SwimmerEnv"``) or kept in a
        dict of specs registered later (``{"entry_point": ...}``, ``register(**spec)``):
        ``make`` imports it and fails (gym is not installed, and gym's mujoco-py *_v3 modules
        have no Gymnasium counterpart). Reported with the replacement: the class to register
        takes other arguments, so the string is never renamed silently."""
        if "entry_point" not in self.facts.text:
            return
        for node in walk(self.facts.tree):
            values: list[ast.expr] = []
            if isinstance(node, ast.Call):
                values = [k.value for k in node.keywords if k.arg == "entry_point"]
            elif isinstance(node, ast.Dict):
                values = [v for k, v in zip(node.keys, node.values) if isinstance(k, ast.Constant) and k.value == "entry_point"]
            for value in values:
                text = _plain_string(value)
                match = _GYM_ENTRY_POINT.fullmatch(text.strip()) if text is not None else None
                if match is None:
                    continue
                rest, name = match.group(1), match.group(2)
                hint = removed_module_hint(rest) or removed_name_hint(rest, name)
                if hint is None:
                    continue
                own = self._own_entry_class(name)
                if own is not None:
                    # the grouping stays the gym module's (the same move), only the advice names the class
                    lacks = hint.split(": ", 1)[0]
                    self._report_removed(value, f"the entry point `{text}` names what Gymnasium lacks ({lacks}); {own}", hint)  # type: ignore[arg-type]
                else:
                    self._report_removed(value, f"the entry point `{text}` names what Gymnasium lacks: {hint}; register that class and check its keyword arguments", hint)  # type: ignore[arg-type]

    def _own_entry_class(self, name: str) -> str | None:
        """Advice for an entry point into a gym module that names ``name`` where the run defines
        a Gym env class of that name. Which class the legacy string reached depended on the gym
        installed (a fork that held the class, or none), so the string is not rewritten; the
        item names the class, and a module this file already registers from that exports it."""
        project = self.receivers.project
        found = project.env_classes_named(name) if project is not None else []
        if not found:
            return None
        if len(found) > 1:
            return f"this project defines env classes named `{name}` in {', '.join(found)}: register the one meant, from its own module"
        exporters = sorted(
            {
                module
                for module in self._entry_modules()
                if not module.startswith("gym.") and project is not None and project.call_kind(f"{module}.{name}") is not None
            }
        )
        where = (
            f"as `entry_point=\"{exporters[0]}:{name}\"` (`{exporters[0]}`, which this module's other entry points name, exports it)"
            if exporters
            else "from its own module"
        )
        return f"this project defines the env class `{name}` ({found[0]}): if that is the class meant, register it {where}"

    def _entry_modules(self) -> list[str]:
        """The modules this file's ``entry_point="module:Class"`` strings name."""
        found = []
        for call in (*self.facts.calls_by_name.get("register", ()), *self.facts.attribute_calls.get("register", ())):
            for keyword in call.keywords:
                text = _plain_string(keyword.value) if keyword.arg == "entry_point" else None
                if text is not None and text.count(":") == 1:
                    found.append(text.partition(":")[0].strip())
        return found


def _plain_string(value: ast.expr) -> str | None:
    """A string literal's text, also written as an f-string with nothing to format
    (``f'gym.envs.mujoco.swimmer_v3:SwimmerEnv'``)."""
    if isinstance(value, ast.Constant) and isinstance(value.value, str):
        return value.value
    if isinstance(value, ast.JoinedStr) and all(isinstance(v, ast.Constant) and isinstance(v.value, str) for v in value.values):
        return "".join(v.value for v in value.values)  # type: ignore[attr-defined]
    return None
