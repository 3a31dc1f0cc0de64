"""The rewrite of import statements: ``import gym[.x] [as y]`` (GM101, GM103) and ``from
gym[.x] import y`` (GM102-GM104, split where its names live in several Gymnasium modules
now), imports of removed things reported (GM105), and gym's Atari class imported only
for class checks moved to ale_py; with the LibCST builds of the new statements."""

from __future__ import annotations

import ast
import builtins
import re

from gymmigrate.edits.lazy import cst
from gymmigrate.edits.syntax import dotted_node
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.module import walk
from gymmigrate.findings import (
    FixKind,
    Tier,
    gym_only_question,
    removed_helper_question,
)
from gymmigrate.rules.gymnasium_api import has_name, module_exists
from gymmigrate.rules.imports.libraries import GYM_ONLY_LIBRARIES, GymOnlyLibraries
from gymmigrate.rules.imports.table import (
    LEGACY_WRAPPER_MODULES,
    MOVED_NAMES,
    RENAMED_NAMES,
    home_of,
    migrated_path,
    removed_module_hint,
    removed_name_hint,
    under_gym,
)

# the gym package named in prose (``gym==0.23``, "install gym"), not gymnasium or gym_foo
_NAMES_GYM = re.compile(r"\bgym\b(?![_-])")
# calls that only show a text to the user: print, a logger's levels, warnings.warn, sys.exit
_SHOWING_CALLS = frozenset({"print", "warn", "warning", "error", "info", "debug", "critical", "exception", "fatal", "exit"})

# Gymnasium 1.4 modules whose ``import *`` raises on a plain install: their ``__all__``
# names the array-conversion wrappers (``JaxToNumpy``, ``ToArray``...), which their
# ``__getattr__`` imports from modules needing the optional ``array_api_compat``.
_STAR_IMPORT_RAISES = frozenset({"gymnasium.wrappers", "gymnasium.wrappers.vector"})
# Names through which a module looks its own names up at run time.
_NAME_LOOKUPS = frozenset({"eval", "exec", "globals", "vars", "locals", "__import__"})
_BUILTINS = frozenset(dir(builtins))


class ImportStatements(GymOnlyLibraries):
    """GM101-GM105 at import statements (mixed into the family)."""

    def _import(self, node: ast.Import, *, guarded: bool) -> None:
        names: list[tuple[str, str | None]] = []  # (module, asname) after the rewrite
        changed = False
        for alias in node.names:
            module = alias.name
            rest = under_gym(module)
            if rest is None:
                names.append((module, alias.asname))
                continue
            self._gym_names.add(alias.asname or module.split(".")[0])
            hint = removed_module_hint(rest)
            if hint:
                self._report_removed(node, f"`{module}` was removed: {hint}", hint)
                names.append((module, alias.asname))
                continue
            library = self._fed_only_to_gym_only_library(node) if rest == "" and not guarded else None
            if library is not None:
                # ``env = bench.Monitor(gym.make(...))`` for baselines: a Gymnasium env would meet
                # baselines' legacy calls (seed(), the four-field step); the file moves with that stack
                self.notes.gym_kept_for = library
                self.report(
                    node,
                    "GM101",
                    f"left on gym: every env this file makes with `{alias.asname or 'gym'}.make` goes to `{library}`, which "
                    f"calls gym's API on it (the obs-only reset, the four-field step); keep the file on gym with it, or port both: "
                    f"{GYM_ONLY_LIBRARIES.get(library, 'it has no Gymnasium release')}",
                    FixKind.FLAG,
                    question=gym_only_question(library),
                )
                names.append((module, alias.asname))
                continue
            changed = True
            if rest == "":
                names.append(("gymnasium", alias.asname or "gym"))
                if guarded:
                    stale, shown_only = self._handler_text_naming_gym(node)
                    if stale is None:
                        # The guard's answer only changes its subject (is gymnasium installed?):
                        # nothing to decide, the line explains the rewrite.
                        self.report(
                            node,
                            "GM101",
                            "import gym -> import gymnasium as gym inside a try/except ImportError: the guard now "
                            "asks whether gymnasium is installed",
                            FixKind.ASSIST,
                            tier=Tier.NOTE,
                        )
                    elif shown_only:
                        # A message the handler raises, prints or logs changes nothing the
                        # program does: worth a line in the notes, not a decision.
                        self.report(
                            node,
                            "GM101",
                            "import gym -> import gymnasium as gym inside a try/except ImportError: the guard now "
                            f"asks whether gymnasium is installed; the message its handler gives at line {stale} still "
                            "names gym (say gymnasium there)",
                            FixKind.ASSIST,
                            tier=Tier.NOTE,
                        )
                    else:
                        self.report(
                            node,
                            "GM101",
                            "import gym -> import gymnasium as gym inside a try/except ImportError: the guard now "
                            f"asks whether gymnasium is installed, but its handler uses a text naming gym at line {stale} "
                            "for more than a message (a command it runs, a value it keeps): make it gymnasium there "
                            "(and drop a gym version pin it asks for)",
                            FixKind.ASSIST,
                        )
                else:
                    self.report(node, "GM101", "import gym -> import gymnasium as gym")
                continue
            new_module = "gymnasium." + migrated_path(rest)
            names.append((new_module, alias.asname))
            self.report(node, "GM103", f"{module} -> {new_module}")
            if alias.asname is None and not self._gym_bound_before(node):
                # ``import gym.spaces`` bound ``gym`` in its scope (a function's own local when
                # the import is inside it); ``import gymnasium.spaces`` binds ``gymnasium``
                # only, so keep that name working in the same scope.
                names.append(("gymnasium", "gym"))
        if changed:
            self.plan.replace(node, lambda import_node: _with_names(import_node, names))

    def _gym_bound_before(self, node: ast.Import) -> bool:
        """Does an earlier import bind ``gym`` wherever ``node`` runs: a statement of the same
        scope before it in its own block or in a block around it (a plain ``import gym``,
        or an ``import gym.x`` that keeps or gets that name)? Another function's import
        binds only that function's local, and one inside an ``if`` does not bind on the
        other path."""
        scope = self.facts.scope_of(node).node
        current: ast.AST = node
        while current is not scope:
            parent = self.facts.parent(current)
            if parent is None:
                return False
            for field in ("body", "orelse", "finalbody", "handlers"):
                block = getattr(parent, field, None)
                if isinstance(block, list) and current in block:
                    for earlier in block[: block.index(current)]:
                        if isinstance(earlier, ast.Import) and any(
                            (alias.asname or alias.name.split(".")[0]) == "gym" and under_gym(alias.name) is not None
                            for alias in earlier.names
                        ):
                            return True
            current = parent
        return False

    def _handler_text_naming_gym(self, node: ast.AST) -> tuple[int | None, bool]:
        """The line of a string in the guard's except handlers that names the gym package
        (``"pip install gym==0.23"``): after the rewrite it tells the user the wrong package;
        and whether every such string is only a message the handler shows (raised, printed,
        logged, warned), which changes nothing the program does."""
        guard = next((a for a in self.facts.ancestors(node) if isinstance(a, ast.Try)), None)
        if guard is None:
            return None, True
        first: int | None = None
        shown_only = True
        for handler in guard.handlers:
            for child in walk(handler):
                if isinstance(child, ast.Constant) and isinstance(child.value, str) and _NAMES_GYM.search(child.value):
                    first = child.lineno if first is None else first
                    shown_only = shown_only and self._shown_message(child)
        return first, shown_only

    def _shown_message(self, text: ast.Constant) -> bool:
        """Is ``text`` part of what a ``raise`` gives, or the argument of a call that only
        shows it (``print``, a logger's level method, ``warnings.warn``, ``sys.exit``)? Text
        kept in a name or handed to anything else (``subprocess.call([... "gym"])``) may act."""
        current: ast.AST = text
        while True:
            parent = self.facts.parent(current)
            if isinstance(parent, (ast.JoinedStr, ast.FormattedValue, ast.BinOp)):
                current = parent
                continue
            if isinstance(parent, ast.Call) and isinstance(parent.func, ast.Attribute) and parent.func.value is current:
                current = parent  # ``"... {}".format(x)``
                continue
            if isinstance(parent, ast.keyword):
                parent = self.facts.parent(parent)
                if not isinstance(parent, ast.Call):
                    return False
            if isinstance(parent, ast.Raise):
                return True
            if not isinstance(parent, ast.Call) or current is parent.func:
                return False
            if isinstance(self.facts.parent(parent), ast.Raise):
                return True  # ``raise ImportError("... gym ...")``
            callee = parent.func.attr if isinstance(parent.func, ast.Attribute) else getattr(parent.func, "id", None)
            return callee in _SHOWING_CALLS


    def _splittable(self, node: ast.ImportFrom) -> bool:
        """An import statement on lines of its own (not after ``;``, not a one-line suite's
        body): one import per module can stand where it stood."""
        parent = self.facts.parent(node)
        body = getattr(parent, "body", None)
        if not isinstance(body, list) or node not in body:
            return False
        if parent is not None and not isinstance(parent, ast.Module) and parent.lineno == node.lineno:  # type: ignore[attr-defined]
            return False  # ``try: from gym.wrappers import ...``
        lines = {n.lineno for n in body if n is not node} | {n.end_lineno for n in body if n is not node}
        return node.lineno not in lines and node.end_lineno not in lines

    def _split_import(self, node: ast.ImportFrom, module: str, homes: list[str]) -> None:
        """``from gym.wrappers import RecordVideo, capped_cubic_video_schedule`` -> one import
        per Gymnasium module the names live in now, in the order of their first name."""
        groups: dict[str, list[ast.alias]] = {}
        for alias, home in zip(node.names, homes):
            groups.setdefault(home, []).append(alias)
        (first, kept), *others = groups.items()
        where = ", ".join(f"{', '.join(f'`{a.name}`' for a in aliases)} from {home}" for home, aliases in groups.items())
        self.report(node, "GM104", f"from {module} import ...: its names live in different Gymnasium modules now: split into {where}")
        keep = {alias.name for alias in kept}
        self.plan.replace(node, lambda from_node: _keep_aliases(from_node, first, keep))
        for home, aliases in others:
            self.plan.insert_after(node, f"from {home} import {', '.join(alias_text(a) for a in aliases)}")

    def _import_from(self, node: ast.ImportFrom) -> None:
        if node.level or node.module is None:
            return
        kept = self._kept_space_imports.get(node)
        if kept is not None:
            self.report(node, "GM103" if node.module != "gym" else "GM102", kept, FixKind.FLAG)
            return
        library = self._handed_only_to_legacy_library(node)
        if library is not None:
            names = ", ".join(f"`{alias.asname or alias.name}`" for alias in node.names)
            self.report(
                node,
                "GM103" if node.module != "gym" else "GM102",
                f"left on gym: {names} is handed only to {library}, which builds legacy gym envs (Gymnasium's classes "
                f"refuse them); move it when that code moves off gym",
                FixKind.FLAG,
            )
            return
        module = node.module
        rest = under_gym(module)
        legacy_gymnasium_wrappers = module.startswith("gymnasium.wrappers.") and module[19:] in LEGACY_WRAPPER_MODULES
        if rest is None and not legacy_gymnasium_wrappers:
            return
        if rest is None:
            rest = module[len("gymnasium.") :]
        star = any(alias.name == "*" for alias in node.names)
        if not star and self._renamed_names(node, rest):
            return
        hint = removed_module_hint(rest)
        advice = hint
        question = None
        if hint is None and not star:
            for alias in node.names:
                hint = advice = removed_name_hint(rest, alias.name)
                if hint:
                    hint = f"`{alias.name}` cannot move to Gymnasium: {hint}"
                    # the uses of the name in the file (GM506) ask the same: what replaces it
                    question = removed_helper_question(rest, alias.name)
                    break
        elif hint is not None:
            hint = f"`{module}` was removed: {hint}"
        if hint and self._atari_class_checks_only(node, rest):
            return
        if hint:
            self._report_removed(node, hint, advice or hint, question)
            return
        new_rest = migrated_path(rest)
        target = "gymnasium" + ("." + new_rest if new_rest else "")
        # Every name must exist where the import points, whether or not the module path
        # changed: ``from gym.wrappers import capped_cubic_video_schedule`` needs
        # ``gymnasium.utils.save_video``. (Names Gymnasium renamed or dropped are reported by
        # the families that rename them: GM906, GM907...)
        if not star and (new_rest != rest or module_exists(target)):
            moved = [
                None
                if module_exists(target) and has_name(target, alias.name)
                else MOVED_NAMES.get((rest.split(".")[-1], alias.name))
                or MOVED_NAMES.get(("*", alias.name))
                or home_of(new_rest, alias.name)
                for alias in node.names
            ]
            first = moved[0] if moved else None
            if first and len(set(moved)) == 1:  # every name moved, to one module
                new_rest = first[len("gymnasium.") :]
            elif any(moved) and self._splittable(node):
                self._split_import(node, module, [m or target for m in moved])
                return
            elif any(moved):
                names = ", ".join(f"`{alias.name}`" for alias in node.names)
                self._report_removed(
                    node,
                    f"{names} now live in different Gymnasium modules ({', '.join(sorted({m or 'gymnasium.' + new_rest for m in moved}))}): "
                    "split this import by hand",
                    "split the import: its names moved to different modules",
                )
                return
        new_module = "gymnasium" + ("." + new_rest if new_rest else "")
        if new_module == module:
            return
        code = "GM102" if rest == "" else "GM104" if new_rest != rest else "GM103"
        if star and new_module in _STAR_IMPORT_RAISES:
            self._decide_failing_star(node, code, module, new_module)
            return
        self.report(node, code, f"from {module} import ... -> from {new_module} import ...")
        self.plan.replace(node, lambda from_node: from_node.with_changes(module=dotted_node(new_module)))

    def _decide_failing_star(self, node: ast.ImportFrom, code: str, module: str, new_module: str) -> None:
        """``from gym.wrappers import *``: the same star import of Gymnasium raises (see
        ``_STAR_IMPORT_RAISES``), so it is never written. Where the module's free names are all
        builtins or names of the new module, and nothing else can supply or look up a name
        (another star import, ``eval``/``exec``/``globals()``/``vars()``, ``__all__``), those names
        are imported explicitly; otherwise the import is reported."""
        free: set[str] = set()
        dynamic = False
        for other in ast.walk(self.facts.tree):
            if other is not node and isinstance(other, ast.ImportFrom) and any(alias.name == "*" for alias in other.names):
                dynamic = True
            elif isinstance(other, ast.Name):
                if other.id in _NAME_LOOKUPS or other.id == "__all__":
                    dynamic = True
                elif isinstance(other.ctx, ast.Load) and not self.facts.bindings_of(other) and other.id not in _BUILTINS:
                    if not (other.id.startswith("__") and other.id.endswith("__")):  # ``__file__``: the import system's
                        free.add(other.id)
        names = sorted(free)
        if not dynamic and names and all(has_name(new_module, name) and not name.startswith("_") for name in names):
            self.report(
                node,
                code,
                f"from {module} import * -> from {new_module} import {', '.join(names)}: Gymnasium's star import of "
                f"`{new_module}` raises ModuleNotFoundError without the optional array-api packages; these are the names the module uses",
            )
            self.plan.replace(
                node,
                lambda from_node, names=tuple(names): from_node.with_changes(
                    module=dotted_node(new_module),
                    names=[cst.ImportAlias(name=cst.Name(name)) for name in names],
                    lpar=None,
                    rpar=None,
                ),
            )
            return
        self.report(
            node,
            code,
            f"`from {module} import *` left on gym: Gymnasium's star import of `{new_module}` raises ModuleNotFoundError "
            "without the optional array-api packages (its `__all__` names the array-conversion wrappers), and which "
            "of its names this module uses is not known here (a name looked up at run time, another star import, or a "
            f"name Gymnasium lacks): import the names it uses explicitly from `{new_module}`",
            FixKind.FLAG,
        )

    def _renamed_names(self, node: ast.ImportFrom, rest: str) -> bool:
        """``from gym.envs.registration import load``: a name Gymnasium kept under another
        name, with the same contract (RENAMED_NAMES). Where every name of the import exists in
        the Gymnasium module once renamed, the import binds the new names to the old ones, so
        no use changes. True when rewritten."""
        renamed = {alias.name: RENAMED_NAMES[(rest, alias.name)] for alias in node.names if (rest, alias.name) in RENAMED_NAMES}
        if not renamed:
            return False
        target = "gymnasium." + migrated_path(rest)
        if not module_exists(target) or not all(has_name(target, renamed.get(a.name, a.name)) for a in node.names):
            return False

        def rename(from_node: cst.ImportFrom) -> cst.ImportFrom:
            names = []
            for alias in from_node.names:  # type: ignore[union-attr]
                old = alias.evaluated_name
                if old in renamed:
                    alias = alias.with_changes(
                        name=cst.Name(renamed[old]), asname=alias.asname or cst.AsName(name=cst.Name(old))
                    )
                names.append(alias)
            return from_node.with_changes(module=dotted_node(target), names=names)

        self.plan.replace(node, rename)
        pairs = ", ".join(f"`{old}` -> `{new} as {old}`" for old, new in renamed.items())
        self.report(
            node,
            "GM105",
            f"from {node.module} import ... -> from {target} import ...: {pairs}, the same contract under Gymnasium's name",
            FixKind.AUTO,
        )
        return True

    def _atari_class_checks_only(self, node: ast.ImportFrom, rest: str) -> bool:
        """``from gym.envs.atari import AtariEnv`` (or ``from gym.envs import atari`` read as
        ``atari.AtariEnv``) where every use is a class check (``isinstance(env.unwrapped,
        AtariEnv)``): the class lives in ale_py now, so the import moves there, certain
        (``from ale_py import AtariEnv``; ``import ale_py as atari``). Any other use (a
        construction, another name) leaves the GM105 report. True when rewritten."""
        if len(node.names) != 1 or node.level:
            return False
        alias = node.names[0]
        bound = alias.asname or alias.name
        if (rest, alias.name) in (("envs.atari", "AtariEnv"), ("envs.atari.atari_env", "AtariEnv")):
            via_module = False
        elif (rest, alias.name) == ("envs", "atari"):
            via_module = True
        else:
            return False
        reads = [n for n in walk(self.facts.tree) if isinstance(n, ast.Name) and n.id == bound]
        if not reads or any(not isinstance(n.ctx, ast.Load) for n in reads):
            return False
        for read in reads:
            checked: ast.AST = read
            if via_module:
                parent = self.facts.parent(read)
                if not (isinstance(parent, ast.Attribute) and parent.value is read and parent.attr == "AtariEnv"):
                    return False
                checked = parent
            if not _in_class_check(self.facts, checked):
                return False
        if via_module:
            new_text = f"import ale_py as {bound}"
            self.plan.replace(
                node, lambda _: cst.Import(names=[cst.ImportAlias(name=cst.Name("ale_py"), asname=cst.AsName(name=cst.Name(bound)))])
            )
        else:
            new_text = "from ale_py import " + alias_text(alias)
            self.plan.replace(node, lambda from_node: from_node.with_changes(module=dotted_node("ale_py")))
        self.report(
            node,
            "GM105",
            f"`from gym.{rest} import {alias.name}` -> `{new_text}`: gym's Atari env class lives in ale_py, and "
            "it is used here only in class checks",
            FixKind.AUTO,
        )
        return True


def _in_class_check(facts: ModuleFacts, expr: ast.AST) -> bool:
    """``expr`` is the class argument of ``isinstance``/``issubclass`` (or one of a tuple)."""
    parent = facts.parent(expr)
    if isinstance(parent, ast.Tuple):
        expr, parent = parent, facts.parent(parent)
    return (
        isinstance(parent, ast.Call)
        and isinstance(parent.func, ast.Name)
        and parent.func.id in ("isinstance", "issubclass")
        and len(parent.args) == 2
        and parent.args[1] is expr
    )


def alias_text(alias: ast.alias) -> str:
    return f"{alias.name} as {alias.asname}" if alias.asname else alias.name


def _keep_aliases(from_node: cst.ImportFrom, module: str, keep: set[str]) -> cst.ImportFrom:
    """``from_node`` importing only the names in ``keep``, from ``module``."""
    every = list(from_node.names)  # type: ignore[arg-type]
    names = [a for a in every if a.evaluated_name in keep]
    names[-1] = names[-1].with_changes(comma=every[-1].comma)  # the statement's own ending (a trailing comma, a newline)
    return from_node.with_changes(module=dotted_node(module), names=names)


def _with_names(node: cst.Import, names: list[tuple[str, str | None]]) -> cst.Import:
    aliases = [
        cst.ImportAlias(name=dotted_node(module), asname=cst.AsName(name=cst.Name(asname)) if asname else None)
        for module, asname in names
    ]
    old = list(node.names)
    if len(aliases) == len(old):
        # Keep the user's own separators and ``as`` spacing.
        aliases = [
            new.with_changes(comma=previous.comma, asname=_same_asname(previous, new))
            for new, previous in zip(aliases, old)
        ]
    else:
        last_comma = old[-1].comma
        aliases = [a.with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))) for a in aliases[:-1]] + [
            aliases[-1].with_changes(comma=last_comma)
        ]
    return node.with_changes(names=aliases)


def _same_asname(previous: cst.ImportAlias, new: cst.ImportAlias) -> cst.AsName | None:
    """The user's ``as name`` node (with its spacing) where the bound name is unchanged."""
    if previous.asname and new.asname and previous.asname.name.value == new.asname.name.value:  # type: ignore[union-attr]
        return previous.asname
    return new.asname
