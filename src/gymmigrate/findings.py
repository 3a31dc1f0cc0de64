"""What a rule reports: one `Finding` per change made or place to review.

Findings are small frozen dataclasses so that a process pool can return them and
every output format (summary, JSON report, later SARIF/GitHub annotations) reads the
same record: rule id, position, fix kind, tier and a one-sentence message.

Two tiers: *review* items are places where a person must decide (the summary lists
them); *notes* explain rewrites already applied (the summary counts them, the JSON
report lists them). The tier follows from the kind (auto -> note, assist/flag ->
review) unless the rule says otherwise: an assist rewrite whose shift is fully
explained and asks nothing of the reader (``__init__`` gains ``render_mode=None``)
is a note.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import asdict, dataclass, field, fields, replace
from enum import Enum


class FixKind(str, Enum):
    """How a rule acted on a site, after the catalog's legend.

    AUTO    rewritten; the meaning is unchanged.
    ASSIST  rewritten, but the meaning may have shifted: a person must review it.
    FLAG    not rewritten: a person must look and decide.
    """

    AUTO = "auto"
    ASSIST = "assist"
    FLAG = "flag"

    @property
    def rewrites(self) -> bool:
        return self is not FixKind.FLAG

    @property
    def needs_review(self) -> bool:
        return self is not FixKind.AUTO


class Tier(str, Enum):
    """Where a finding is shown: REVIEW needs a person's decision, NOTE explains a rewrite."""

    REVIEW = "review"
    NOTE = "note"

    @classmethod
    def of(cls, kind: FixKind) -> Tier:
        return cls.REVIEW if kind.needs_review else cls.NOTE


# The first item of a question key that the files of a run share: the question (where a
# class's ``self.env`` comes from) belongs to the run, and ``report.decide_once`` asks it once.
# Such a key is ``(RUN_QUESTION, action, path of the module that decides it, ...)``.
RUN_QUESTION = "run"
_QUESTION_SEPARATOR = "\n"


def gym_only_question(stack: str) -> tuple[str, ...]:
    """What every place an env of a Gym-only library stack (GM107) asks: how that stack is
    ported. Its imports, wrappers and the resets and steps of its envs in every module are
    one decision of the run, asked in the first file by path (no module's code decides it)."""
    return (RUN_QUESTION, "gym-only-library", "", stack)


def removed_helper_question(module: str, name: str) -> tuple[str, ...]:
    """What the import of a name Gymnasium removed (GM105) and every use of it in the file
    (GM506 ``hash_seed(...)``) ask: what replaces it. One decision per file, asked at the
    first of those lines; the others are listed as notes pointing at it."""
    return ("removed-helper", module, name)


def configure_hook_question() -> tuple[str, ...]:
    """What every env class whose gym < 0.9 ``_configure`` hook was renamed ``configure``
    asks where the run calls ``x.configure(...)``: how those callers reach it now. One
    decision of the run, asked in the first file by path."""
    return (RUN_QUESTION, "configure-hook", "", "configure")


def rllib_question() -> tuple[str, ...]:
    """What every module importing RLlib next to gym asks (GM107): the ray release, and
    with it the multi-agent env API, the project's RLlib code moves to. One decision of the
    run, asked in the first file by path."""
    return (RUN_QUESTION, "rllib-era", "", "ray")


def id_version_question(rule: str, change: str) -> tuple[str, ...]:
    """What every bump of a retired env id to a version that behaves differently asks: does
    the program accept that change (a policy or normaliser saved on the old version)? The
    change is the catalog's reason for the step (``env_ids/catalog.py``): ids whose bump
    gives the same one (every MuJoCo ``-v3`` -> ``-v4``) ask one decision, wherever they
    are in the run, asked in the first file by path."""
    return (RUN_QUESTION, "id-version", "", rule, change)


def kept_render_question(path: str, name: str) -> tuple[str, ...]:
    """What a class of the run whose render(mode) keeps ``mode`` for the untraced
    ``x.render(mode)`` calls of other modules asks (GM405 at its def), and what each of those
    calls asks where that class is the one render(mode) its module can reach: one decision,
    asked at the def (``path``, the deciding module); the calls are listed there."""
    return (RUN_QUESTION, "kept-render-mode", path, name)


def recorder_mode_question(line: int, column: int) -> tuple[object, ...]:
    """What a Monitor call turned RecordVideo asks wherever it keeps a question: the mode its
    env is made with (GM407, creation site not found) and the arguments it dropped (GM611),
    at one call, are one review item; the other points at it."""
    return ("recorder-call", line, column)


def run_question_text(question: object) -> str | None:
    """``Finding.question`` for a question key of a rule: its text where the run shares it."""
    if isinstance(question, tuple) and question[:1] == (RUN_QUESTION,):
        return _QUESTION_SEPARATOR.join(str(part) for part in question)
    return None


def deciding_module(question: str) -> str:
    """The path of the module whose code decides a run's question (see RUN_QUESTION)."""
    parts = question.split(_QUESTION_SEPARATOR)
    return parts[2] if len(parts) > 2 else ""


@dataclass(frozen=True, order=True)
class Finding:
    """One change or review item, positioned in the original source (1-based line, 0-based column).

    ``line_after`` is the same place in the rewritten source, when the file changed, and
    ``message_after`` the message naming the rewritten source's lines (``placed``): a
    person reading a rewritten file reads both, so one item never mixes the two versions.
    ``end_line``/``end_column`` close the span of the node reported (SARIF, editors).
    ``cell`` is the notebook cell (0-based) when the file is a notebook; ``line`` is
    then counted within that cell.
    ``tier`` defaults to what the kind implies (``Tier.of(kind)``).
    """

    line: int
    column: int
    rule: str
    kind: FixKind
    message: str
    line_after: int | None = None
    end_line: int | None = None
    end_column: int | None = None
    cell: int | None = None
    tier: Tier | None = None
    # A question the files of a run share (see RUN_QUESTION), spelled as text; not reported.
    question: str | None = field(default=None, compare=False, metadata={"internal": True})
    # The message with the lines it names in the rewritten source, set with ``line_after``; not
    # reported (the JSON's message, like its ``line``, reads the source).
    message_after: str | None = field(default=None, compare=False, metadata={"internal": True})

    def __post_init__(self) -> None:
        if self.tier is None:
            object.__setattr__(self, "tier", Tier.of(self.kind))

    @property
    def is_change(self) -> bool:
        return self.kind.rewrites

    @property
    def needs_review(self) -> bool:
        return self.tier is Tier.REVIEW

    def placed(self, forward: Callable[[int], int]) -> Finding:
        """This finding placed in the rewritten source too, by ``forward`` (a source line to
        the rewritten one): its own line, and every line its message names."""
        return replace(self, line_after=forward(self.line), message_after=renumber_lines(self.message, forward))

    def to_json(self) -> dict[str, object]:
        """Every field but the internal ones (``metadata={"internal": True}``)."""
        data = {key: value for key, value in asdict(self).items() if not _INTERNAL.get(key)}
        data["kind"] = self.kind.value
        data["tier"] = self.tier.value  # type: ignore[union-attr]
        return data


# How a message names lines of its own file: "line 48", "lines 10, 12" (another file's are
# "path:line"). Every rule spells them so, which lets the lines follow the file when it is
# rewritten (``renumber_lines``) or split into a notebook's cells (``sources.programs``).
NAMED_LINES = re.compile(r"\blines? (\d+(?:, \d+)*)")


def renumber_lines(message: str, renumber: Callable[[int], int]) -> str:
    """``message`` with each line of its own file it names passed through ``renumber``. Two
    lines that fall on one (a statement rewritten as one line) are named once."""

    def renumbered(match: re.Match[str]) -> str:
        lines = list(dict.fromkeys(renumber(int(number)) for number in match[1].split(", ")))
        return f"{'line' if len(lines) == 1 else 'lines'} {', '.join(map(str, lines))}"

    return NAMED_LINES.sub(renumbered, message)


_INTERNAL = {f.name: bool(f.metadata.get("internal")) for f in fields(Finding)}
