"""What a vector step returns in ``infos``, and when sub-envs reset (GM705, GM706).

* GM705 vector ``infos`` is one dict of arrays with ``_key`` masks (since gym 0.24):
  list-style readers (``for info in infos``, ``infos[i]``) either get the env wrapped in
  ``gymnasium.wrappers.vector.DictInfoToList`` (when the env is created right here and
  nothing reads infos as a dict) or are reported.
* GM706 Gymnasium 1.0 autoresets on the *next* step and drops ``final_observation``.
  Readers of ``infos["final_observation"]`` get the least change: the env is created with
  ``autoreset_mode=AutoresetMode.SAME_STEP`` and the key renamed ``final_obs``; readers of
  ``final_info`` (now a dict of arrays) and ``terminal_observation`` are reported.

Stable-Baselines3 VecEnvs keep their list of info dicts and ``terminal_observation``
(SB104): receivers go through ``facts.decisions.decide``.
Sources: Gymnasium ``wrappers/vector/dict_info_to_list.py``, ``vector/vector_env.py``
(``AutoresetMode``); gym 0.24/0.26.2 release notes; Farama blog "Vector Autoreset
Mode" (2025-02-20); Gymnasium#1103.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from collections.abc import Hashable
from dataclasses import dataclass, field
from typing import cast

from gymmigrate.facts import names as N
from gymmigrate.facts.decisions import Action, decide
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import full_name, keyword, string_value
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.step_done.common import looks_vectorised
from gymmigrate.rules.vector.common import (
    LIST_INFO_WRAPPERS,
    VECTOR_CLASSES,
    VectorFamilyBase,
    argument_value,
    arguments_in_order,
    gym_rest,
)

# What a gymnasium VectorWrapper such as DictInfoToList exposes (it has no __getattr__):
# ``envs.call(...)``, ``envs.get_attr(...)`` or ``envs.envs`` would break once wrapped.
_VECTOR_WRAPPER_API = frozenset(
    {
        "reset",
        "step",
        "close",
        "render",
        "seed",  # becomes reset(seed=...) (GM208)
        "action_space",
        "observation_space",
        "single_action_space",
        "single_observation_space",
        "num_envs",
        "metadata",
        "render_mode",
        "spec",
        "unwrapped",
        "np_random",
        "closed",
        "env",
    }
)
# Keys the legacy vector envs put in infos when a sub-env ended.
FINAL_OBS_KEYS = {"final_observation": "final_obs", "_final_observation": "_final_obs"}
_FINAL_INFO_KEYS = ("final_info", "_final_info")
_TERMINAL_KEYS = ("terminal_observation", "_terminal_observation")
# The one question every legacy-autoreset item of a file asks (``Plan.ask_once``): how this
# code meets Gymnasium's next-step autoreset.
_AUTORESET = ("GM706", "autoreset")
_POSITIONAL_CONSUMERS = ("enumerate", "zip", "len", "list", "tuple", "iter", "sorted", "reversed")


@dataclass
class InfosReaders:
    """How the ``infos`` of one step call are read."""

    positional: list[ast.AST] = field(default_factory=list)  # infos[i], for info in infos
    keyed: list[ast.AST] = field(default_factory=list)  # infos["k"], "k" in infos
    final_obs: list[ast.Constant] = field(default_factory=list)
    final_info: list[ast.AST] = field(default_factory=list)
    terminal: list[ast.AST] = field(default_factory=list)
    key_strings: list[ast.AST] = field(default_factory=list)  # every key literal seen


class Infos(VectorFamilyBase):
    """GM705 and GM706, mixed into the vector family."""

    def plan_infos(self, handled: set[int]) -> None:
        """Group the step calls by the env that made them, then decide per env."""
        by_creation: dict[int, list[InfosReaders]] = defaultdict(list)
        creations: dict[int, ast.Call | None] = {}
        counted: set[int] = set()  # readers whose key strings are in ``handled``
        untraced: dict[int, tuple[str, Hashable | None]] = {}  # receiver text and question, by key
        for step, infos in self._step_assigns():
            func = step.func
            if not isinstance(func, ast.Attribute):  # ``x.step(...)`` calls only
                continue
            receiver = func.value
            kind = self.receivers.kind_of(receiver)
            decision = decide(kind, receiver, self.context.profile, legacy_shape=True, expected=EnvKind.GYM_VEC, origins=self.receivers)
            if decision.action is Action.LEAVE:
                continue
            readers = self._readers(infos)
            if decision.action is not Action.REWRITE and not self._vector_evidence(step, readers):
                # Not shown to be a vector env and nothing says it is one: a list of infos
                # (per-agent infos of a multi-agent env, another library's VecEnv) never
                # changed shape. Whether it is a Gym env at all is asked at its step or reset.
                continue
            if id(readers) not in counted:
                counted.add(id(readers))
                handled.update(id(node) for node in readers.key_strings)
            creation = self._direct_creation(receiver) if decision.action is Action.REWRITE else None
            # Steps whose creation is unknown are decided one by one; steps that share their
            # infos bindings share their readers, and one decision covers them all.
            key = id(creation) if creation is not None else id(readers)
            creations[key] = creation
            if decision.action is not Action.REWRITE:
                # Not shown to be a Gym vector env (a project's own VectorEnv keeps its list of
                # infos): the read is a question only if it is one, which its step or reset
                # asks already; the read joins that question rather than ask again.
                untraced[key] = (full_name(receiver) or self.facts.segment(receiver), self.receiver_question(receiver, decision))
            if not any(use is readers for use in by_creation[key]):
                by_creation[key].append(readers)
        for key, uses in by_creation.items():
            self._plan_creation(creations[key], uses, untraced.get(key))

    def _vector_evidence(self, step: ast.Call, readers: InfosReaders) -> bool:
        """An untraced receiver that says it is a vector env: a plural name (``envs``), a
        ``dones`` target, or infos read for the keys only vector envs set."""
        assign = cast(ast.Assign, self.facts.parent(step))
        target = cast(ast.Tuple, assign.targets[0])
        if readers.final_obs or readers.final_info or readers.terminal:
            return True
        return looks_vectorised(cast(ast.Attribute, step.func).value, target.elts[2])

    def _step_assigns(self) -> list[tuple[ast.Call, ast.Name]]:
        """``obs, rewards, dones, infos = x.step(a)`` (four or five names): the step and its infos name."""
        found = []
        for step in self.facts.attribute_calls.get("step", []):
            assign = self.facts.parent(step)
            if not (isinstance(assign, ast.Assign) and assign.value is step and len(assign.targets) == 1):
                continue
            target = assign.targets[0]
            if isinstance(target, (ast.Tuple, ast.List)) and len(target.elts) in (4, 5):
                last = target.elts[-1]
                if isinstance(last, ast.Name):
                    found.append((step, last))
        return found

    def _reads_of(self, binding: ast.Name) -> list[ast.Name]:
        """The reads of a name that may see this binding (in its scope and nested ones).

        Bindings of one name in one scope are seen by the same reads (the facts are
        flow-insensitive), so the reads are grouped once by the bindings they see.
        """
        index = self.facts.memo(("vector-reads-by-bindings", 0), self._reads_by_bindings)
        seen = self.facts.resolve(binding.id, self.facts.scope_of(binding))[1]
        return index.get(id(seen), [])

    def _reads_by_bindings(self) -> dict[int, list[ast.Name]]:
        index: dict[int, list[ast.Name]] = defaultdict(list)
        for scope in self.facts.scopes.values():
            for reads in scope.reads.values():
                for read in reads:
                    bindings = self.facts.bindings_of(read)
                    if bindings:  # (an unbound name's empty list is a fresh object each time)
                        index[id(bindings)].append(read)
        return index

    def _direct_creation(self, receiver: ast.AST) -> ast.Call | None:
        """The vector creation call, if ``receiver`` is bound exactly once, straight to it."""
        found = self.finder.find(receiver)
        if not found.found or len(found.calls) != 1 or not isinstance(receiver, ast.Name):
            return None
        call = found.calls[0]
        bindings = self.facts.bindings_of(receiver)
        if len(bindings) != 1 or not isinstance(bindings[0], ast.Name):
            return None
        assign = self.facts.parent(bindings[0])
        if not (isinstance(assign, ast.Assign) and assign.value is call):
            return None
        self.decisions.wrapper_safe[id(call)] = all(self._wrapper_keeps(read) for read in self._reads_of(bindings[0]))
        return call

    def _wrapper_keeps(self, use: ast.AST) -> bool:
        """Does ``envs.<attr>`` still work once ``envs`` is a VectorWrapper (which forwards nothing)?"""
        parent = self.facts.parent(use)
        if isinstance(parent, ast.Attribute) and parent.value is use:
            return parent.attr in _VECTOR_WRAPPER_API
        return True

    def _plan_creation(
        self, creation: ast.Call | None, uses: list[InfosReaders], untraced: tuple[str, Hashable | None] | None = None
    ) -> None:
        positional = [n for r in uses for n in r.positional]
        keyed = [n for r in uses for n in r.keyed]
        final_obs = [n for r in uses for n in r.final_obs]
        final_info = [n for r in uses for n in r.final_info]
        terminal = [n for r in uses for n in r.terminal]
        wrapper_safe = self.decisions.wrapper_safe
        lists_already = creation is not None and self._creates_list_infos(creation)
        if positional and not lists_already:
            if (
                creation is not None
                and not keyed
                and not final_obs
                and not final_info
                and self._can_edit(creation)
                and wrapper_safe.get(id(creation), False)
            ):
                self.decisions.list_infos[id(creation)] = creation
                infos_names = ", ".join(sorted({f"`{self._infos_name(n)}`" for n in positional}))
                self.report(
                    creation,
                    "GM705",
                    f"vector infos are a dict of arrays in Gymnasium: wrapped the env in DictInfoToList so the "
                    f"list-style reads of {infos_names} still get one dict per sub-env",
                    tier=Tier.NOTE,  # the wrapper gives the legacy lists back exactly: nothing to decide
                )
            else:
                caveat = ""
                if creation is not None and not wrapper_safe.get(id(creation), True):
                    caveat = " (not done here: the env is also used through methods the wrapper does not forward)"
                condition, question = (f"if `{untraced[0]}` is a Gym vector env, its ", untraced[1]) if untraced else ("", None)
                for node in positional:
                    self.report(
                        node,
                        "GM705",
                        f"{condition or 'vector '}infos are one dict of arrays with `_key` masks, so this list-style read breaks "
                        "(iterating gives keys): wrap the env in gymnasium.wrappers.vector.DictInfoToList"
                        f'{caveat} or read infos["k"][i] where infos["_k"][i]',
                        FixKind.FLAG,
                        question=question,
                    )
        same_step = bool(final_obs) and creation is not None and self._can_set_autoreset(creation)
        if same_step and creation is not None:  # ``same_step`` already implies a creation
            self.decisions.autoreset[id(creation)] = creation
            creator = self.facts.segment(creation.func)
            for node in final_obs:
                old = cast(str, node.value)  # ``_keyed`` keeps only the strings in FINAL_OBS_KEYS
                new = FINAL_OBS_KEYS[old]
                self.plan.replace(node, lambda string, new=new: _renamed(string, new))
                self.report(
                    node,
                    "GM706",
                    f'Gymnasium resets sub-envs on the next step by default: the {creator}(...) env now uses '
                    f'autoreset_mode=SAME_STEP, which keeps the legacy timing, and "{old}" is "{new}"',
                )
        elif creation is not None and self.context.profile.imports_gym:
            # Every legacy vector env reset a finished sub-env inside the same step. Neither
            # Gymnasium mode is that: NEXT_STEP adds a step, SAME_STEP moves the ending step's
            # info (``"episode"``...) into infos["final_info"]. The final_info/terminal readers'
            # items ask the same question: the file's review list asks it once.
            self.report(
                creation,
                "GM706",
                "legacy vector envs reset a finished sub-env within the same step; Gymnasium's default returns the "
                "final observation and resets on the next step, which ignores its action and returns reward 0 (one "
                "extra transition per episode in code that stores every step): skip that step (mask it with the "
                "previous step's `terminations | truncations`), or create the env with "
                'autoreset_mode=AutoresetMode.SAME_STEP (the ending step\'s info is then in infos["final_info"])',
                FixKind.FLAG,
                question=_AUTORESET,
            )
        if not same_step:
            for node in final_obs:
                self.report(
                    node,
                    "GM706",
                    "Gymnasium 1.x has no final_observation: by default the final obs is in obs and the sub-env resets "
                    'on the next step; create the env with autoreset_mode=AutoresetMode.SAME_STEP and read "final_obs"',
                    FixKind.FLAG,
                    question=_AUTORESET,
                )
        for node in final_info:
            hint = "with SAME_STEP autoreset" if same_step else "with autoreset_mode=SAME_STEP (the default NEXT_STEP has none)"
            self.report(
                node,
                "GM706",
                f'infos["final_info"] exists only {hint} and is now a dict of arrays with a "_final_info" mask, not '
                "an array of per-env dicts: rewrite this reader",
                FixKind.FLAG,
                question=_AUTORESET,
            )
        for node in terminal:
            self.report(
                node,
                "GM706",
                "terminal_observation (gym 0.22-0.24) is gone: with the default NEXT_STEP autoreset the final obs is in "
                'obs itself; with autoreset_mode=SAME_STEP read infos["final_obs"][i] where infos["_final_obs"][i]',
                FixKind.FLAG,
                question=_AUTORESET,
            )

    def _creates_list_infos(self, creation: ast.Call) -> bool:
        return any(r.rsplit(".", 1)[-1] in LIST_INFO_WRAPPERS for r in gym_rest(self.facts, creation.func))

    def _can_edit(self, creation: ast.Call) -> bool:
        return id(creation) in self.decisions.vector_makes or bool(
            gym_rest(self.facts, creation.func) & (N.GYM_VEC_FACTORIES | VECTOR_CLASSES)
        )

    def _can_set_autoreset(self, creation: ast.Call) -> bool:
        rests = gym_rest(self.facts, creation.func)
        if id(creation) in self.decisions.vector_makes:
            return keyword(creation, "autoreset_mode") is None
        if "make_vec" in rests:
            existing = keyword(creation, "vector_kwargs")
            if existing is None:
                return True
            value = existing.value
            return isinstance(value, ast.Dict) and not any(string_value(k) == "autoreset_mode" for k in value.keys)
        if rests & VECTOR_CLASSES:
            return keyword(creation, "autoreset_mode") is None and not any(isinstance(a, ast.Starred) for a in creation.args) and not any(
                kw.arg is None for kw in creation.keywords
            )
        return False

    # -- readers of infos ---------------------------------------------------------------------

    def _readers(self, infos: ast.Name) -> InfosReaders:
        seen = self.facts.resolve(infos.id, self.facts.scope_of(infos))[1]
        return self.facts.memo(("vector-infos-readers", id(seen)), lambda: self._classify_reads(infos))

    def _classify_reads(self, infos: ast.Name) -> InfosReaders:
        readers = InfosReaders()
        for read in self._reads_of(infos):
            self._classify_read(read, readers)
        return readers

    def _classify_read(self, node: ast.Name, readers: InfosReaders) -> None:
        facts = self.facts
        parent = facts.parent(node)
        if isinstance(parent, (ast.For, ast.AsyncFor, ast.comprehension)) and parent.iter is node:
            readers.positional.append(node)
        elif isinstance(parent, ast.Subscript) and parent.value is node:
            if _written(parent, facts.parent(parent)):
                # ``info["terminal_observation"] = obs``: the code sets the key for its own
                # readers (a worker of its own VecEnv); no Gym env's key is read here.
                return
            key = _subscript_key(parent)
            if key is None:
                outer = facts.parent(parent)
                outer_key = _subscript_key(outer) if isinstance(outer, ast.Subscript) and outer.value is parent else None
                if isinstance(outer, ast.Subscript) and (
                    outer_key in _TERMINAL_KEYS or outer_key in _FINAL_INFO_KEYS or outer_key in FINAL_OBS_KEYS
                ):
                    # ``infos[i]["terminal_observation"]``: the list form of gym 0.22-0.23
                    readers.terminal.append(outer)
                    readers.key_strings.append(outer.slice)
                else:
                    readers.positional.append(parent)
            else:
                self._keyed(parent, key, parent.slice, readers)
        elif isinstance(parent, (ast.Call, ast.keyword)):
            call = parent if isinstance(parent, ast.Call) else facts.parent(parent)
            if isinstance(call, ast.Call) and call.func is not node:
                if isinstance(call.func, ast.Name) and call.func.id in _POSITIONAL_CONSUMERS:
                    readers.positional.append(call)
        elif isinstance(parent, ast.Compare) and node in parent.comparators:
            operator = parent.ops[parent.comparators.index(node)]
            if isinstance(operator, (ast.In, ast.NotIn)):
                key = string_value(parent.left)
                if key is not None:
                    self._keyed(parent, key, parent.left, readers, presence=True)
        elif isinstance(parent, ast.Attribute) and parent.value is node and parent.attr in ("get", "pop"):
            call = facts.parent(parent)
            if isinstance(call, ast.Call) and call.func is parent:
                arguments = arguments_in_order(call)
                if arguments:
                    first = argument_value(arguments[0])
                    key = string_value(first)
                    if key is not None:
                        self._keyed(call, key, first, readers)

    def _keyed(self, node: ast.AST, key: str, string: ast.expr | None, readers: InfosReaders, presence: bool = False) -> None:
        """``string`` is the literal ``key`` was read from (a Constant), if any."""
        if string is not None:
            readers.key_strings.append(string)
        if presence and key in _FINAL_INFO_KEYS:
            return  # ``"final_info" in infos`` still works; the reads below it are what break
        if key in FINAL_OBS_KEYS and isinstance(string, ast.Constant):
            readers.final_obs.append(string)
        elif key in _FINAL_INFO_KEYS:
            readers.final_info.append(node)
        elif key in _TERMINAL_KEYS:
            readers.terminal.append(node)
        else:
            readers.keyed.append(node)

    def _infos_name(self, reader: ast.AST) -> str:
        """The infos variable a list-style read uses (``infos`` in ``infos[i]`` or ``enumerate(infos)``)."""
        if isinstance(reader, ast.Name):
            return reader.id
        if isinstance(reader, ast.Subscript):
            return self.facts.segment(reader.value)
        if isinstance(reader, ast.Call):
            values = map(argument_value, arguments_in_order(reader))
            return next((value.id for value in values if isinstance(value, ast.Name)), "infos")
        return "infos"

    # -- keys read off something else ---------------------------------------------------------

    def flag_stray_final_keys(self, handled: set[int]) -> None:
        """``final_observation`` read off something that is not traced to a step (e.g. a loop variable)."""
        if self.context.profile.imports_sb3 or not self.context.profile.imports_gym:
            return  # SB3 VecEnvs keep terminal_observation (SB104); Gymnasium-era files keep their keys
        for string in self.facts.strings:
            key = string.value
            if key not in ("terminal_observation", "final_observation", "final_info") or id(string) in handled:
                continue
            if not self._reads_a_key(string):
                continue
            self.report(
                string,
                "GM706",
                f'"{key}" comes from legacy vector autoreset: Gymnasium 1.x resets sub-envs on the next step and has no '
                'such key (with autoreset_mode=SAME_STEP: "final_obs"/"final_info", dicts of arrays); rewrite this reader',
                FixKind.FLAG,
                question=_AUTORESET,
            )

    def _reads_a_key(self, string: ast.Constant) -> bool:
        """``x["k"]``, ``"k" in x``, ``x.get("k")``: the string is used as a dict key."""
        parent = self.facts.parent(string)
        if isinstance(parent, ast.Subscript):
            return parent.slice is string and not isinstance(parent.ctx, ast.Store)
        if isinstance(parent, ast.Compare):
            return parent.left is string
        if isinstance(parent, ast.Call):
            func = parent.func
            arguments = arguments_in_order(parent)
            return isinstance(func, ast.Attribute) and func.attr in ("get", "pop") and bool(arguments) and arguments[0] is string
        return False


def _written(subscript: ast.Subscript, outer: ast.AST | None) -> bool:
    """``x["k"] = v`` or ``x[i]["k"] = v``: a store into the dict, which reads no key."""
    if isinstance(subscript.ctx, ast.Store):
        return True
    return isinstance(outer, ast.Subscript) and outer.value is subscript and isinstance(outer.ctx, ast.Store)


def _subscript_key(subscript: ast.AST | None) -> str | None:
    if not isinstance(subscript, ast.Subscript):
        return None
    return string_value(subscript.slice)


def _renamed(node, value: str):
    return node.with_changes(value=f"{node.prefix}{node.quote}{value}{node.quote}")
