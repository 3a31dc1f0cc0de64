"""Which modules of the run reach which, passes of ``ProjectFacts.join``: the packages near
each module, the env modules a module imports (directly, through package ``__init__``
modules, or for ``render``, through the modules of the factories it imports) for its
untraced ``seed``/``render`` calls, the importers of a module registering
envs from data, and the packages the migrated imports require.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from gymmigrate.facts import names as N
from gymmigrate.facts.import_roots import import_parts
from gymmigrate.facts.module_summary import ModuleSummary

if TYPE_CHECKING:
    from gymmigrate.facts.project import ProjectFacts


def join_nearby_packages(facts: ProjectFacts, summaries: list[ModuleSummary]) -> None:
    own = {s.path: frozenset(q.split(".", 1)[0] for q in s.imported if not q.startswith(".")) for s in summaries}
    nearby = {path: set(tops) for path, tops in own.items()}
    for summary in summaries:
        imports: set[str] = set()
        for qualified in summary.imported:
            split = facts._split(qualified, summary.path)
            if split is None or split[0] == summary.path or split[0] not in own:
                continue
            imports.add(split[0])
            nearby[summary.path] |= own[split[0]]
            nearby[split[0]] |= own[summary.path]
        # A script importing a factory of one module and the agent of another hands what
        # the one makes to the other (``env = make_env(); Agent.init_from_env(env)``): two
        # modules it imports are next to each other. A package's ``__init__`` only
        # re-exports its modules, it hands nothing between them.
        if os.path.basename(summary.path) != "__init__.py" and len(imports) > 1:
            siblings = set().union(*(own[path] for path in imports))
            for path in imports:
                nearby[path] |= siblings
    facts.nearby_packages = {path: frozenset(tops) for path, tops in nearby.items()}


def join_import_components(facts: ProjectFacts, summaries: list[ModuleSummary]) -> None:
    """``ProjectFacts.import_components``: the modules of the run its imports connect, each
    way and through any number of steps (every package on an imported path counts): what
    one module says of another of its project, not of an unrelated one the run also holds."""
    parent = {s.path: s.path for s in summaries}

    def root(path: str) -> str:
        while parent[path] != path:
            parent[path] = parent[parent[path]]
            path = parent[path]
        return path

    edges: dict[str, set[str]] = {}
    for summary in summaries:
        for qualified in (*summary.imported, *summary.star_imports):
            level, parts = import_parts(qualified)
            for cut in range(0 if level else 1, len(parts) + 1):
                path = facts._module_path(parts[:cut], level, summary.path)
                if path and path in parent:
                    parent[root(path)] = root(summary.path)
                    edges.setdefault(summary.path, set()).add(path)
    facts.import_components = {path: root(path) for path in parent}
    facts.module_imports = {path: frozenset(found) for path, found in edges.items()}


def join_opaque_registrations(facts: ProjectFacts, by_path: dict[str, ModuleSummary]) -> None:
    kept = sorted(
        name
        for (path, name) in facts.mode_renders_below
        if name in by_path[path].fixed_mode_renders
    )
    registrars = {path for path, summary in by_path.items() if summary.opaque_registrations}
    if not kept or not registrars:
        return
    # ``import pkg.catalog`` binds (and records) ``pkg``: a registrar in that package counts.
    dotted = [name for name, path in facts.modules.items() if path in registrars]
    for summary in by_path.values():
        for qualified in summary.imported:
            level, parts = import_parts(qualified)
            reached = {facts._module_path(parts[:cut], level, summary.path) for cut in range(1, len(parts) + 1)}
            inside = level == 0 and any(name == qualified or name.startswith(qualified + ".") for name in dotted)
            if reached & registrars or inside:
                facts.opaque_kept_renders[summary.path] = kept[0]
                break


def imported_env_modules(facts: ProjectFacts, summary: ModuleSummary, declared: dict[str, ModuleSummary] | None = None) -> set[str]:
    """The other modules of the run with env classes that ``summary``'s module imports
    (``declared``: by the classes each module declares, blocked or not)."""
    found = set()
    for qualified in summary.imported:
        level, parts = import_parts(qualified)
        for module in (parts, parts[:-1]):  # `import envs` / `from envs import Dice`
            path = facts._module_path(module, level, summary.path) if module else None
            if path and path != summary.path and (
                facts.env_classes.get(path) or (declared is not None and path in declared and declared[path].env_classes)
            ):
                found.add(path)
    return found


def made_by_def(facts: ProjectFacts, qualified: str, importer: str, by_path: dict[str, ModuleSummary]) -> bool:
    """``pkg.make_board`` names a def of the run (not a class, whose construction the
    rendering rules give a ``render_mode``), followed through re-exports."""
    resolved = facts._resolve(qualified, importer)
    if resolved is None:
        return False
    path, name = resolved
    summary = by_path.get(path)
    return summary is not None and "." not in name and name in summary.defs and name not in summary.classes


def env_modules_through_packages(facts: ProjectFacts, summary: ModuleSummary, by_path: dict[str, ModuleSummary]) -> set[str]:
    """``_imported_env_modules``, and those of every package ``__init__`` of the run it
    imports, followed through the ``__init__`` modules those import; and those of every
    module whose def it imports (``from env import make_env``): a factory of the run builds
    the env classes its own module imports (in its body, often), so an env this module got
    from it, untraced, may be one of theirs."""
    found = imported_env_modules(facts, summary)
    for qualified in summary.imported:
        resolved = facts._resolve(qualified, summary.path)
        if resolved is not None and resolved[0] in by_path and made_by_def(facts, qualified, summary.path, by_path):
            found |= imported_env_modules(facts, by_path[resolved[0]])
    seen = {summary.path}
    queue = [summary]
    while queue:
        current = queue.pop()
        for qualified in current.imported:
            level, parts = import_parts(qualified)
            for module in (parts, parts[:-1]):
                path = facts._module_path(module, level, current.path) if module else None
                if path is None or path in seen or os.path.basename(path) != "__init__.py" or path not in by_path:
                    continue
                seen.add(path)
                found |= imported_env_modules(facts, by_path[path])
                queue.append(by_path[path])
    return found




def kept_mode_render(
    facts: ProjectFacts, summary: ModuleSummary, by_path: dict[str, ModuleSummary]
) -> tuple[str, str, frozenset[str]] | None:
    """For a module with an untraced ``x.render(mode)``: (path, class, the names the module
    imports it by) of the one env class of the run it reaches whose own render() takes
    ``mode`` and keeps it for the calls of other modules (its module is ``render_called``);
    None when it reaches none or several. It reaches what it imports
    (``env_modules_through_packages``) and what the ``__init__`` of each package above it
    imports, which runs whenever the module is imported (``import pkg.runner`` runs
    ``pkg/__init__.py`` first)."""
    reached = env_modules_through_packages(facts, summary, by_path)
    # its dotted name from the run's root (the longest suffix naming it): each prefix is a
    # package whose ``__init__`` runs first (a comment-only one has no summary: skipped)
    dotted = max((name for name, path in facts.modules.items() if path == summary.path), key=len, default="")
    parts = dotted.split(".")[:-1]
    for cut in range(1, len(parts) + 1):
        init = by_path.get(facts.modules.get(".".join(parts[:cut])) or "")
        if init is not None and init is not summary:
            reached |= env_modules_through_packages(facts, init, by_path)
    definers = {
        (path, name)
        for path in reached
        if path in facts.render_called
        for name in by_path[path].env_classes
        if "mode" in getattr(by_path[path].defs.get(f"{name}.render"), "params", ())
        and (path, name) not in facts.own_renders
    }
    if len(definers) != 1:
        return None
    path, name = definers.pop()
    # the names this module builds it by (``from pkg import BoardEnv``, a package's
    # re-export followed)
    builds = frozenset(
        qualified
        for qualified in summary.imported
        if facts._split(qualified, summary.path) == (path, name)
        or (facts._resolve(qualified, summary.path) or facts._resolve_reexported(qualified, summary.path, by_path))
        in ((path, name), (path, f"{name}.__init__"))
    )
    return path, name, builds


def required_packages(imported: set[str]) -> frozenset[str]:
    """The packages the migrated code needs declared, by what the run imports (``imported``)."""
    requires = {
        package
        for family, (package, rewritten) in N.PZ_MOVED_FAMILIES.items()
        if rewritten and any(
            q == family or q.startswith(family + ".") or q == package or q.startswith(package + ".")
            for q in imported
        )
    }
    # Gymnasium 1.x's ``envs/mujoco/__init__.py`` imports its renderer, which imports
    # imageio: any import under ``gym.envs.mujoco`` (``gymnasium.envs.mujoco``) needs it.
    if any(q.split(".")[:3] in (["gym", "envs", "mujoco"], ["gymnasium", "envs", "mujoco"]) for q in imported):
        requires.add("imageio")
    return frozenset(requires)


def imports_env_checker(qualified: str) -> bool:
    """``gym.utils.env_checker.check_env`` or its module, under Gym or Gymnasium."""
    parts = qualified.split(".")
    return parts[0] in ("gym", "gymnasium") and parts[1:4] in (["utils", "env_checker"], ["utils", "env_checker", "check_env"])
