"""Requirements located in a text, decided, and written back in place.

A format module finds its requirement strings (``Site``: where the string is, and which
span goes when it is redundant) and leaves everything else to ``migrate_sites``: one
decision per requirement (``mapping.decide``), ale-py deduplicated, edits applied to
those spans only, findings placed. Every byte outside a changed requirement is kept.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from packaging.utils import canonicalize_name

from gymmigrate.dependencies import mapping
from gymmigrate.dependencies.mapping import GYM_ONLY, Decision, Note
from gymmigrate.dependencies.positions import Positions
from gymmigrate.findings import Finding, FixKind


@dataclass(frozen=True)
class Site:
    """A requirement string at ``text[start:end]`` (without quotes)."""

    start: int
    end: int
    removal: tuple[int, int] | None = None  # the span deleted when the requirement is redundant
    hashed: bool = False  # pinned by ``--hash`` options (requirements files)
    conda: bool = False  # a conda match spec (``gym=0.21``), not PEP 508
    bare_word: bool = False  # an unquoted shell word: quote the new text if the shell would split it
    group: object = None  # requirements installed together (one list, one command): ale-py is deduplicated within it


@dataclass(frozen=True)
class Edit:
    """``text[start:end]`` becomes ``text``. ``code`` is the rule the edit carries out (a
    run that leaves the rule out drops the edit); ``companions`` are findings that exist
    only because of the edit (the --hash warning)."""

    start: int
    end: int
    text: str
    code: str = mapping.GYM_PACKAGE
    companions: tuple[Finding, ...] = ()


@dataclass
class Outcome:
    """Edits and findings for one text; ``decided`` maps each requirement text that changes
    to its new text ("" when it is removed), for formats that verify the result."""

    edits: list[Edit] = field(default_factory=list)
    findings: list[Finding] = field(default_factory=list)
    decided: dict[str, str] = field(default_factory=dict)
    # every PEP 508 requirement read: (its site, its canonical name), for ``companions``
    declared: list[tuple[Site, str]] = field(default_factory=list)


def finding(positions: Positions, start: int, end: int, note: Note) -> Finding:
    line, column = positions.of(start)
    end_line, end_column = positions.of(end)
    return Finding(line, column, note.code, note.kind, note.message, end_line=end_line, end_column=end_column)


_CONDA_SPEC = re.compile(r"(?:(?P<channel>[\w.-]+)::)?(?P<name>[A-Za-z0-9_.-]+)\s*(?P<rest>.*)", re.S)


def _decide_conda(text: str) -> Decision | None:
    match = _CONDA_SPEC.fullmatch(text.strip())
    if match is None:
        return None
    name = canonicalize_name(match["name"])
    if name == "gym":
        return Decision(
            "gymnasium",
            [],
            mapping.GYMNASIUM_SPEC,
            [Note(mapping.GYM_PACKAGE, FixKind.ASSIST, f"conda `{text.strip()}` -> `gymnasium{mapping.GYMNASIUM_SPEC}` (conda-forge): the code must be migrated with it")],
        )
    if name in mapping.GYM_ONLY_PACKAGES or name in mapping.ALE_PREDECESSORS or name in mapping.MOVED_WITH_GYM:
        return Decision(notes=[Note(GYM_ONLY, FixKind.FLAG, f"conda `{text.strip()}`: check it has a release for Gymnasium 1.x (see docs/dependencies.md)")])
    return Decision()


def migrate_sites(text: str, sites: list[Site], positions: Positions | None = None) -> Outcome:
    positions = positions or Positions(text)
    outcome = Outcome()
    decided: list[tuple[Site, str, Decision]] = []
    for site in sites:
        raw = text[site.start : site.end]
        if site.conda:
            decision = _decide_conda(raw)
            if decision is None:
                continue
        else:
            requirement = mapping.parse(raw.strip())
            if requirement is None:
                if mapping.mentions_gym(raw):
                    note = Note(GYM_ONLY, FixKind.FLAG, f"cannot read the requirement `{raw.strip()}`; left as it is: check it by hand")
                    outcome.findings.append(finding(positions, site.start, site.end, note))
                continue
            decision = mapping.decide(requirement)
            outcome.declared.append((site, canonicalize_name(requirement.name)))
        decided.append((site, raw, decision))

    # PettingZoo's Atari envs (multi-agent-ale-py) still take their ROMs from AutoROM.
    if any(_needs_autorom(raw, site) for site, raw, _ in decided):
        decided = [
            (site, raw, _autorom_kept(raw) if decision.ale and _name(raw, site) != "atari-py" else decision)
            for site, raw, decision in decided
        ]
    # ale-py: the Atari extra of gymnasium already requires it; keep one at most per group.
    has_ale: set[object] = set()
    for site, raw, decision in decided:
        if (decision.name == "gymnasium" and {"atari", "all"} & set(decision.extras)) or _is_ale_already(raw, decision, site):
            has_ale.add(site.group)
    for site, raw, decision in decided:
        new: str | None = None
        notes = list(decision.notes)
        if decision.ale and site.group in has_ale and site.removal is not None:
            outcome.edits.append(Edit(*site.removal, "", code=mapping.GYM_PACKAGE))
            outcome.decided[raw] = ""
            notes = [Note(mapping.GYM_PACKAGE, FixKind.AUTO, f"`{raw.strip()}` removed: ale-py (required by gymnasium[atari] or listed here) ships the Atari ROMs")]
        elif decision.rewrites:
            new = _conda_render(raw, decision) if site.conda else mapping.render_pep508(raw, decision)
            if site.bare_word and re.search(r"[\s<>|&;()$`\\\"']", new):
                new = f'"{new}"'  # `>=` unquoted would be a redirection
            if decision.ale:
                has_ale.add(site.group)
        if new is not None and new != raw:
            companions: tuple[Finding, ...] = ()
            if site.hashed:
                hashes = Note(GYM_ONLY, FixKind.FLAG, "this requirement is pinned by --hash: the hashes belong to the old package; regenerate them (pip-compile --generate-hashes)")
                companions = (finding(positions, site.start, site.end, hashes),)
            code = next((note.code for note in decision.notes if note.kind.rewrites), mapping.GYM_PACKAGE)
            outcome.edits.append(Edit(site.start, site.end, new, code=code, companions=companions))
            outcome.decided[raw] = new
        elif decision.rewrites and new == raw:
            notes = []
        outcome.findings.extend(finding(positions, site.start, site.end, note) for note in notes)
    return outcome


def companions(text: str, outcome: Outcome, requires: frozenset[str], positions: Positions | None = None) -> None:
    """Packages the migrated code imports that moved out of a declared one (``mpe2`` out of
    ``pettingzoo``): once per file, a line is added after the first requirement of that
    library, in the same list and style (``"pettingzoo>=1.21",`` -> ``"mpe2>=1.0",`` below
    it), where that requirement has a line of its own; elsewhere the place is reported."""
    positions = positions or Positions(text)
    declared = {name for _, name in outcome.declared}
    for package in sorted(requires - declared):
        companion = mapping.COMPANIONS.get(package)
        if companion is None:
            continue
        anchor, requirement, why = companion
        site = next((site for site, name in outcome.declared if name == anchor), None)
        if site is None:
            continue  # the file does not declare the library it came out of: not this file's business
        line = line_span(text, site.start, site.end)
        suffix = text[site.end : line[1]] if line is not None else ""
        if "#" in suffix:  # the requirement's comment stays with it
            suffix = suffix[: suffix.index("#")].rstrip() + ("\n" if suffix.endswith("\n") else "")
        quote = text[site.start - 1 : site.start]
        quoted = quote in ("'", '"')
        added = Note(mapping.PINS, FixKind.AUTO, f"`{requirement}` added: the migrated code imports `{package}` ({why})")
        if (
            quoted and not (site.hashed or site.bare_word or site.conda)
            and text[site.end : site.end + 1] == quote and re.match(r"[ \t]*\]", text[site.end + 1 :])
        ):
            # The last element of a one-line list (``mujoco = ["mujoco>=2.3"]``): a new
            # element after it, in the same quotes.
            outcome.edits.append(Edit(site.end + 1, site.end + 1, f", {quote}{requirement}{quote}", code=mapping.PINS))
            _settled(outcome, positions, site.start, package)
            outcome.findings.append(finding(positions, site.start, site.end, added))
            continue
        if line is None or site.hashed or site.bare_word or site.conda or (quoted and "," not in suffix):
            note = Note(mapping.PINS, FixKind.FLAG, f"the migrated code imports `{package}`: add `{requirement}` "
                        f"next to `{text[site.start:site.end].strip()}` by hand ({why})")
            outcome.findings.append(finding(positions, site.start, site.end, note))
            continue
        new_line = text[line[0] : site.start] + requirement + suffix
        if not new_line.endswith("\n"):
            new_line = "\n" + new_line
        outcome.edits.append(Edit(line[1], line[1], new_line, code=mapping.PINS))
        _settled(outcome, positions, site.start, package)
        outcome.findings.append(finding(positions, site.start, site.end, added))


def _settled(outcome: Outcome, positions: Positions, start: int, package: str) -> None:
    """The anchor's own finding asking for ``package`` by hand (GM110 on ``mujoco``) is
    answered by the line just added: drop it."""
    if package != "imageio":
        return
    where = positions.of(start)
    outcome.findings[:] = [
        f for f in outcome.findings if not (f.message == mapping.MUJOCO_IMAGEIO and (f.line, f.column) == where)
    ]


def _name(raw: str, site: Site) -> str | None:
    requirement = None if site.conda else mapping.parse(raw.strip())
    return canonicalize_name(requirement.name) if requirement is not None else None


def _needs_autorom(raw: str, site: Site) -> bool:
    requirement = None if site.conda else mapping.parse(raw.strip())
    if requirement is None:
        return False
    name = canonicalize_name(requirement.name)
    extras = {canonicalize_name(extra) for extra in requirement.extras}
    return name == "multi-agent-ale-py" or (name == "pettingzoo" and bool(extras & {"atari", "all"}))


def _autorom_kept(raw: str) -> Decision:
    return Decision(
        notes=[
            Note(
                GYM_ONLY,
                FixKind.FLAG,
                f"`{raw.strip()}` left: PettingZoo's Atari envs (multi-agent-ale-py) still take their ROMs from AutoROM; "
                "Gymnasium's Atari envs need only ale-py, which ships the ROMs",
            )
        ]
    )


def _is_ale_already(raw: str, decision: Decision, site: Site) -> bool:
    if site.conda or decision.rewrites:
        return False
    requirement = mapping.parse(raw.strip())
    return requirement is not None and canonicalize_name(requirement.name) == "ale-py"


def _conda_render(raw: str, decision: Decision) -> str:
    match = _CONDA_SPEC.fullmatch(raw.strip())
    assert match is not None
    leading = raw[: len(raw) - len(raw.lstrip())]
    trailing = raw[len(raw.rstrip()) :]
    channel = f"{match['channel']}::" if match["channel"] else ""
    return f"{leading}{channel}{decision.name}{decision.specifier}{trailing}"


def apply_edits(text: str, edits: list[Edit]) -> str:
    """``text`` with the edits made (they never overlap: one per requirement)."""
    out: list[str] = []
    position = 0
    for edit in sorted(edits, key=lambda e: (e.start, e.end)):
        if edit.start < position:
            raise ValueError("overlapping dependency edits")
        out.append(text[position : edit.start])
        out.append(edit.text)
        position = edit.end
    out.append(text[position:])
    return "".join(out)


def line_span(text: str, start: int, end: int) -> tuple[int, int] | None:
    """The whole lines holding ``text[start:end]`` when nothing else but whitespace, one
    trailing comma and a comment shares them (so deleting them deletes only this item)."""
    line_start = text.rfind("\n", 0, start) + 1
    newline = text.find("\n", end)
    line_end = len(text) if newline < 0 else newline + 1
    before = text[line_start:start]
    after = text[end:line_end]
    if not re.fullmatch(r"""(-\s*)?["']?""", before.strip()) or not re.fullmatch(r"""["']?\s*,?\s*(#.*)?\r?\n?""", after):
        return None
    return line_start, line_end
