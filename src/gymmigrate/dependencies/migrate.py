"""The dependency-file formats and their migration (``gymmigrate.dependencies`` loads this
with the first dependency file of a run, so runs over Python files never import the
parsers: ``packaging``, the TOML scanner)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path, PurePath
from typing import TYPE_CHECKING

from gymmigrate.dependencies import DependencyError, kind_of
from gymmigrate.dependencies.core import apply_edits, companions
from gymmigrate.dependencies.lines import (
    migrate_environment,
    migrate_requirements,
    migrate_setup_cfg,
)
from gymmigrate.dependencies.mapping import (
    GYM_PACKAGE,
    MIGRATE_WITH_IT,
    MIGRATED_WITH_IT,
    only_describes_gym_pin,
)
from gymmigrate.dependencies.plugins import plugin_findings
from gymmigrate.dependencies.pyproject import PyprojectError, migrate_pyproject
from gymmigrate.dependencies.setup_py import SetupPyError, migrate_setup_py
from gymmigrate.dependencies.shell import migrate_dockerfile, migrate_page
from gymmigrate.engine import LineMap
from gymmigrate.findings import Finding, FixKind, Tier

if TYPE_CHECKING:
    from collections.abc import Mapping

    from gymmigrate.dependencies.plugins import Route
    from gymmigrate.selection import Selection


@dataclass(frozen=True)
class DependencyResult:
    rewritten: bytes
    findings: list[Finding]

    def __iter__(self):  # ``rewritten, findings = migrate_dependency_file(...)``
        return iter((self.rewritten, self.findings))


def _requirements(text: str):
    return migrate_requirements(text)


def _environment(text: str):
    return migrate_environment(text)


def _setup_cfg(text: str):
    return migrate_setup_cfg(text)


def _setup_py(text: str):
    try:
        return migrate_setup_py(text)
    except SetupPyError as exc:
        raise DependencyError(str(exc)) from None


def _pyproject(text: str):
    try:
        return migrate_pyproject(text)
    except PyprojectError as exc:
        raise DependencyError(str(exc)) from None


def _dockerfile(text: str):
    return migrate_dockerfile(text)


# The kind of a dependency file (``dependencies.kind_of``) -> its handler.
HANDLERS: dict[str, Callable] = {
    "requirements": _requirements,
    "setup.py": _setup_py,
    "setup.cfg": _setup_cfg,
    "pyproject.toml": _pyproject,
    "environment.yml": _environment,
    "dockerfile": _dockerfile,
}


def _decode(source: bytes) -> tuple[str, bool]:
    bom = source.startswith(b"\xef\xbb\xbf")
    try:
        return source[3 if bom else 0 :].decode("utf-8"), bom
    except UnicodeDecodeError as exc:
        raise DependencyError(f"cannot decode the file as UTF-8 ({exc.reason} at byte {exc.start}); left unchanged") from None


def _run(handler: Callable, source: bytes, selection: Selection | None = None,
         requires: frozenset[str] = frozenset()) -> DependencyResult:
    def allowed(code: str) -> bool:
        return selection is None or selection.allows(code)

    text, bom = _decode(source)
    outcome = handler(text)
    if requires:
        companions(text, outcome, requires)
    # --select/--ignore: a rule left out neither reports nor fixes.
    edits = [edit for edit in outcome.edits if allowed(edit.code)]
    findings = sorted(
        [finding for finding in outcome.findings if allowed(finding.rule)]
        + [companion for edit in edits for companion in edit.companions if allowed(companion.rule)]
    )
    if not edits:
        return DependencyResult(source, findings)
    new_text = apply_edits(text, edits)
    rewritten = (b"\xef\xbb\xbf" if bom else b"") + new_text.encode("utf-8")
    if rewritten == source:
        return DependencyResult(source, findings)
    line_map = LineMap(text, new_text)
    return DependencyResult(rewritten, [f.placed(line_map.forward) for f in findings])


def migrate_dependency_file(
    path: Path | str,
    source: bytes,
    *,
    selection: Selection | None = None,
    requires: frozenset[str] = frozenset(),
    plugins: Mapping[str, Route] | None = None,
    code_migrated: bool = False,
) -> DependencyResult:
    """The migrated bytes of a dependency file and what was changed or must be reviewed.
    ``requires``: packages the run's migrated code imports (``ProjectFacts.requires``).

    ``plugins``: what the run did with each ``gym.envs`` entry point of the file (GM111,
    ``plugins.py``), by target; None for a file migrated on its own.

    ``code_migrated``: the same run migrates the code the file declares (its Python
    programs): the move of gym's own pin asks nothing more, and is a note.

    Raises DependencyError when the file cannot be read as its kind, or when the rewrite
    would not be stable (a second run would change it again).
    """
    kind = kind_of(path)
    if kind is None:
        raise DependencyError("not a dependency file")
    handler = HANDLERS[kind]
    if kind in ("setup.py", "setup.cfg", "pyproject.toml"):
        handler = _reporting_plugins(handler, kind, plugins)
    result = _run(handler, source, selection, requires)
    if result.rewritten != source and _run(handler, result.rewritten, selection, requires).rewritten != result.rewritten:
        raise DependencyError("the dependency rewrite is not stable (a second run would change it again); file left unchanged")
    if code_migrated:
        return replace(result, findings=[_moved_with_the_code(finding) for finding in result.findings])
    return result


def _moved_with_the_code(finding: Finding) -> Finding:
    """GM109's item on gym's own pin, whose every reason describes the rewrite, where the run
    migrates the code beside the file: what it asks ("the code must be migrated with it") is
    done, so it is a note saying so. Any other finding as it is."""
    if finding.rule == GYM_PACKAGE and finding.kind is FixKind.ASSIST and only_describes_gym_pin(finding.message):
        return replace(finding, tier=Tier.NOTE, message=finding.message.replace(MIGRATE_WITH_IT, MIGRATED_WITH_IT))
    return finding


def _reporting_plugins(handler: Callable, kind: str, plugins: Mapping[str, Route] | None) -> Callable:
    def run(text: str):
        outcome = handler(text)
        outcome.findings.extend(plugin_findings(kind, text, plugins))
        return outcome

    return run


def migrate_page_commands(path: Path | str, source: bytes, *, selection: Selection | None = None) -> DependencyResult:
    """``pip install`` lines in the shell/console code blocks of a Markdown or RST page."""
    markdown = PurePath(path).suffix.lower() in (".md", ".markdown")
    return _run(lambda text: migrate_page(text, markdown), source, selection)
