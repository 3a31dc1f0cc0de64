"""What the rules decided for one file: findings, and the edits that carry them out.

Rules decide from ``ModuleFacts`` (CPython ``ast``) and record here *what* to change,
addressed by ``ast`` nodes. Nothing is changed while rules decide: every rule sees the
same original module, so one run reaches the fixed point, and a file whose plan holds
no edit never pays for a LibCST tree. ``gymmigrate.edits.apply`` then carries out all
edits in one traversal.
"""

from __future__ import annotations

import ast
from bisect import bisect_left
from collections import defaultdict
from collections.abc import Callable, Hashable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

from gymmigrate.findings import Finding, FixKind, Tier, run_question_text

if TYPE_CHECKING:
    from gymmigrate.facts import ModuleFacts

# Receives the node as already changed by edits inside it; returns its replacement
# (a node, or a LibCST FlattenSentinel / RemovalSentinel where the parent allows it).
# The parameter is the LibCST counterpart of the ``ast`` node given to ``replace``: its
# class (``cst.Call`` for an ``ast.Call``, ...) is known to the rule, not to the plan, so
# a build may annotate it with the class it expects.
Build = Callable[..., Any]  # called with that one node; a lambda may bind values as defaults


@dataclass(frozen=True)
class Need:
    """What a change reads that only another family's edit makes: a parameter that family
    adds to a signature (GM207 reads the ``options`` GM501 gives an env's reset). The
    change is kept only while an edit of ``family`` on ``node``, or on a class or function
    around it, is kept (``edits.filtering``); else it is reported, not made. ``what``
    names that edit in the report."""

    family: str
    node: ast.AST
    what: str


# Items that join another's question but are named apart in it, with what they are: per
# rule, the phrase of the item's own advice and the words the question names its lines with
# (an unrewritten step's done that masks a bootstrap, or that ends the episode).
# The suffix keeps no parentheses inside it (``report._SAME_IN_FILE`` strips it whole).
UNTRACED_MASK = "read `terminated` once the step gives five values"
UNTRACED_BOUNDARY = "keep `terminated or truncated` there"
UNTRACED_SPLIT = "split the test"
# The words naming an env's own methods and attributes in its question (``Plan.join``).
_OWN_USES = (
    "the env's own methods and attributes, which a Gymnasium wrapper no longer forwards: "
    "if it is a Gym env, read them through `.unwrapped` or `get_wrapper_attr`"
)
_NAMED_APART = {
    "GM302": (
        (UNTRACED_MASK, "where the step's done decides bootstrapping: read `terminated` there once the step gives five values"),
        (UNTRACED_BOUNDARY, "where the step's done marks the episode's boundary: keep `terminated or truncated` there"),
        (UNTRACED_SPLIT, "where the step's done both ends the episode and replaces the next state: split the test, reset under `terminated or truncated`, replace under `terminated`"),
    )
}


@dataclass
class Plan:
    """Findings and edits for one file, in the order the rules produced them."""

    facts: ModuleFacts
    findings: list[Finding] = field(default_factory=list)
    replacements: dict[ast.AST, list[Build]] = field(default_factory=lambda: defaultdict(list))
    before: dict[ast.stmt, list[Any]] = field(default_factory=lambda: defaultdict(list))
    after: dict[ast.stmt, list[Any]] = field(default_factory=lambda: defaultdict(list))
    removed: set[ast.stmt] = field(default_factory=set)
    # Removed statements whose comment lines (above them) move to the next statement.
    keep_comments: set[ast.stmt] = field(default_factory=set)
    imports: list[str] = field(default_factory=list)  # new top-level import lines
    # Which finding each edit carries out, so a finding dropped by rule selection or a
    # suppression comment takes its fix with it (``drop_findings``). ``deciding`` names
    # the family deciding now (set by the engine).
    deciding: str = ""
    finding_nodes: list[ast.AST] = field(default_factory=list)
    finding_families: list[str] = field(default_factory=list)  # the family that reported each
    # The question each review item asks, where rules name one (``ask_once``): items of one
    # file asking the same question (is this receiver a Gym env?) are one decision.
    finding_questions: list[Hashable | None] = field(default_factory=list)
    finding_needs: list[Need | None] = field(default_factory=list)  # see ``Need``
    # Lines whose code depends on the answer to a question but that no rule reports on their
    # own (``join``): an untraced env's own methods and attributes, which a Gymnasium wrapper
    # no longer forwards. The item asking that question names them; with no item, nothing.
    joined: dict[Hashable, set[int]] = field(default_factory=lambda: defaultdict(set))
    # Changes of one file that are made at every place or at none (GM207's reset contract):
    # findings with the same key are kept or left out together (``edits.filtering``).
    finding_groups: list[Hashable | None] = field(default_factory=list)
    # Families the engine did not run because the selection leaves out every rule of theirs:
    # a change that needs one of their edits is left out with them.
    left_out_families: set[str] = field(default_factory=set)
    _edits: list[_Edit] = field(default_factory=list)
    partial: bool = False  # some findings were dropped (with their edits)
    # A family renamed methods every other family must decide on under their new names
    # (gym < 0.9's ``_step`` -> ``step``, GM616): the engine applies that family's plan alone
    # and lets the next round decide everything on the renamed code.
    renames_first: bool = False
    allow_renames_first: bool = True  # False: the renames were left out, decide as usual
    _seen: set[tuple[int, str, str]] = field(default_factory=set)

    @property
    def has_edits(self) -> bool:
        return bool(self.replacements or self.before or self.after or self.removed or self.imports)

    # -- findings -------------------------------------------------------------------------

    def report(
        self,
        node: ast.AST,
        code: str,
        kind: FixKind,
        message: str,
        tier: Tier | None = None,
        question: Hashable | None = None,
        needs: Need | None = None,
        together: Hashable | None = None,
    ) -> None:
        line = node.lineno  # type: ignore[attr-defined]
        column = self.facts.column(node)
        # Two routes to the same conclusion, or the same item at two columns of one line
        # (`env.render(); env.render()`): one item.
        key = (line, code, message)
        if key in self._seen:
            return
        self._seen.add(key)
        self.finding_nodes.append(node)
        self.finding_families.append(self.deciding)
        self.finding_questions.append(question)
        self.finding_needs.append(needs)
        self.finding_groups.append(together)
        end_line, end_column = self.facts.end(node)
        self.findings.append(
            Finding(
                line=line,
                column=column,
                rule=code,
                kind=kind,
                message=message,
                end_line=end_line,
                end_column=end_column,
                tier=tier,
                question=run_question_text(question),
            )
        )

    def join(self, question: Hashable, line: int) -> None:
        """``line`` depends on the answer to ``question``: named by the item that asks it, if one does."""
        self.joined[question].add(line)

    def ask_once(self) -> None:
        """One review item per question: where several review items of the file ask the same
        question (the same untraced receiver, in one function or one class), the first one
        asks it and names the other lines; the others become notes that point at it, so
        every place is still listed (``check``, the JSON report) and decided once."""
        groups: dict[Hashable, list[int]] = defaultdict(list)
        for index, question in enumerate(self.finding_questions):
            if question is not None and self.findings[index].needs_review:
                groups[question].append(index)
        for question, indexes in groups.items():
            if len(indexes) < 2 and not self.joined.get(question):
                continue
            # at one place, the item left for a person (not rewritten) asks, the rewrite points at it
            indexes.sort(key=lambda i: (self.findings[i].line, self.findings[i].column, self.findings[i].kind is not FixKind.FLAG))
            first, *others = indexes
            # the reads of a step's done that decide bootstrapping (GM302) are named apart: they
            # are what must change beyond the API if the answer is "a Gym env"
            head = self.findings[first]
            apart: dict[str, set[int]] = {}
            for i in others:
                finding = self.findings[i]
                if finding.rule == head.rule or finding.line == head.line:
                    continue
                for phrase, words in _NAMED_APART.get(finding.rule, ()):
                    if phrase in finding.message:
                        apart.setdefault(words, set()).add(finding.line)
                        break
            named = set().union(*apart.values())
            lines = sorted({self.findings[i].line for i in others} - {head.line} - named)
            parts = [f"{'line' if len(lines) == 1 else 'lines'} {', '.join(map(str, lines))}"] if lines else []
            own = sorted(self.joined.get(question, set()) - {self.findings[i].line for i in indexes} - named)
            if own:
                # no finding of their own: the answer decides them too (a wrapper stack no longer forwards them)
                apart[_OWN_USES] = set(own)
            for words, word_lines in apart.items():
                where = "line" if len(word_lines) == 1 else "lines"
                parts.append(f"{'and at ' if parts else ''}{where} {', '.join(map(str, sorted(word_lines)))}, {words}")
            if parts:
                also = f" (the same question at {'; '.join(parts)})"
                self.findings[first] = replace(self.findings[first], message=self.findings[first].message + also)
            for i in others:
                finding = self.findings[i]
                self.findings[i] = replace(
                    finding, message=f"{finding.message} (asked once, at line {self.findings[first].line})", tier=Tier.NOTE
                )

    # -- edits ----------------------------------------------------------------------------

    def replace(self, node: ast.AST, build: Build) -> None:
        """Replace the LibCST counterpart of ``node`` with ``build(node_as_changed)``."""
        self.replacements[node].append(build)
        self._record(node, self.replacements, node, build)

    def insert_before(self, statement: ast.stmt, *code: Any) -> None:
        self.before[statement].extend(code)
        for item in code:
            self._record(statement, self.before, statement, item)

    def insert_after(self, statement: ast.stmt, *code: Any) -> None:
        self.after[statement].extend(code)
        for item in code:
            self._record(statement, self.after, statement, item)

    def withdraw(self, statement: ast.stmt, code: Any) -> None:
        """Take back one piece of ``code`` inserted around ``statement`` (the very object
        given to ``insert_before``/``insert_after``): a later family that removes the last
        reader of an inserted line (e.g. ``done = terminated or truncated``) drops it."""
        for inserted in (self.before, self.after):
            items = inserted.get(statement)
            if items is None:
                continue
            for index, item in enumerate(items):
                if item is code:
                    del items[index]
                    if not items:
                        del inserted[statement]
                    return

    def remove(self, statement: ast.stmt, keep_comments: bool = False) -> None:
        """Delete ``statement``; with ``keep_comments``, the comment lines above it stay,
        above the statement that follows it in its block."""
        self.removed.add(statement)
        if keep_comments:
            self.keep_comments.add(statement)
        self._record(statement, self.removed, statement, statement)

    def add_import(self, line: str) -> None:
        """A top-level import statement, added once after the module's last import."""
        if line not in self.imports:
            self.imports.append(line)
        self._record(None, self.imports, None, line)  # every finding that needs it keeps it

    def ensure_import(self, module: str, name: str | None = None, asname: str | None = None) -> str:
        """Make ``module`` (or ``module.name``) available; return the name to use in code."""
        qualified = f"{module}.{name}" if name else module
        bound = self.facts.imported_as(qualified)
        if bound is not None:
            return bound
        if name:
            self.add_import(f"from {module} import {name}" + (f" as {asname}" if asname else ""))
            return asname or name
        self.add_import(f"import {module}" + (f" as {asname}" if asname else ""))
        return asname or module

    # -- which finding an edit carries out --------------------------------------------------

    def _record(self, node: ast.AST | None, container: Any, anchor: Any, item: Any) -> None:
        self._edits.append(_Edit(self.deciding, node, len(self.findings), container, anchor, item))

    def drop_findings(self, dropped: set[int], flagged: dict[int, str] | None = None) -> None:
        """Drop the findings at these indexes and every edit that only carries them out.

        ``flagged``: findings among ``dropped`` that stay, as items not rewritten, with
        the message given (a change left out because one it goes with is).

        Rules do not say which finding an edit serves, so it is read from how they
        decide. Only findings of the family that made the edit, and only changes (a flag
        finding is "not rewritten"), are candidates: every finding inside a class or
        function the edit rebuilds whole; else every one on the very node edited; else
        the one on the same statement, in the same function, or of the family, that was
        reported next after the edit (rules record a decision's edits, then report it),
        else the one just before. An import line serves both neighbours. An edit is dropped when every
        finding it serves is; one that serves none is kept.
        ``tests/test_selection.py`` holds this to every fixture of every rule.
        """
        if not dropped:
            return
        self.partial = True
        for edits, served in self._edit_groups():
            if served and served <= dropped:
                for edit in edits:
                    edit.undo()
        flagged = flagged or {}
        for index, message in flagged.items():
            # "not rewritten": a review item of its own, asked of nobody else
            self.findings[index] = replace(self.findings[index], kind=FixKind.FLAG, tier=None, message=message)
            self.finding_questions[index] = None
            self.finding_needs[index] = None
            self.finding_groups[index] = None
        gone = dropped - flagged.keys()
        self.findings = [f for i, f in enumerate(self.findings) if i not in gone]
        self.finding_nodes = [n for i, n in enumerate(self.finding_nodes) if i not in gone]
        self.finding_families = [f for i, f in enumerate(self.finding_families) if i not in gone]
        self.finding_questions = [q for i, q in enumerate(self.finding_questions) if i not in gone]
        self.finding_needs = [n for i, n in enumerate(self.finding_needs) if i not in gone]
        self.finding_groups = [g for i, g in enumerate(self.finding_groups) if i not in gone]
        self._edits = []

    def kept_edits(self, dropped: set[int]) -> set[tuple[str, int]]:
        """``(family, id(node))`` of each edit ``drop_findings(dropped)`` would keep (nothing
        is changed yet); an import line's node is None."""
        return {(edit.family, id(edit.node)) for edits, served in self._edit_groups() if not (served and served <= dropped) for edit in edits}

    def _edit_groups(self) -> list[tuple[list[_Edit], set[int]]]:
        """The recorded edits, grouped where they are one change, each group with the
        findings it serves (``drop_findings``)."""
        by_node: dict[tuple[str, int], list[int]] = defaultdict(list)
        by_statement: dict[tuple[str, int], list[int]] = defaultdict(list)
        changes: dict[str, list[int]] = defaultdict(list)  # by family, in report order
        by_function: dict[tuple[str, int], list[int]] = defaultdict(list)  # changes, in report order
        for index, node in enumerate(self.finding_nodes):
            family = self.finding_families[index]
            if self.findings[index].is_change:
                changes[family].append(index)
            by_node[family, id(node)].append(index)
            by_statement[family, id(self.facts.statement_of(node))].append(index)
            if self.findings[index].is_change:
                by_function[family, id(self.facts.enclosing_function(node))].append(index)
        serves: dict[tuple[int, int, object], set[int]] = defaultdict(set)
        edits: dict[tuple[int, int, object], list[_Edit]] = defaultdict(list)
        for edit in self._edits:
            # An import line is one edit however many findings asked for it; two edits
            # that share a key (the same change asked for twice) go or stay together.
            key = (id(edit.container), id(edit.anchor), edit.item if edit.container is self.imports else id(edit.item))
            edits[key].append(edit)
            serves[key].update(self._served_by(edit, by_node, by_statement, by_function, changes))
        return [(edits[key], serves[key]) for key in edits]

    def _served_by(
        self, edit: _Edit, by_node: dict, by_statement: dict, by_function: dict, changes: dict[str, list[int]]
    ) -> list[int]:
        # Rules record a decision's edits just before reporting it, as a rule: the next
        # finding of the family first, among those on the same node or statement if any.
        # A flag finding is "not rewritten": no edit serves it.
        family = changes.get(edit.family, [])
        if edit.node is None:
            # An import serves both neighbours: an import kept for nothing is harmless,
            # one dropped under a kept edit is a NameError.
            return [i for i in (_next(family, edit.reported), _previous(family, edit.reported)) if i is not None]
        inside = self._inside(edit, family)
        if inside:
            return inside
        # Several findings on the very node edited: which one it serves cannot be told,
        # so it serves them all (kept while any of them is).
        same = [index for index in by_node.get((edit.family, id(edit.node)), ()) if self.findings[index].is_change]
        if same:
            return same
        near = by_statement.get((edit.family, id(self.facts.statement_of(edit.node))), ())
        candidates = (
            [index for index in near if self.findings[index].is_change]
            or by_function.get((edit.family, id(self.facts.enclosing_function(edit.node))))
            or family
        )
        chosen = _next(candidates, edit.reported)
        if chosen is None:
            chosen = _previous(candidates, edit.reported)
        return [chosen] if chosen is not None else []

    def _inside(self, edit: _Edit, family: list[int]) -> list[int]:
        """The family's changes inside a class or function the edit rebuilds whole."""
        node = edit.node
        if not isinstance(node, (ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            return []
        first, last = node.lineno, node.end_lineno or node.lineno
        return [index for index in family if first <= self.findings[index].line <= last]


def _next(indexes: list[int], position: int) -> int | None:
    """The first of the sorted ``indexes`` at or after ``position``."""
    at = bisect_left(indexes, position)
    return indexes[at] if at < len(indexes) else None


def _previous(indexes: list[int], position: int) -> int | None:
    """The last of the sorted ``indexes`` before ``position``."""
    at = bisect_left(indexes, position)
    return indexes[at - 1] if at > 0 else None


@dataclass
class _Edit:
    """One recorded edit: who made it, when, and where it sits in the plan."""

    family: str
    node: ast.AST | None
    reported: int  # how many findings existed when it was made
    container: Any
    anchor: Any
    item: Any

    def undo(self) -> None:
        container = self.container
        if isinstance(container, set):
            container.discard(self.item)
        elif isinstance(container, list):
            if self.item in container:
                container.remove(self.item)
        else:  # a dict of lists, by node
            items = container.get(self.anchor, [])
            for index, existing in enumerate(items):
                if existing is self.item:
                    del items[index]
                    break
            if not items and self.anchor in container:
                del container[self.anchor]
