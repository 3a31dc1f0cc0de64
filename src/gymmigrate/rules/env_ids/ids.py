"""Env id strings: retired ids, Atari variants, removed families, plugin registration.

* GM803 retired ids are bumped to the id Gymnasium 1.4 registers (``catalog.RETIRED_IDS``).
  Only strings in an env-id position are touched: the id argument of ``make`` /
  ``make_vec`` / ``vector.make`` / ``spec`` / the legacy registry methods / SB3's
  ``make_vec_env`` and ``make_atari_env``, a constant that is only ever assigned one
  literal and is passed there, and the ``default=`` of an ``--env...`` argparse option.
  Gymnasium raises ``DeprecatedEnv`` for every retired id.
* GM804 Atari ids removed in ale-py 0.11.1 (``*Deterministic*``, ``*-ram*``) become the
  base id plus ``frameskip=`` / ``obs_type="ram"`` on the call that makes the env; where
  that call cannot take the keywords (``spec``, a constant, one branch of a conditional)
  they are reported instead.
* GM805 ids of removed families (robotics, Striker/Thrower, the unittest envs) are reported.
* GM106 Gymnasium 1.0 removed plugin auto-registration: a module that makes an Atari id
  gets ``import ale_py`` + ``gym.register_envs(ale_py)`` (AUTO; ``register_envs`` keeps
  linters from deleting an import that looks unused); MiniGrid and highway-env ids get
  their package import (ASSIST).

This module decides; ``id_sites.py`` finds the id strings (``IdSites``, with
``handed_on_ids.py`` for those the project's code makes), and
``atari_evidence.py`` tells, where no literal id does, whether the module makes Atari
envs (a built id, a helper that uses what only Atari envs have).
"""

from __future__ import annotations

import ast
import os

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.handovers import handovers
from gymmigrate.facts.import_guards import catches_import_error
from gymmigrate.facts.module import walk
from gymmigrate.facts.summaries import loads_saved_state, registered_ids
from gymmigrate.findings import FixKind, Tier, gym_only_question, id_version_question
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.env_ids.atari_evidence import AtariEvidence
from gymmigrate.rules.env_ids.catalog import (
    ALE,
    GYM_ONLY_PREFIXES,
    EnvPackage,
    IdMigration,
    env_package,
    migration_for,
    plugin_of,
    removed_family,
)
from gymmigrate.rules.env_ids.id_literals import IdSite, imported_modules
from gymmigrate.rules.env_ids.id_sites import IdSites
from gymmigrate.rules.env_ids.syntax import gym_alias

RULES = (
    Rule(
        "GM106",
        "register third-party env packages",
        FixKind.ASSIST,
        "Atari ids get `import ale_py` + `gym.register_envs(ale_py)`; MiniGrid/highway ids get their package import.",
    ),
    Rule("GM803", "retired env ids", FixKind.AUTO, "Retired env ids are bumped to the version Gymnasium 1.4 registers.", once_per_run=True),
    Rule(
        "GM804",
        "Atari ids",
        FixKind.ASSIST,
        "Removed `*Deterministic*` / `*-ram*` Atari ids become the base id plus keywords; `info[\"ale.lives\"]` reads `\"lives\"`.",
        once_per_run=True,
    ),
    Rule("GM805", "removed env families", FixKind.FLAG, "Ids of env families Gymnasium removed are reported.", once_per_run=True),
)

# ``notes.gymnasium_imported`` is set when the registration block imports ``gymnasium`` itself, so the
# registry family does not import it a second time.

_ALE_LIVES = "ale.lives"
# ``Atari``/``atari``: a class, def or helper named for Atari (``atari_evidence._named_for_atari``)
_ATARI_WORDS = (_ALE_LIVES, ".ale", "NoFrameskip", "get_action_meanings", "Atari", "atari")


class EnvIds(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        # ids, gym's Atari info key, and what only an Atari env has (``_atari_helper``), here
        # or in a def or class of another module of the run this one imports
        if "-v" in facts.text or any(sign in facts.text for sign in _ATARI_WORDS):
            return True
        if any(f"{package}:" in facts.text for package in GYM_ONLY_PREFIXES):
            return True  # ``"dm2gym:" + name``: an id of a Gym-only package built here
        project = context.options.project
        if project is None or "make" not in facts.text:
            return False
        view = project.view(context.path)
        return any(view.uses_atari(q) for q in facts.imports.values())

    def decide(self) -> None:
        if self.notes.gym_kept_for is not None:
            return  # the file stays on gym with the library its envs go to: gym registers its ids
        self._rename_lives_key()
        self._planned: set[ast.Constant] = set()
        self._new_keywords: dict[ast.Call, list[tuple[str, str]]] = {}
        # package module -> (package, the first id string that needs it, and for a helper
        # known only by what it does with its env, the message and kind that say why)
        self._packages: dict[str, tuple[EnvPackage, ast.expr, tuple[str, FixKind] | None]] = {}
        # package module -> where this module makes its envs (a make call, else the id literal
        # handed on): the registration goes there
        self._made: dict[str, list[ast.AST]] = {}
        # the makes the evidence leaves open (``may make Atari envs``): other ids reach them too
        self._other_ids_too: set[int] = set()
        self._bumped: dict[str, tuple[str, ast.Constant]] = {}  # old id -> new id, the first site bumped
        sites = IdSites(self.facts, self.receivers)
        found = sites.find()
        # the Atari signs of the reads ``find`` noted, in its order: the first one decides
        # what the ale_py registration says; every make with one needs the registration
        atari = AtariEvidence(self.facts, self.receivers, sites.literal_of)
        for call, value in sites.atari_reads:
            if call is None:
                evidence = atari.formatted_id(value)
            else:
                assert isinstance(value, (ast.Name, ast.Attribute, ast.Subscript))
                evidence = atari.helper(call, value)
            if evidence is not None:
                node, message, kind = evidence
                if ALE.module not in self._packages:
                    self._packages[ALE.module] = (ALE, node, (message, kind))
                made = call if call is not None else value
                self._made.setdefault(ALE.module, []).append(made)
                if kind is not FixKind.AUTO:
                    self._other_ids_too.add(id(made))
        for site in found:
            self._decide_site(site)
        for literal, text in sites.built_prefixes:
            self._ask_gym_only_prefix(literal, text.split(":", 1)[0], f"`{text}` + ...")
        self._bump_comparisons()
        self._ask_stray_ids()
        for call, keywords in self._new_keywords.items():
            self.plan.replace(call, lambda node, keywords=keywords: _append_keywords(node, keywords))
        self._decide_registration()

    def _rename_lives_key(self) -> None:
        """``info["ale.lives"]`` (``info.get("ale.lives")``): gym's AtariEnv named the key so;
        ale-py's envs, which Gymnasium's Atari ids make, call it ``"lives"`` (KeyError now)."""
        if _ALE_LIVES not in self.facts.text or not self.context.profile.imports_gym:
            return
        for node in self.facts.strings:
            if node.value != _ALE_LIVES:
                continue
            parent = self.facts.parent(node)
            keyed = isinstance(parent, ast.Subscript) and parent.slice is node
            got = (
                isinstance(parent, ast.Call)
                and isinstance(parent.func, ast.Attribute)
                and parent.func.attr in ("get", "pop")
                and parent.args[:1] == [node]
            )
            classdef = self.facts.enclosing_class(node)
            if classdef is not None and self.receivers.wraps_vec_env(classdef):
                continue  # the infos of the VecEnv the class wraps, left with the class (GM602)
            if keyed or got:
                self.plan.replace(node, lambda cst_node: _with_string_value(cst_node, "lives"))
                self.report(node, "GM804", '"ale.lives" -> "lives": ale-py\'s Atari envs name the info key so', FixKind.AUTO)

    def _decide_site(self, site: IdSite) -> None:
        if site.string in self._planned:  # a constant passed to several calls
            return
        self._planned.add(site.string)
        if site.report_only:
            package = env_package(site.env_id)
            self.report(
                site.string,
                "GM106",
                f"`{site.env_id}` ({site.via}) is handed to code elsewhere that makes the env: since Gymnasium 1.0 that "
                f"module (or this one) must `import {package.module}` and call `gymnasium.register_envs({package.module})`"
                if package is not None
                else f"`{site.env_id}` ({site.via}) is handed to code elsewhere that makes the env",
                kind=FixKind.FLAG,
            )
            return
        if site.untraced:
            self._ask_untraced(site)
            return
        prefix = site.module_prefix[:-1]
        if prefix in GYM_ONLY_PREFIXES and removed_family(site.env_id) is None:
            self._ask_gym_only_prefix(site.string, prefix, f"`{site.module_prefix}{site.env_id}`")
            return
        migration = migration_for(site.env_id)
        if migration is not None:
            self._decide_migration(site, migration)
        hint = removed_family(site.env_id)
        if hint is not None:
            plugin = plugin_of(site.env_id)
            # The import of the plugin package asks the same question (GM107): the file's
            # review list asks it once, at the first of them; where the import's item is
            # silenced (a noqa comment naming GM107 on ``import pybullet_envs``), the id's site asks it.
            question = gym_only_question(N.gym_only_stack(plugin)) if plugin is not None else None
            if self._registered_by_run(site.env_id):
                # The project registers this id for a class of its own: the id resolves under
                # Gymnasium as it did under gym. What may remain is that class's dependency on
                # the plugin package whose ids share the name; without one, nothing to decide.
                if plugin is not None:
                    reason = hint.partition(":")[0]
                    self.report(
                        site.string,
                        "GM805",
                        f"`{site.env_id}` is registered by this project (a register() call of the run), so the id stays; "
                        f"the decision is the registered env's dependency on {plugin}: {reason}; replace what it uses of "
                        f"{plugin}, or keep that env on legacy gym",
                        question=question,
                    )
            else:
                self.report(site.string, "GM805", f"`{site.env_id}` no longer exists: {hint}", question=question)
        final_id = migration.new_id if migration is not None else site.env_id
        package = env_package(final_id)
        if package is not None and not site.module_prefix:
            if package.module not in self._packages:
                self._packages[package.module] = (package, site.string, None)
            made = site.call or site.made_at or site.string
            self._made.setdefault(package.module, []).append(made)
            if site.command_line_default:
                # only a default: the command line may name any other id, whose env needs no
                # such package, as it needed no atari-py on gym
                self._other_ids_too.add(id(made))

    def _ask_gym_only_prefix(self, string: ast.Constant, package: str, spelled: str) -> None:
        """``gym.make("dm2gym:" + name)``: make imports the package of the prefix, which
        registers its envs with gym only; the id resolves under Gymnasium whatever follows."""
        hint = GYM_ONLY_PREFIXES.get(package)
        if hint is None or string in self._planned:
            return
        self._planned.add(string)
        self.report(
            string,
            "GM805",
            f"{spelled}: the `{package}:` prefix makes the env with {package}, not with Gymnasium: {hint}",
            kind=FixKind.FLAG,
            question=gym_only_question(N.gym_only_stack(package)),
        )

    def _registered_by_run(self, env_id: str) -> bool:
        """The run registers this very id (a literal ``register(id=...)`` in one of its modules)."""
        project = self.context.options.project
        if project is not None:
            return env_id in project.registered_ids
        return env_id in self.facts.memo(("registered-ids", 0), lambda: registered_ids(self.facts))

    def _ask_untraced(self, site: IdSite) -> None:
        """A retired id whose way to a make the run could not follow: one question, no rewrite."""
        rule, what = _if_made(site.env_id, migration_for(site.env_id))
        question = site.question
        plugin = plugin_of(site.env_id)
        if question is None and plugin is not None:
            # the id of a Gym-only package asks what its import asks (GM107): how that
            # package's envs are ported, once for the run
            question = gym_only_question(N.gym_only_stack(plugin))
        self.report(
            site.string,
            rule,
            f"`{site.env_id}` is {site.via}, which the run could not follow to a make; if it reaches gym.make, {what}",
            kind=FixKind.FLAG,
            question=question,
        )

    def _decide_migration(self, site: IdSite, migration: IdMigration) -> None:
        old, new = site.env_id, migration.new_id
        where = f" ({site.via})" if site.via else ""
        if migration.kwargs:
            keywords = ", ".join(f"{k}={v}" for k, v in migration.kwargs)
            taken = {kw.arg for kw in site.call.keywords if kw.arg is not None} if site.call else set()
            clash = [k for k, _ in migration.kwargs if k in taken]
            if not site.forwards_kwargs or clash or site.call is None or site.conditional:
                if clash:
                    why = f"the call already passes {', '.join(clash)}"
                elif site.via and not site.keywords_at_call:
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
            planned = self._new_keywords.setdefault(site.call, [])
            planned.extend(k for k in migration.kwargs if k not in planned)
            new_text = f"`{new}` with {keywords}"
        else:
            new_text = f"`{new}`"
        new_value = site.module_prefix + new
        self.plan.replace(site.string, lambda node: _with_string_value(node, new_value))
        if not migration.kwargs and not site.module_prefix:
            self._bumped.setdefault(old, (new, site.string))
        # A new version is a question for a program that loads what an earlier run saved
        # (a policy, a normaliser); one that trains from scratch just gets the current env.
        # The run is the program: an evaluation script of the run may load, through a class or
        # task of this module, a model trained on the old version.
        # Only a module that imports this one (directly or through others) can load a model
        # into its classes or tasks: a load elsewhere in the run is another program's.
        # A script with no def or class, whose make takes the literal itself, offers another
        # module no class or task to load through: only its own loads count.
        project = self.context.options.project
        standalone = self._standalone_make(site)
        reached = project is not None and os.path.realpath(self.context.path) in project.load_reach
        run_loads = reached and not standalone
        settled = migration.kind is FixKind.ASSIST and not run_loads and not loads_saved_state(self.facts.tree)
        here = "in the run" if project is not None and not standalone else "here"
        if standalone and project is not None and project.loads_saved_state:
            here = "in this script, which has no def or class another module could load one through,"
        elif project is not None and project.loads_saved_state and not standalone:
            here = "here or in a module that imports this one"
        self.report(
            site.string,
            migration.rule,
            f"`{old}` -> {new_text}{where}: {migration.reason}" + (f"; nothing {here} loads a saved model" if settled else ""),
            kind=migration.kind,
            tier=Tier.NOTE if settled else None,
            # the same change at several places of the run (several ids of one family of
            # envs, one id in several notebook cells or scripts) is one decision
            question=None if settled or migration.kind is FixKind.AUTO else id_version_question(migration.rule, migration.reason),
        )

    def _standalone_make(self, site: IdSite) -> bool:
        """``env = gym.make("LunarLander-v2")`` in a module that defines no def or class: the
        id is made right there, in a script no other module uses for its envs."""
        if site.call is None or not any(arg is site.string for arg in site.call.args):
            return False
        return not any(isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda)) for node in walk(self.facts.tree))

    def _bump_comparisons(self) -> None:
        """``if self.env_name == 'LunarLander-v2':`` where this module bumps that id: the test
        would never hold again, so the compared string moves with the id."""
        if not self._bumped:
            return
        for node in self.facts.strings:
            if node in self._planned or node.value not in self._bumped:
                continue
            compare = self.facts.parent(node)
            if isinstance(compare, (ast.List, ast.Tuple, ast.Set)):  # ``env_id in ('A-v2', 'B-v2')``
                compare = self.facts.parent(compare)
            if not (isinstance(compare, ast.Compare) and all(isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)) for op in compare.ops)):
                continue
            new, first = self._bumped[node.value]
            self._planned.add(node)
            self.plan.replace(node, lambda cst_node, new=new: _with_string_value(cst_node, new))
            self.report(
                node,
                "GM803",
                f"`{node.value}` -> `{new}` in a comparison: the id is bumped at line {first.lineno}, so the test moves with it",
                kind=FixKind.AUTO,
            )

    def _ask_stray_ids(self) -> None:
        """A literal that is exactly a Gym id Gymnasium retired or removed, which no id site
        of the module holds, where a program keeps ids as data: compared (``name ==
        "Pendulum-v0"``, ``name not in ["LunarLander-v2", ...]``) or in a table or constant
        (``CONFIGS = [["dqn", "atari", "PongDeterministic-v4"], ...]``). The run did not see
        it reach a make, so nothing is rewritten (a comparison moves only with an id this
        module bumps, ``_bump_comparisons``); it is asked, in a module that uses legacy gym,
        or a module of a run that imports no Gym at all (its configuration). A module on
        Gymnasium already keeps such a string as a label. An id in a message, a path, a
        dict key or a call's argument is left, and so is one handed only to calls that
        reach no make (printed, dumped): it names an env, it does not choose one."""
        if "-v" not in self.facts.text:
            return
        profile = self.context.profile
        if profile.imports_gymnasium or not (profile.imports_gym or self.context.options.project is not None):
            return
        for node in self.facts.strings:
            if node in self._planned or not isinstance(node.value, str):
                continue
            migration = migration_for(node.value)
            hint = removed_family(node.value) if migration is None else None
            if migration is None and hint is None:
                continue
            held = self._held_as_data(node)
            if held is None or (held != "compared" and handovers(self.facts, self.receivers, node)):
                continue  # a table's item handed on: ``_retired_ids_passed_along`` followed it to no make
            self._planned.add(node)
            rule, what = _if_made(node.value, migration)
            plugin = plugin_of(node.value)
            if held == "compared":
                message = (
                    f"`{node.value}` is compared here, and no make of this module bumps it: {what}; "
                    "keep the test in step with the ids the program makes now"
                )
            else:
                message = f"`{node.value}` is {held}, which the run could not follow to a make; if it reaches gym.make, {what}"
            # the ids one function compares, or one table holds, are one decision: which ids the
            # program makes now
            where = self.facts.enclosing_function(node) if held == "compared" else self.facts.statement_of(node)
            question: tuple[object, ...] = ("retired ids kept as data", held, getattr(where, "lineno", 0))
            if plugin is not None:
                question = gym_only_question(N.gym_only_stack(plugin))
            self.report(node, rule, message, kind=FixKind.FLAG, question=question)

    def _held_as_data(self, node: ast.Constant) -> str | None:
        """How a string literal is kept as data, or None: "compared" (an operand of ``==``,
        ``!=``, ``in``, ``not in``, or an item of the collection tested), "an item of a
        table" (a list, tuple or set literal, or a dict's value, stored or returned), "a
        constant" (a name or attribute assigned it)."""
        child: ast.AST = node
        parent = self.facts.parent(node)
        item = False
        while isinstance(parent, (ast.List, ast.Tuple, ast.Set)) or (isinstance(parent, ast.Dict) and child in parent.values):
            item = True
            child, parent = parent, self.facts.parent(parent)
        if isinstance(parent, ast.Compare):
            if all(isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)) for op in parent.ops):
                return "compared"
            return None
        if isinstance(parent, (ast.Assign, ast.AnnAssign, ast.Return)) and getattr(parent, "value", None) is child:
            return "an item of a table" if item else "a constant"
        return None

    def _decide_registration(self) -> None:
        """The registration goes where the envs are made: into each function that makes
        them, right before the make, so a module whose makes run only when its functions
        are called still imports where the package is not installed (ale-py is often an
        optional extra); at module level only when an env is made at import time (or the
        id is handed on from there). Where the makes are deferred but no function can
        hold the lines (a lambda in a module-level table), module level under
        ``try``/``except ImportError``."""
        if not self._packages:
            return
        imported = imported_modules(self.facts.tree, self.facts)
        # gym itself is an optional import here (``try: import gym / except ImportError``):
        # its guard already keeps the module importable, and the registration joins it
        optional_gym = gym_alias(self.facts) is None and _guarded_gym_import(self.facts.tree.body) is not None
        at_top: list[str] = []
        guarded: list[str] = []
        optional: list[str] = []
        in_functions: list[tuple[str, list[ast.stmt], bool]] = []
        for package, string, why in self._packages.values():
            if package.module in imported:
                continue
            if package.legacy_module and package.legacy_module in imported:
                continue  # the gym-era package: GM112 renames its import or reports it
            made = self._made.get(package.module) or [string]
            statements, deferred = ([], False) if optional_gym else self._where_made(made)
            makers = sorted({f"`{self.facts.enclosing_function(s).name}`" for s in statements})  # type: ignore[union-attr]
            # Where other ids may reach every make too (a parameter, ids of several families), an
            # install without the package must still make those envs, as gym made them without
            # atari-py: the registration is tried, and an Atari id then fails at the make, as it
            # did on gym without atari-py. Nothing is left to decide.
            other_ids_too = not optional_gym and all(id(node) in self._other_ids_too for node in made)
            if why is not None and other_ids_too:
                why = (why[0], FixKind.AUTO)
            if statements:
                in_functions.append((package.module, statements, other_ids_too))
                where = f" in {_listing(makers)}, right before the make, so an install without {package.module} still imports this module"
                if other_ids_too:
                    where = (
                        f" in {_listing(makers)}, right before the make, under `try`/`except ImportError`: other ids may reach "
                        f"it, and their envs need no {package.module}, as they needed no atari-py on gym"
                    )
            elif other_ids_too:
                optional.append(package.module)
                where = (
                    f" under `try`/`except ImportError`: other ids may reach the make, and their envs need no {package.module}, "
                    "as they needed no atari-py on gym"
                )
            elif deferred:
                guarded.append(package.module)
                where = (
                    f" at module level under `try`/`except ImportError`: the envs are made later (in a lambda), so an "
                    f"install without {package.module} still imports this module"
                )
            else:
                at_top.append(package.module)
                where = ""
            if why is None:
                message, kind = _registration_message(package, where), package.kind
            else:
                message, kind = why
                message += where
                if kind is not FixKind.AUTO:
                    # what the evidence leaves open: whether the code there makes these envs
                    message += f": drop it if {_listing(makers, 'or')} never makes these envs" if makers else ": drop it if this module never makes these envs"
            self.report(string, "GM106", message, kind=kind)
        strings = [s for _, s, _ in self._packages.values()]
        for module, statements, tried in in_functions:
            for statement in statements:
                alias, bound = self._gym_name_at(statement)
                lines = [f"import {module}", f"{alias}.register_envs({module})"]
                if not bound:
                    lines.insert(0, "import gymnasium")
                if tried:
                    body = "\n".join(f"    {line}" for line in lines)
                    lines = [f"try:\n{body}\nexcept ImportError:  {_OTHER_IDS_COMMENT}\n    pass"]
                self.plan.insert_before(statement, *lines)
        if at_top:
            self._insert_registration(at_top, strings)
        if guarded:
            self._insert_registration(guarded, strings, guard=True)
        if optional:
            self._insert_registration(optional, strings, guard=True, comment=_OTHER_IDS_COMMENT)

    def _where_made(self, made: list[ast.AST]) -> tuple[list[ast.stmt], bool]:
        """The statements of functions that make the envs (each registration right before
        its make), when every make is in a function; else no statement, and whether the
        makes only run later (in a lambda at module level) rather than at import time."""
        statements: list[ast.stmt] = []
        deferred = False
        for node in made:
            function = self.facts.enclosing_function(node)
            if function is None or self.facts.statement_of(node) is function:
                # at module level (or a default of a def's parameter, evaluated there)
                if self.facts.enclosing(node, ast.Lambda) is None:
                    return [], False
                deferred = True
                continue
            statement = self.facts.statement_of(node)
            parent = self.facts.parent(statement)
            while isinstance(parent, ast.If) and parent.orelse == [statement]:
                statement, parent = parent, self.facts.parent(parent)  # an ``elif``: before its ``if``
            if statement not in statements:
                statements.append(statement)
        if deferred:
            return [], True
        return statements, False

    def _gym_name_at(self, statement: ast.stmt) -> tuple[str, bool]:
        """The name Gymnasium is called by where ``statement`` runs (the module's top-level
        import, else one of the function around it: ``try: import gym`` in ``__init__``),
        and whether it is bound there; else ``gymnasium``, which then needs its import."""
        alias = gym_alias(self.facts)
        if alias is not None:
            return alias, True
        function = self.facts.enclosing_function(statement)
        for node in walk(function) if function is not None else ():
            if isinstance(node, ast.Import) and (node.lineno, node.col_offset) < (statement.lineno, statement.col_offset):
                for name in node.names:
                    if name.name in ("gym", "gymnasium"):
                        return name.asname or name.name, True
        return "gymnasium", False

    def _insert_registration(
        self, packages: list[str], strings: list[ast.expr], guard: bool = False, comment: str = "# the envs that need it are made later; without it they are not found"
    ) -> None:
        """``import ale_py`` after the last top-level import that comes before the first use
        of an id, then a blank line and ``gym.register_envs(ale_py)``; with ``guard``, both
        in a ``try`` whose ``except ImportError`` passes."""
        body = self.facts.tree.body
        first_use = min(body.index(self._top_level_statement(s)) for s in strings)
        alias = gym_alias(self.facts)
        guarded = _guarded_gym_import(body) if alias is None else None
        if guarded is not None:
            # gym is an optional import here (``try: import gym / except ImportError:``, a
            # test module that skips without it): the registration goes into the same guard,
            # so a missing ale_py (or gymnasium) still takes the except branch instead of
            # failing the module's import
            guard_import, alias = guarded
            self.plan.insert_after(guard_import, *[f"import {package}" for package in packages])
            self.plan.insert_after(guard_import, *[f"{alias}.register_envs({package})" for package in packages])
            return
        lines = []
        if alias is None:
            alias = "gymnasium"
            lines.append("import gymnasium")
            self.notes.gymnasium_imported = True
        if guard:
            block = "\n".join(["try:", *[f"    import {p}" for p in packages], *[f"    {alias}.register_envs({p})" for p in packages]])
            lines.append("\n" + block + f"\nexcept ImportError:  {comment}\n    pass")
            calls = []
        else:
            lines += [f"import {package}" for package in packages]
            calls = [f"{alias}.register_envs({package})" for package in packages]
            calls[0] = "\n" + calls[0]
        last_import: ast.stmt | None = next((s for s in reversed(body[:first_use]) if isinstance(s, (ast.Import, ast.ImportFrom))), None)
        binding = _binding_statement(body, alias)
        if binding is not None and (last_import is None or body.index(binding) > body.index(last_import)):
            # the id is written before gym is imported (a constant at the top of a script,
            # a notebook's first cell): the call needs the name bound, and no make runs
            # before the import anyway
            last_import = binding
            following = body[body.index(binding) + 1 :]
            for statement in following:  # and after the imports that follow it
                if not isinstance(statement, (ast.Import, ast.ImportFrom)):
                    break
                last_import = statement
        if last_import is not None:
            self.plan.insert_after(last_import, *lines, *calls)
            return
        # No import before the first use: after a module docstring, else first, with a
        # blank line before the module's own code where its first statement can take one.
        if _is_docstring(body[0]):
            self.plan.insert_after(body[0], *lines, *calls)
            return
        self.plan.insert_before(body[0], *lines, *calls)
        if isinstance(body[0], (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.If, ast.For, ast.While, ast.With, ast.Try)):
            self.plan.replace(body[0], lambda node: node.with_changes(leading_lines=[cst.EmptyLine()]))

    def _top_level_statement(self, node: ast.AST) -> ast.stmt:
        statement = self.facts.statement_of(node)
        tree = self.facts.tree
        while self.facts.parent(statement) is not tree:
            statement = self.facts.statement_of(self.facts.parent(statement))  # type: ignore[arg-type]
        return statement


# Why a registration tried where other ids may reach the make passes on ImportError.
_OTHER_IDS_COMMENT = "# only Atari ids need it, as only they needed atari-py"


def _guarded_gym_import(body: list[ast.stmt]) -> tuple[ast.Import, str] | None:
    """``import gym`` (``import gymnasium as gym``) directly in the body of a top-level ``try``
    one of whose handlers catches ImportError, with the name it binds."""
    for statement in body:
        if not isinstance(statement, ast.Try) or not any(catches_import_error(h) for h in statement.handlers):
            continue
        for inner in statement.body:
            if isinstance(inner, ast.Import):
                for name in inner.names:
                    if name.name in ("gym", "gymnasium"):
                        return inner, name.asname or name.name
    return None


def _binding_statement(body: list[ast.stmt], alias: str) -> ast.stmt | None:
    """The first top-level statement that imports ``alias`` (directly, or in an ``if`` or
    ``try`` at module level), None when the module does not bind it at top level."""
    for statement in body:
        if isinstance(statement, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            continue
        for node in walk(statement):
            if isinstance(node, (ast.Import, ast.ImportFrom)) and any(
                (name.asname or name.name.split(".")[0]) == alias for name in node.names
            ):
                return statement
    return None


def _listing(names: list[str], last: str = "and") -> str:
    return names[0] if len(names) == 1 else f"{', '.join(names[:-1])} {last} {names[-1]}"


def _is_docstring(statement: ast.stmt) -> bool:
    return isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant) and isinstance(statement.value.value, str)


def _if_made(env_id: str, migration: IdMigration | None) -> tuple[str, str]:
    """The rule and the clause saying what ``gym.make`` of a retired id (``migration``) or
    a removed one gives under Gymnasium 1.4, for an id the run could not follow to a make:
    the questions about such ids word it alike wherever the id is held."""
    if migration is not None:
        keywords = ", ".join(f"{k}={v}" for k, v in migration.kwargs)
        target = f"`{migration.new_id}`" + (f" with {keywords}" if keywords else "")
        # a retired id is registered no more (ale-py's removed spellings neither): make refuses
        # it (DeprecatedEnv for an old version, ImportError for MuJoCo's mujoco-py ones,
        # NameNotFound for a retired name) and makes no other env in its place
        return migration.rule, f"Gymnasium 1.4 raises for it and registers {target} in its place ({migration.reason})"
    return "GM805", f"it no longer exists: {removed_family(env_id)}"


def _registration_message(package: EnvPackage, where: str) -> str:
    if package is ALE:
        return f"Atari ids need `import ale_py` since Gymnasium 1.0 removed plugin auto-registration; added it with `register_envs(ale_py)`{where}"
    return (
        f"these ids need `import {package.module}` since Gymnasium 1.0 removed plugin auto-registration; "
        f"added it{where}: check the package is installed and registers the ids on import"
    )


# -- building the new code ------------------------------------------------------------------


def _with_string_value(node: cst.SimpleString, text: str) -> cst.SimpleString:
    return node.with_changes(value=f"{node.prefix}{node.quote}{text}{node.quote}")


def _append_keywords(call: cst.Call, keywords: list[tuple[str, str]]) -> cst.Call:
    """Add ``name=value`` arguments at the end, following the call's comma style."""
    args = list(call.args)
    no_space = cst.SimpleWhitespace("")
    new_args = [
        cst.Arg(keyword=cst.Name(name), value=cst.parse_expression(value), equal=cst.AssignEqual(whitespace_before=no_space, whitespace_after=no_space))
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
