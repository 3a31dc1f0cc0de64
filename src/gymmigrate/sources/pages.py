"""Documentation pages: the Python code blocks of a Markdown or reStructuredText page.

``markdown.py`` and ``rst.py`` only find the blocks (the lines between the fences, the
content of a directive); this module turns them into programs and puts the migrated code
back, so every other byte of the page stays as it was.

- A block is its own program, unless a block uses a name that it does not bind itself and
  an earlier block binds (``env`` made in one block, stepped in the next): then the page
  is read as a tutorial and all its blocks are one program, in page order.
- An interactive session (the block's first line starts with ``>>>``) keeps its prompts
  and printed output: only the code after ``>>>`` / ``...`` is migrated; each ``>>>``
  example is a segment, and a statement that grows lines gets ``...`` prompts.
- A block that does not parse is left as it is; if it mentions Gym it is reported (GM001,
  flag), since the reader may still paste legacy code from it.
"""

from __future__ import annotations

import ast
import os
from dataclasses import dataclass, field

from gymmigrate.findings import Finding, FixKind
from gymmigrate.source_text import TransformError, may_hold_gym_code
from gymmigrate.sources import Location, Segment, lines_of

# Pages are text; this keeps the same bound as a Python module.
MAX_FILE_BYTES = 1024 * 1024

UNPARSED_BLOCK = "GM001"
PYTHON_LANGUAGES = frozenset({"python", "py", "python3", "py3", "pycon", "python-console"})


@dataclass
class Block:
    """Lines of a page (``first`` is the 0-based index of the first) holding Python code,
    every non-blank one starting with ``indent``."""

    first: int
    lines: list[str]
    indent: str
    maybe_python: bool = False  # no language given (an RST literal block): Python only if it parses


@dataclass
class _Example:
    """One ``>>>`` example of a session: its prompt lines, then its printed output."""

    prompt_lines: list[str]
    code: str
    output: list[str] = field(default_factory=list)


@dataclass
class _Parsed:
    block: Block
    code_lines: list[str]  # the lines without ``indent``
    session: bool
    preamble: list[str]  # session lines before the first prompt
    examples: list[_Example]
    added_newline: bool  # the page ended inside the block, without a final newline

    def segments(self) -> list[Segment]:
        if not self.session:
            return [Segment("".join(self.code_lines), Location(self.block.first + 1))]
        out = []
        line = self.block.first + 1 + len(self.preamble)
        for example in self.examples:
            out.append(Segment(example.code, Location(line)))
            line += len(example.prompt_lines) + len(example.output)
        return out


def page_text(source: bytes) -> str:
    try:
        return source.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise TransformError(f"cannot decode the page as UTF-8 ({exc.reason} at byte {exc.start}); left unchanged") from None


class Page:
    def __init__(self, text: str, blocks: list[Block]) -> None:
        self.lines = lines_of(text)
        self.notes: list[Finding] = []
        self.changes_outside_code = False
        parsed = [p for p in (_parse(block) for block in blocks) if p is not None]
        self._blocks: list[_Parsed] = []
        trees: list[ast.Module] = []
        for block in parsed:
            code = "".join(segment.code for segment in block.segments())
            try:
                trees.append(ast.parse(code))
            except (SyntaxError, ValueError) as exc:
                if not block.block.maybe_python:
                    self._note_unparsed(block, code, exc)
                continue
            self._blocks.append(block)
        if _builds_one_program(trees):
            self._programs_of_blocks = [list(range(len(self._blocks)))] if self._blocks else []
        else:
            self._programs_of_blocks = [[index] for index in range(len(self._blocks))]
        self.programs = [
            [segment for index in members for segment in self._blocks[index].segments()]
            for members in self._programs_of_blocks
        ]

    def _note_unparsed(self, block: _Parsed, code: str, exc: Exception) -> None:
        if not may_hold_gym_code(code.encode("utf-8")):
            return
        detail = f"line {exc.lineno} of the block: {exc.msg}" if isinstance(exc, SyntaxError) else str(exc)
        self.notes.append(
            Finding(
                line=block.block.first + 1,
                column=0,
                rule=UNPARSED_BLOCK,
                kind=FixKind.FLAG,
                message=f"this Python code block does not parse ({detail}); left as it is, check it by hand",
            )
        )

    def rebuild(self, codes: list[list[str]]) -> tuple[bytes, list[list[Location]]]:
        new_code: dict[int, list[str]] = {}
        for members, program_codes in zip(self._programs_of_blocks, codes):
            position = 0
            for index in members:
                count = len(self._blocks[index].segments())
                new_code[index] = program_codes[position : position + count]
                position += count
        out: list[str] = []
        starts: dict[int, list[Location]] = {}
        taken = 0
        for index, block in enumerate(self._blocks):
            out.extend(self.lines[taken : block.block.first])
            lines, segment_offsets = _block_lines(block, new_code[index])
            starts[index] = [Location(len(out) + 1 + offset) for offset in segment_offsets]
            out.extend(lines)
            taken = block.block.first + len(block.block.lines)
        out.extend(self.lines[taken:])
        text = "".join(out)
        return text.encode("utf-8"), [[start for index in members for start in starts[index]] for members in self._programs_of_blocks]

    def check_writable(self) -> None:
        """A page is text: whatever its blocks become can be written."""

    def code_view(self) -> str:
        return "".join(self.lines)

    def code_line_indexes(self) -> set[int]:
        """The 0-based page lines that belong to a Python block gymmigrate migrates."""
        return {block.block.first + k for block in self._blocks for k in range(len(block.block.lines))}


def _parse(block: Block) -> _Parsed | None:
    # An excerpt of a method body is indented as a whole: read it from its own margin.
    margins = [_margin(line[len(block.indent) :]) for line in block.lines if line.strip() and line.startswith(block.indent)]
    if margins and (common := os.path.commonprefix(margins)):
        block = Block(block.first, block.lines, block.indent + common, block.maybe_python)
    code_lines: list[str] = []
    for line in block.lines:
        if line.startswith(block.indent):
            code_lines.append(line[len(block.indent) :])
        elif not line.strip():
            code_lines.append(line.lstrip(" \t"))
        else:
            return None  # a line outside the block's indentation: not a block we understand
    added_newline = bool(code_lines) and not code_lines[-1].endswith("\n")
    if added_newline:
        code_lines[-1] += "\n"
    first = next((line for line in code_lines if line.strip()), "")
    if not first.startswith(">>>"):
        return _Parsed(block, code_lines, False, [], [], added_newline)
    preamble, examples = _session(code_lines)
    return _Parsed(block, code_lines, True, preamble, examples, added_newline)


def _margin(line: str) -> str:
    return line[: len(line) - len(line.lstrip(" \t"))]


def _prompt(line: str, prompt: str) -> str | None:
    """The code after ``prompt`` (``>>>`` or ``...``), or None if the line has no such prompt."""
    if line.startswith(prompt + " "):
        return line[len(prompt) + 1 :]
    if line.rstrip("\r\n") == prompt:
        return line[len(prompt) :] or "\n"
    return None


def _session(lines: list[str]) -> tuple[list[str], list[_Example]]:
    preamble: list[str] = []
    examples: list[_Example] = []
    for line in lines:
        code = _prompt(line, ">>>")
        if code is not None:
            examples.append(_Example([line], code))
            continue
        current = examples[-1] if examples else None
        more = _prompt(line, "...") if current is not None and not current.output else None
        if current is None:
            preamble.append(line)
        elif more is not None:
            current.prompt_lines.append(line)
            current.code += more
        else:
            current.output.append(line)
    return preamble, examples


def _block_lines(block: _Parsed, codes: list[str]) -> tuple[list[str], list[int]]:
    """The block's lines with ``codes`` in place, and where each segment starts in them."""
    indent = block.block.indent
    if not block.session:
        if codes[0] == block.segments()[0].code:
            return block.block.lines, [0]
        lines = [indent + line if line.strip() else line for line in lines_of(codes[0])]
        if block.added_newline and lines:
            lines[-1] = lines[-1].removesuffix("\n")
        return lines, [0]
    out = block.block.lines[: len(block.preamble)]
    offsets = []
    start = len(block.preamble)
    for example, code in zip(block.examples, codes):
        offsets.append(len(out))
        prompts_end = start + len(example.prompt_lines)
        end = prompts_end + len(example.output)
        if code == example.code:
            out.extend(block.block.lines[start:end])
        elif not code.strip():
            pass  # the example was removed (a seed merged into a reset): its printed output goes too
        else:
            out.extend(indent + line for line in _with_prompts(code))
            out.extend(block.block.lines[prompts_end:end])  # the printed output, as it was
        start = end
    if block.added_newline and out:
        out[-1] = out[-1].removesuffix("\n")
    return out, offsets


def _with_prompts(code: str) -> list[str]:
    """``>>>`` before each top-level statement, ``...`` before the lines that continue one."""
    lines = lines_of(code)
    tree = ast.parse(code)
    starts = {min([node.lineno, *(d.lineno for d in getattr(node, "decorator_list", ()))]) for node in tree.body}
    out = []
    for number, line in enumerate(lines, start=1):
        if not line.strip() and number + 1 in starts:
            continue  # a blank line before the next statement: the next `>>>` separates them
        prompt = ">>>" if number == 1 or number in starts else "..."
        out.append(f"{prompt} {line}" if line.strip() else f"{prompt}{line}")
    return out


def _builds_one_program(trees: list[ast.Module]) -> bool:
    """True if some block uses a name it does not bind but an earlier block binds."""
    bound_before: set[str] = set()
    for tree in trees:
        bound, used = _names(tree)
        if (used - bound) & bound_before:
            return True
        bound_before |= bound
    return False


def _names(tree: ast.Module) -> tuple[set[str], set[str]]:
    bound: set[str] = set()
    used: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Name):
            (used if isinstance(node.ctx, ast.Load) else bound).add(node.id)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            bound.update((alias.asname or alias.name).split(".")[0] for alias in node.names)
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            bound.add(node.name)
        elif isinstance(node, ast.arg):
            bound.add(node.arg)
    return bound, used
