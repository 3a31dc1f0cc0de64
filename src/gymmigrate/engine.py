"""Run the rule passes over one file, verify the result, and write it safely.

``transform_source`` is pure (bytes in, bytes and findings out) so tests, the CLI and
a future process pool share it. ``process_file`` adds the I/O: reading, the atomic
write that keeps the file's mode, and turning every failure into a reported error
instead of a traceback.
"""

from __future__ import annotations

import ast
import difflib
import io
import os
import re
import tokenize
from bisect import bisect_right
from dataclasses import dataclass, field, replace
from enum import Enum
from pathlib import Path

import libcst as cst

from gymmigrate.edits.apply import apply_plan
from gymmigrate.edits.plan import Plan
from gymmigrate.edits.splice import splice_plan
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.receivers import Receivers
from gymmigrate.findings import Finding
from gymmigrate.rules import registered_families
from gymmigrate.rules.base import FileContext, FileProfile, RewriteOptions
from gymmigrate.selection import family_selected, filter_plan
from gymmigrate.suppressions import skips_file

# A file that mentions none of these cannot hold Gym code: skip it before parsing.
# ``envs?\b`` catches env, envs, vec_env, CartPoleEnv, but not os.environ.
_MAY_HOLD_GYM_CODE = re.compile(rb"gym|pettingzoo|baselines|envs?\b", re.IGNORECASE)


class Status(str, Enum):
    UNCHANGED = "unchanged"
    CHANGED = "changed"
    SKIPPED = "skipped"  # filtered out before parsing
    ERROR = "error"


@dataclass(frozen=True)
class FileResult:
    path: str
    status: Status
    findings: tuple[Finding, ...] = ()
    error: str | None = None
    diff: str | None = None
    written: bool = False

    @property
    def changed(self) -> bool:
        return self.status is Status.CHANGED


class TransformError(Exception):
    """The file could not be processed; the message says why in one sentence."""


@dataclass
class Transformed:
    original: bytes
    rewritten: bytes
    encoding: str
    findings: list[Finding] = field(default_factory=list)

    @property
    def changed(self) -> bool:
        return self.original != self.rewritten


def may_hold_gym_code(source: bytes) -> bool:
    return _MAY_HOLD_GYM_CODE.search(source) is not None


def parse(source: bytes, path: str) -> cst.Module:
    """Parse for rewriting, or raise TransformError saying in one sentence why not."""
    text, _ = decode(source)
    _parse_ast(text, source, path)
    return _parse_cst(source)


def _parse_cst(source: bytes | str) -> cst.Module:
    """A whole file (bytes) or a cut of its statements (text)."""
    try:
        return cst.parse_module(source)
    except cst.ParserSyntaxError as exc:
        raise TransformError(f"syntax error at line {exc.raw_line}, column {exc.raw_column}") from None


_PY2_HINTS = re.compile(rb"^\s*(print\s+[^\s(=]|exec\s+[\"']|except\s+[\w.]+\s*,\s*\w+\s*:)|\bur[\"']|`[^`\n]+`", re.M)


def _looks_like_python2(source: bytes) -> bool:
    return _PY2_HINTS.search(source) is not None


def transform_source(source: bytes, path: str = "<string>", options: RewriteOptions | None = None) -> Transformed:
    """Migrate ``source`` and verify the output.

    Raises TransformError when the file cannot be parsed, a rule fails, or the output
    would not parse or would change again on a second run.
    """
    options = options or RewriteOptions()
    text, encoding = decode(source)
    tree = _parse_ast(text, source, path)
    result = _migrate(source, text, encoding, tree, path, options)
    if result.changed:
        _verify(result, path, options)
    return result


def lint_source(source: bytes, path: str = "<string>", options: RewriteOptions | None = None) -> tuple[list[Finding], bool]:
    """What ``check`` needs: the findings, and whether ``rewrite`` would change the file.

    Costs a CPython parse and the rules' decisions: no LibCST tree, no verification run.
    """
    options = options or RewriteOptions()
    text, _ = decode(source)
    tree = _parse_ast(text, source, path)
    plan = plan_file(tree, text, path, options)
    return sorted(plan.findings), plan.has_edits


def decode(source: bytes) -> tuple[str, str]:
    """The text of ``source`` and its encoding (PEP 263 cookie or BOM, else UTF-8)."""
    try:
        encoding, _ = tokenize.detect_encoding(io.BytesIO(source).readline)
        text = source.decode(encoding)
    except UnicodeDecodeError as exc:
        raise TransformError(f"cannot decode the file ({exc.reason} at byte {exc.start})") from None
    except (LookupError, SyntaxError) as exc:  # unknown or malformed encoding cookie
        raise TransformError(f"cannot decode the file: {exc}") from None
    if encoding == "utf-8-sig":
        text = text.removeprefix("\ufeff")
    return text, encoding


def _parse_ast(text: str, source: bytes, path: str) -> ast.Module:
    # CPython's parser: cheap, exact positions, and it rejects cleanly what would crash
    # LibCST's native parser (pathological nesting segfaults it).
    try:
        return ast.parse(text, filename=path)
    except SyntaxError as exc:
        hint = " (this looks like Python 2 code)" if _looks_like_python2(source) else ""
        where = f" at line {exc.lineno}" if exc.lineno else ""
        raise TransformError(f"syntax error{where}: {exc.msg}{hint}") from None
    except (ValueError, RecursionError, MemoryError) as exc:
        raise TransformError(f"cannot parse the file: {exc}") from None


def plan_file(tree: ast.Module, text: str, path: str, options: RewriteOptions) -> Plan:
    """Every rule family decides on the same facts; nothing is changed yet."""
    facts = ModuleFacts(tree, text)
    context = FileContext(path=path, options=options, profile=FileProfile.from_source(text))
    plan = Plan(facts)
    if skips_file(text, _first_statement_line(tree)):
        return plan
    receivers = Receivers(facts, options.project.view(path) if options.project is not None else None)
    for family in registered_families():
        if not family_selected(family, options.selection) or not family.may_fire(facts, context):
            continue
        plan.deciding = family.__name__
        try:
            family(context, facts, receivers, plan).decide()
        except RecursionError:
            raise TransformError(f"internal error in {family.__name__}: the code is nested too deeply to analyse") from None
        except Exception as exc:  # a rule bug must not lose the user's file or print a traceback
            raise TransformError(f"internal error in {family.__name__}: {type(exc).__name__}: {exc}") from exc
    filter_plan(plan, text, options)  # --select/--ignore and suppression comments
    return plan


def _first_statement_line(tree: ast.Module) -> int | None:
    body = tree.body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str):
        body = body[1:]  # the docstring
    return body[0].lineno if body else None


def _migrate(source: bytes, text: str, encoding: str, tree: ast.Module, path: str, options: RewriteOptions) -> Transformed:
    plan = plan_file(tree, text, path, options)
    findings = sorted(plan.findings)
    if not plan.has_edits:
        # Nothing to change: no LibCST tree at all.
        return Transformed(original=source, rewritten=source, encoding=encoding, findings=findings)
    try:
        new_text = _apply(source, text, plan)
    except TransformError:
        raise
    except Exception as exc:  # noqa: BLE001  (a rule's edit could not be placed)
        if plan.partial:
            raise TransformError(
                "the rules left out here (by --select/--ignore or a suppression comment) share one fix with "
                "rules that are not: select them together, or silence the whole statement; file left unchanged"
            ) from exc
        raise TransformError(f"internal error while applying edits: {type(exc).__name__}: {exc}") from exc
    rewritten = new_text.encode(encoding)  # a BOM comes back with utf-8-sig
    if rewritten == source:
        return Transformed(original=source, rewritten=source, encoding=encoding, findings=findings)
    # Findings are placed in the original; place them in the output too.
    line_map = LineMap(text, new_text)
    findings = [replace(f, line_after=line_map.forward(f.line)) for f in findings]
    return Transformed(original=source, rewritten=rewritten, encoding=encoding, findings=findings)


_UNREPRODUCIBLE = re.compile(r"\r(?!\n)|\f")


def _apply(source: bytes, text: str, plan: Plan) -> str:
    """The rewritten text: only the top-level statements that change are parsed and
    printed again where that is exact (``edits.splice``), else the whole module."""
    if not _UNREPRODUCIBLE.search(text):
        spliced = splice_plan(text, plan, _parse_cst)
        if spliced is not None:
            return spliced
    module = apply_plan(_parse_cst(source), plan)
    new_text = module.code
    if new_text.encode(module.encoding) != source:
        _check_round_trip(source, text)
    return new_text


def _check_round_trip(source: bytes, text: str) -> None:
    # LibCST cannot reproduce every file (CR-only line endings, form feeds): writing its
    # output would drop bytes no rule touched. Only those characters need the check.
    if _UNREPRODUCIBLE.search(text) and _parse_cst(source).bytes != source:
        raise TransformError(
            "the file cannot be reproduced byte for byte (CR-only line endings or form feeds?); left unchanged"
        )


def _verify(result: Transformed, path: str, options: RewriteOptions) -> None:
    """The output must compile, and a second run over it must change nothing.

    The second run decides on ``ast`` like the first; it only builds a LibCST tree
    when a rule would change the output again (an unstable rewrite).
    """
    text = result.rewritten.decode(result.encoding)
    if result.encoding == "utf-8-sig":
        text = text.removeprefix("\ufeff")
    try:
        tree = ast.parse(text, filename=path)
    except SyntaxError as exc:
        raise TransformError(f"the rewrite would not parse (line {exc.lineno}: {exc.msg}); file left unchanged") from None
    again = _migrate(result.rewritten, text, result.encoding, tree, path, options)
    if again.rewritten != result.rewritten:
        raise TransformError("the rewrite is not stable (a second run would change it again); file left unchanged")


class LineMap:
    """Maps line numbers between two versions of a text (1-based), via difflib opcodes."""

    def __init__(self, before: str, after: str) -> None:
        a = before.splitlines()
        b = after.splitlines()
        # autojunk: in files of 200+ lines, very frequent lines (blank lines, `done = ...` in a
        # generated loop) stop anchoring matches; without it matching is quadratic there.
        self._ops = difflib.SequenceMatcher(None, a, b, autojunk=True).get_opcodes()
        self._starts_a = [op[1] for op in self._ops]
        self._starts_b = [op[3] for op in self._ops]
        self._len_a, self._len_b = len(a), len(b)

    def forward(self, line: int) -> int:
        return self._map(line, self._starts_a, forward=True)

    def backward(self, line: int) -> int:
        return self._map(line, self._starts_b, forward=False)

    def _map(self, line: int, starts: list[int], forward: bool) -> int:
        index = line - 1
        i = max(bisect_right(starts, index) - 1, 0)
        # Skip zero-length ranges on the side we are mapping from.
        while i < len(self._ops):
            tag, i1, i2, j1, j2 = self._ops[i]
            lo, hi, tlo, thi = (i1, i2, j1, j2) if forward else (j1, j2, i1, i2)
            if lo <= index < hi or i == len(self._ops) - 1:
                break
            i += 1
        tag, i1, i2, j1, j2 = self._ops[i]
        lo, hi, tlo, thi = (i1, i2, j1, j2) if forward else (j1, j2, i1, i2)
        if thi == tlo:  # deleted lines map to where they were
            target = tlo
        else:
            target = tlo + min(index - lo, thi - tlo - 1)
        limit = self._len_b if forward else self._len_a
        return max(1, min(target + 1, max(limit, 1)))


def unified_diff(path: str, transformed: Transformed) -> str:
    before = transformed.original.decode(transformed.encoding).splitlines(keepends=True)
    after = transformed.rewritten.decode(transformed.encoding).splitlines(keepends=True)
    lines = []
    old, new = (path, path) if os.path.isabs(path) else (f"a/{path}", f"b/{path}")
    for line in difflib.unified_diff(before, after, fromfile=old, tofile=new):
        if not line.endswith(("\n", "\r")):
            line += "\n\\ No newline at end of file\n"
        lines.append(line)
    return "".join(lines)


def write_atomically(path: Path, data: bytes, *, expected: bytes | None = None) -> None:
    """Write via a temporary file in the same folder, keep mode and owner, then replace.

    With ``expected``, refuse (``writes.ChangedOnDisk``) if the file no longer holds
    those bytes. See ``gymmigrate.writes``.
    """
    from gymmigrate import writes

    writes.write_atomically(path, data, expected=expected)


def process_file(
    path: Path,
    options: RewriteOptions,
    *,
    write: bool,
    want_diff: bool,
    display_path: str | None = None,
    lint: bool = False,
) -> FileResult:
    """Read, rewrite, verify and (if asked) write one file. Never raises for bad input.

    ``lint`` (``gymmigrate check``): only decide; the findings and whether the file would
    change come from the plan, with no LibCST tree and no verification run.
    """
    from gymmigrate.safety import MAX_SOURCE_BYTES, Refused, read_source, screen
    from gymmigrate.sources import adapter_for
    from gymmigrate.sources.programs import document_diff, lint_document, transform_document
    from gymmigrate.writes import ChangedOnDisk

    shown = display_path or str(path)
    # Dependency declarations (gymmigrate.dependencies): a path of their own. [deps branch]
    from gymmigrate.dependencies import is_dependency_file
    from gymmigrate.dependencies.process import lint_page_commands, process_dependency_file, with_page_commands

    if is_dependency_file(path):
        return process_dependency_file(path, shown, write=write, want_diff=want_diff, lint=lint, selection=options.selection)
    adapter = adapter_for(path)  # notebooks and documentation pages; None for Python source
    try:
        source = read_source(path, may_hold_gym_code, limit=adapter.max_bytes if adapter else MAX_SOURCE_BYTES)
    except Refused as exc:
        return FileResult(shown, Status.ERROR, error=str(exc))
    except OSError as exc:
        return FileResult(shown, Status.ERROR, error=f"cannot read the file: {exc.strerror or exc}")
    try:
        if source is None or not screen(source, may_hold_gym_code):
            return FileResult(shown, Status.SKIPPED)
        if lint:
            if adapter:
                findings, would_change = lint_document(adapter, source, shown, options)
                findings, would_change = lint_page_commands(adapter, path, source, findings, would_change, options.selection)  # [deps branch]
            else:
                findings, would_change = lint_source(source, shown, options)
            return FileResult(shown, Status.CHANGED if would_change else Status.UNCHANGED, findings=tuple(findings))
        if adapter:
            transformed = transform_document(adapter, source, shown, options)
            transformed = with_page_commands(adapter, path, transformed, options.selection)  # pip install lines [deps branch]
        else:
            transformed = transform_source(source, shown, options)
    except (Refused, TransformError) as exc:
        return FileResult(shown, Status.ERROR, error=str(exc))
    except RecursionError:
        return FileResult(shown, Status.ERROR, error="the file is nested too deeply to analyse")
    findings = tuple(transformed.findings)
    if not transformed.changed:
        return FileResult(shown, Status.UNCHANGED, findings=findings)
    diff = None
    if want_diff:
        diff = document_diff(adapter, shown, transformed) if adapter else unified_diff(shown, transformed)
    if write:
        try:
            # ``expected``: an edit saved while this file was being rewritten wins.
            write_atomically(path, transformed.rewritten, expected=source)
        except ChangedOnDisk as exc:
            return FileResult(shown, Status.ERROR, findings=findings, error=f"not rewritten: {exc}; left as it is now")
        except OSError as exc:
            return FileResult(shown, Status.ERROR, findings=findings, error=f"cannot write the file: {exc.strerror or exc}")
    return FileResult(shown, Status.CHANGED, findings=findings, diff=diff, written=write)
