"""One program's migration, pure: text in, text and findings out.

``plan_file`` lets every rule family decide on the same CPython ``ast`` facts;
``lint_source`` (what ``check`` needs) stops there. ``transform_source`` applies the plan
with LibCST, only where it has edits, and verifies the output: it parses, and a second
run changes nothing. No file I/O here: ``process`` reads and writes.
"""

from __future__ import annotations

import ast
import difflib
import os
import re
from bisect import bisect_right
from dataclasses import dataclass, field, replace

from gymmigrate.edits.filtering import filter_plan
from gymmigrate.edits.lazy import cst
from gymmigrate.edits.plan import Plan
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.profile import FileProfile
from gymmigrate.facts.receivers import Receivers
from gymmigrate.findings import Finding, renumber_lines
from gymmigrate.options import RewriteOptions
from gymmigrate.rules import families_for
from gymmigrate.rules.base import FileContext, RuleFamily
from gymmigrate.selection import Selection
from gymmigrate.source_text import (
    TransformError,
    decode,
    first_statement_line,
    parse_python,
)
from gymmigrate.suppressions import skips_file


@dataclass
class Transformed:
    original: bytes
    rewritten: bytes
    encoding: str
    findings: list[Finding] = field(default_factory=list)
    # The families whose edits made this rewrite (named when a rewrite does not settle).
    changed_by: frozenset[str] = frozenset()
    # Only methods were renamed (``Plan.renames_first``): the next round's findings are
    # the file's, review items too.
    renamed_first: bool = False

    @property
    def changed(self) -> bool:
        return self.original != self.rewritten


def _parse_cst(source: bytes | str) -> cst.Module:
    """A whole file (bytes) or a cut of its statements (text)."""
    try:
        return cst.parse_module(source)
    except cst.ParserSyntaxError as exc:
        raise TransformError(f"syntax error at line {exc.raw_line}, column {exc.raw_column}") from None


def transform_source(source: bytes, path: str = "<string>", options: RewriteOptions | None = None) -> Transformed:
    """Migrate ``source`` and verify the output.

    Raises TransformError when the file cannot be parsed, a rule fails, or the output
    would not parse or would change again on a second run.
    """
    options = options or RewriteOptions()
    text, encoding = decode(source)
    tree = parse_python(text, source, path)
    result = _migrate(source, text, encoding, tree, path, options)
    if result.changed:
        result = _settle(result, text, path, options)
    return result


def lint_source(source: bytes, path: str = "<string>", options: RewriteOptions | None = None) -> tuple[list[Finding], bool]:
    """What ``check`` needs: the findings, and whether ``rewrite`` would change the file.

    Costs a CPython parse and the rules' decisions: no LibCST tree, no verification run.
    """
    options = options or RewriteOptions()
    text, _ = decode(source)
    tree = parse_python(text, source, path)
    plan = plan_file(tree, text, path, options)
    if plan.renames_first:
        # What the file needs is decided on the renamed code (the next round).
        result = transform_source(source, path, options)
        return sorted(result.findings), result.changed
    return sorted(plan.findings), plan.has_edits


def plan_file(tree: ast.Module, text: str, path: str, options: RewriteOptions, renames_first: bool = True) -> Plan:
    """Every rule family decides on the same facts; nothing is changed yet.

    ``renames_first``: a family may ask for a round of its renames alone (``Plan.renames_first``)."""
    # names its star imports of the run bind, where its classes derive them
    bindings = options.project.star_bindings.get(os.path.realpath(path)) if options.project is not None else None
    facts = ModuleFacts(tree, text, bindings)
    context = FileContext(path=path, options=options, profile=FileProfile.from_source(text))
    plan = Plan(facts, allow_renames_first=renames_first)
    if skips_file(text, first_statement_line(tree)):
        return plan
    view = options.project.view(path) if options.project is not None else None
    if view is not None:
        facts.is_run_record = view.is_record_class
    receivers = Receivers(facts, view)
    left_out: set[str] = set()
    for family in families_for(text, in_a_run=options.project is not None):
        if not (family.decides_the_module or _family_selected(family, options.selection)):
            left_out.add(family.__name__)
            continue
        if not family.may_fire(facts, context):
            continue
        _decide(family, context, facts, receivers, plan)
        if context.notes.module_kept_for is not None:
            break  # the module stays on gym as it is (a Gym-only plugin makes its envs): its item is all
        if plan.renames_first:
            # The other families decided on the old names (a dead ``_step``): this round is
            # the rename alone, and the next one decides everything on the renamed code.
            plan = Plan(facts)
            _decide(family, context, facts, receivers, plan)
            plan.renames_first = True
            break
    plan.left_out_families = left_out
    filter_plan(plan, text, options)  # --select/--ignore, suppression comments, the changes that go with them
    if plan.renames_first and not plan.has_edits:
        # The renames were left out (--ignore GM616, a suppression): decide as usual.
        return plan_file(tree, text, path, options, renames_first=False)
    plan.ask_once()
    return plan


def _decide(family: type[RuleFamily], context: FileContext, facts: ModuleFacts, receivers: Receivers, plan: Plan) -> None:
    plan.deciding = family.__name__
    try:
        family(context, facts, receivers, plan).decide()
    except RecursionError:
        raise TransformError(f"internal error in {family.__name__}: the code is nested too deeply to analyse") from None
    except Exception as exc:  # a rule bug must not lose the user's file or print a traceback
        raise TransformError(f"internal error in {family.__name__}: {type(exc).__name__}: {exc}") from exc


def _family_selected(family: type[RuleFamily], selection: Selection | None) -> bool:
    """Whether any rule of ``family`` is on: a family with none is not even run (unless it
    decides whether the module is migrated at all, ``RuleFamily.decides_the_module``)."""
    return selection is None or any(selection.allows(rule.code) for rule in family.RULES)


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
    findings = [f.placed(line_map.forward) for f in findings]
    changed_by = frozenset(family for finding, family in zip(plan.findings, plan.finding_families) if finding.is_change)
    return Transformed(
        original=source,
        rewritten=rewritten,
        encoding=encoding,
        findings=findings,
        changed_by=changed_by,
        renamed_first=plan.renames_first,
    )


_UNREPRODUCIBLE = re.compile(r"\r(?!\n)|\f")


def _apply(source: bytes, text: str, plan: Plan) -> str:
    """The rewritten text: only the top-level statements that change are parsed and
    printed again where that is exact (``edits.splice``), else the whole module."""
    # The apply layer, and with it LibCST, loads with the first edit of the process: a
    # run with nothing to change, and ``check``, never import it.
    from gymmigrate.edits.apply import apply_plan
    from gymmigrate.edits.splice import splice_plan

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


# A rewrite that needs more rounds than this to reach its fixed point oscillates.
MAX_ROUNDS = 3


def _settle(first: Transformed, original_text: str, path: str, options: RewriteOptions) -> Transformed:
    """The output must compile, and a further run over it must change nothing.

    As ruff's fix loop does: where the verifying run still finds something to change (one
    rule's output is legacy code another rule reads), that change is applied and verified
    in turn, up to ``MAX_ROUNDS``. Only a real oscillation (a text seen before) or a rewrite
    that does not settle is refused, naming the rules that kept changing it. Each run
    decides on ``ast``; a LibCST tree is built only where a run has edits.
    """
    current, findings, seen = first, list(first.findings), {first.original, first.rewritten}
    for _ in range(MAX_ROUNDS):
        text = _text_of(current.rewritten, current.encoding)
        try:
            tree = ast.parse(text, filename=path)
        except SyntaxError as exc:
            raise TransformError(f"the rewrite would not parse (line {exc.lineno}: {exc.msg}); file left unchanged") from None
        again = _migrate(current.rewritten, text, current.encoding, tree, path, options)
        settled = again.rewritten == current.rewritten
        if settled and not current.renamed_first:
            if current is first:
                return first
            final = _text_of(current.rewritten, current.encoding)
            return replace(current, original=first.original, findings=_placed(findings, original_text, final))
        if not settled and again.rewritten in seen:
            raise TransformError(
                f"the rewrite oscillates ({', '.join(sorted(again.changed_by))} undo what another round wrote); file left unchanged"
            )
        seen.add(again.rewritten)
        # The later round's own changes, placed in the original by way of the text it read.
        back = LineMap(original_text, text)
        # Its message names lines of that text too ("the same question at line 12"): they
        # follow the same way, so the item reads the original throughout. After a round of
        # renames alone every finding of the next is the file's, whether or not it changes
        # anything more (a review item on a renamed call is all there may be).
        findings += [
            replace(f, line=back.backward(f.line), message=renumber_lines(f.message, back.backward))
            for f in again.findings
            if f.is_change or current.renamed_first
        ]
        if settled:
            final = _text_of(current.rewritten, current.encoding)
            return replace(current, original=first.original, findings=_placed(findings, original_text, final))
        current = again
    raise TransformError(
        f"the rewrite does not settle after {MAX_ROUNDS} rounds ({', '.join(sorted(current.changed_by))} kept changing it); "
        "file left unchanged"
    )


def _text_of(data: bytes, encoding: str) -> str:
    text = data.decode(encoding)
    return text.removeprefix("\ufeff") if encoding == "utf-8-sig" else text


def _placed(findings: list[Finding], original: str, final: str) -> list[Finding]:
    """Every finding with its line in the original and in the final output."""
    forward = LineMap(original, final)
    return sorted(f.placed(forward.forward) for f in findings)


class LineMap:
    """Maps line numbers between two versions of a text (1-based), via difflib opcodes."""

    def __init__(self, before: str, after: str) -> None:
        a = before.splitlines()
        b = after.splitlines()
        self._lines = (a, b)
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
        elif tag == "replace":
            target = self._likeliest(index, lo, hi, tlo, thi, forward)
        else:
            target = tlo + min(index - lo, thi - tlo - 1)
        limit = self._len_b if forward else self._len_a
        return max(1, min(target + 1, max(limit, 1)))


    def _likeliest(self, index: int, lo: int, hi: int, tlo: int, thi: int, forward: bool) -> int:
        """Where a line of a replaced run went: the line of the other side's run that reads
        most like it (`obs = env.reset()` -> `obs, info = env.reset()`), not its offset in the
        run, which a rule's added line (`done = terminated or truncated`) pushes off by one.
        Among equally alike lines, the one nearest its offset; by offset alone where nothing
        reads alike (a statement rewritten beyond recognition)."""
        source, target = self._lines if forward else self._lines[::-1]
        offset = tlo + min(index - lo, thi - tlo - 1)
        # a long run is searched near the offset only: each look costs a comparison per line
        window = range(max(tlo, offset - _REPLACED_WINDOW), min(thi, offset + _REPLACED_WINDOW + 1))
        text = source[index].strip()
        best, best_ratio = offset, _ALIKE
        for candidate in window:
            matcher = difflib.SequenceMatcher(None, text, target[candidate].strip(), autojunk=False)
            if matcher.real_quick_ratio() < best_ratio or matcher.quick_ratio() < best_ratio:
                continue
            ratio = matcher.ratio()
            if ratio > best_ratio or (ratio == best_ratio and abs(candidate - offset) < abs(best - offset)):
                best, best_ratio = candidate, ratio
        return best


# How alike (difflib's ratio) a line of a replaced run must read to be taken for a rewritten
# one, and how far from its offset in the run it is looked for.
_ALIKE = 0.6
_REPLACED_WINDOW = 20


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
