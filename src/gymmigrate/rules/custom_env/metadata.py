"""GM404: metadata keys ``render.modes`` / ``video.frames_per_second`` -> ``render_modes`` / ``render_fps``.

The keys were renamed in gym 0.23 and ``gymnasium.make`` checks them. A metadata dict
that declares render modes without a frame rate gets ``"render_fps": 30`` (for review):
the env checker wants one whenever modes are declared.
"""

from __future__ import annotations

import ast
from collections.abc import Sequence

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.module import FUNCTIONS, ModuleFacts, string_value, walk
from gymmigrate.findings import FixKind, Tier
from gymmigrate.rules.base import FileContext, Rule, RuleFamily
from gymmigrate.rules.repeats import Repeats

LEGACY_METADATA_KEYS = {"render.modes": "render_modes", "video.frames_per_second": "render_fps"}
DEFAULT_RENDER_FPS = 30


class MetadataKeys(RuleFamily):
    RULES = (
        Rule("GM404", "metadata keys", FixKind.AUTO, "`render.modes` / `video.frames_per_second` become `render_modes` / `render_fps`."),
    )

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return "render.modes" in facts.text or "video.frames_per_second" in facts.text

    def decide(self) -> None:
        self._fps_advice = Repeats("GM404")
        sites: dict[str, list[ast.Constant]] = {}
        for string in self.facts.strings:
            value = string.value
            if (
                value in LEGACY_METADATA_KEYS
                and self._is_metadata_key(string)
                and not self._fallback_read(string)
                and not self._read_on_gym_only_env(string)
            ):
                sites.setdefault(value, []).append(string)
        for value, strings in sites.items():
            # One finding per key and file, however many envs and reads spell it.
            new = LEGACY_METADATA_KEYS[value]
            for string in strings:
                twin = self._modern_twin(string, new)
                if twin is not None:
                    self.plan.replace(twin, _without_key(value))  # ``{"render.modes": m, "render_modes": m}``
                else:
                    self.plan.replace(string, _renamed_key(value, new))
            more = f" ({len(strings)} places in this file)" if len(strings) > 1 else ""
            self.report(strings[0], "GM404", f"metadata key {value!r} -> {new!r}{more}")
        for statement in self._metadata_stores():
            if isinstance(statement.value, ast.Dict):
                self._add_render_fps(statement.value)

    def _read_on_gym_only_env(self, string: ast.Constant) -> bool:
        """A read of the legacy key from the metadata of an env a Gym-only library makes
        (``Unvectorize(...).metadata["video.frames_per_second"]``): that env stays on gym, whose
        metadata keeps the legacy keys, so the renamed key would raise KeyError there. Its
        port is the decision the library's import asks (GM107)."""
        parent = self.facts.parent(string)
        if isinstance(parent, ast.Subscript):
            holder: ast.AST = parent.value
        elif isinstance(parent, ast.Call) and isinstance(parent.func, ast.Attribute):
            holder = parent.func.value  # ``env.metadata.get(key)``
        elif isinstance(parent, ast.Compare) and parent.comparators:
            holder = parent.comparators[0]  # ``key in env.metadata``
        else:
            return False  # a key declared in a dict
        if not (isinstance(holder, ast.Attribute) and holder.attr == "metadata"):
            return False
        receiver = holder.value
        return bool(self._gym_only_origin(receiver) or self.receivers.gym_only_stack(receiver))

    def _fallback_read(self, string: ast.Constant) -> bool:
        """A read of the legacy key that only runs for an env declaring no new key: in the
        statement that reads the new key first (``m.get("render_modes", m.get("render.modes"))``,
        a conditional expression), in the ``except`` of a ``try`` reading the new key, or in
        the ``else`` of an ``if`` testing it. It serves envs still on the legacy key (which
        Gymnasium's own checker only warns about); renamed, it would read the new key twice."""
        parent = self.facts.parent(string)
        if isinstance(parent, ast.Dict):
            return False  # a key being declared, not read
        new = LEGACY_METADATA_KEYS[str(string.value)]
        current: ast.AST = string
        statement = self.facts.statement_of(string)
        compound = (ast.If, ast.Try, ast.For, ast.AsyncFor, ast.While, ast.With, ast.AsyncWith)
        if not isinstance(statement, compound) and _names_key(statement, new):
            return True
        while True:
            parent = self.facts.parent(current)
            if parent is None or isinstance(parent, (*FUNCTIONS, ast.ClassDef)):
                return False
            if isinstance(parent, ast.Try) and any(current is handler for handler in parent.handlers):
                if any(_names_key(node, new) for node in parent.body):
                    return True
            elif isinstance(parent, ast.If) and any(current is node for node in parent.orelse):
                if _names_key(parent.test, new):
                    return True
            current = parent

    def _modern_twin(self, string: ast.Constant, new: str) -> ast.Dict | None:
        """The dict literal holding ``string`` as a key when it already has the new key too:
        the legacy entry is dropped there instead of renamed into a duplicate key."""
        parent = self.facts.parent(string)
        if isinstance(parent, ast.Dict) and any(string_value(key) == new for key in parent.keys if key is not None):
            return parent
        return None

    def _metadata_stores(self) -> list[ast.Assign | ast.AnnAssign]:
        found: list[ast.Assign | ast.AnnAssign] = []
        for string in self.facts.strings:
            if string.value in LEGACY_METADATA_KEYS:
                parent = self.facts.parent(string)
                if isinstance(parent, ast.Dict) and _is_metadata_store(self.facts.parent(parent)):
                    holder = self.facts.parent(parent)
                    if holder not in found and holder.value is parent:  # type: ignore[union-attr]
                        found.append(holder)  # type: ignore[arg-type]
        return found

    def _is_metadata_key(self, string: ast.Constant) -> bool:
        parent = self.facts.parent(string)
        if isinstance(parent, ast.Dict) and any(key is string for key in parent.keys):
            return _is_metadata_store(self.facts.parent(parent))
        if isinstance(parent, ast.Subscript) and parent.slice is string:
            return _is_metadata_expr(parent.value)
        if isinstance(parent, ast.Call) and parent.args and parent.args[0] is string:
            func = parent.func
            return isinstance(func, ast.Attribute) and func.attr == "get" and _is_metadata_expr(func.value)
        if isinstance(parent, ast.Compare) and parent.left is string:
            return any(isinstance(op, (ast.In, ast.NotIn)) and _is_metadata_expr(c) for op, c in zip(parent.ops, parent.comparators))
        return False

    def _add_render_fps(self, metadata: ast.Dict) -> None:
        keys = [string_value(key) for key in metadata.keys]
        renamed = [LEGACY_METADATA_KEYS.get(k, k) if k is not None else None for k in keys]
        modes = next((v for k, v in zip(renamed, metadata.values) if k == "render_modes"), None)
        if modes is None or "render_fps" in renamed or not any(k in LEGACY_METADATA_KEYS for k in keys):
            return  # modern metadata may set render_fps elsewhere (Gymnasium's MuJoCo envs do)
        if isinstance(modes, (ast.List, ast.Tuple)) and not modes.elts:
            return  # no render modes: the checker needs no fps
        # Legacy code never reads the new key itself; Gymnasium reads it for frames
        # (RecordVideo, play). Without "rgb_array" among literal modes the value changes
        # nothing the env does: a note. With it (or modes not spelled out) it sets the
        # speed of recorded videos: a person picks the rate.
        literal_modes = [string_value(e) for e in modes.elts] if isinstance(modes, (ast.List, ast.Tuple)) else None
        frames = literal_modes is None or any(m is None or "rgb_array" in m for m in literal_modes)
        held = self._render_handed_on(metadata)
        if held is not None:
            # ``def render(self): return self.env.render()``: the frames are the held env's,
            # drawn at its rate; this class's value only satisfies the checker.
            frames = False
            message = (
                f"added \"render_fps\": {DEFAULT_RENDER_FPS} because render modes are declared without a frame rate; "
                f"render() hands on `{held}.render()`, whose frames come at that env's own rate"
            )
        elif frames and self._reads_frame_rate():
            message = f"added \"render_fps\": {DEFAULT_RENDER_FPS} because render modes are declared without a frame rate; set the rate the env really draws at"
        elif frames:
            # Recorders fall back to the same 30 frames per second when the key is absent
            # (gym's VideoRecorder and Gymnasium's RecordVideo and play alike), and nothing
            # in the module reads the rate itself: the value only satisfies the checker.
            frames = False
            message = (
                f"added \"render_fps\": {DEFAULT_RENDER_FPS} because render modes are declared without a frame rate; "
                f"recorders used {DEFAULT_RENDER_FPS} without it, so nothing changes (set the rate the env really draws at if it differs)"
            )
        else:
            message = (
                f"added \"render_fps\": {DEFAULT_RENDER_FPS} because render modes are declared without a frame rate; "
                "no rgb_array mode, so no recorded video reads it"
            )
        question = self._fps_advice.question("render_fps")
        self.report(metadata, "GM404", message, FixKind.ASSIST, tier=None if frames else Tier.NOTE, question=question)
        self.plan.replace(metadata, _with_render_fps)


    def _reads_frame_rate(self) -> bool:
        """The module reads the frame rate from metadata itself (``self.metadata["render_fps"]``,
        ``metadata.get("video.frames_per_second", 50)``): the added value replaces what that
        read found or fell back to."""
        for string in self.facts.strings:
            if string.value in ("render_fps", "video.frames_per_second") and self._is_metadata_key(string):
                parent = self.facts.parent(string)
                if not (isinstance(parent, ast.Dict) or isinstance(getattr(parent, "ctx", None), ast.Store)):
                    return True
        return False

    def _render_handed_on(self, metadata: ast.Dict) -> str | None:
        """The class that declares ``metadata`` renders only by returning ``self.<x>.render(...)``
        (a held env's frames): ``self.<x>``; else None."""
        classdef = self.facts.enclosing_class(metadata)
        render = next((s for s in classdef.body if isinstance(s, FUNCTIONS) and s.name == "render"), None) if classdef else None
        if render is None:
            return None
        body = [s for s in render.body if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant))]
        value = body[0].value if len(body) == 1 and isinstance(body[0], ast.Return) else None
        if not (isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute) and value.func.attr == "render"):
            return None
        held = value.func.value
        if isinstance(held, ast.Attribute) and isinstance(held.value, ast.Name) and held.value.id == "self":
            return self.facts.segment(held)
        return None


def _is_metadata_expr(expr: ast.AST) -> bool:
    return (isinstance(expr, ast.Attribute) and expr.attr == "metadata") or (isinstance(expr, ast.Name) and expr.id == "metadata")


def _is_metadata_store(node: ast.AST | None) -> bool:
    """``metadata = {...}`` in a class body or ``self.metadata = {...}``."""
    if isinstance(node, ast.Assign):
        return any(_is_metadata_expr(t) for t in node.targets)
    if isinstance(node, ast.AnnAssign):
        return _is_metadata_expr(node.target)
    return False


def _renamed_key(old: str, new: str):
    def build(node: cst.SimpleString) -> cst.SimpleString:
        return node.with_changes(value=node.value.replace(old, new))

    return build


def _without_key(key: str):
    """Drop the ``key`` entry of a dict literal (its modern spelling is there already)."""

    def build(node: cst.Dict) -> cst.Dict:
        kept = [
            element
            for element in node.elements
            if not (isinstance(element, cst.DictElement) and isinstance(element.key, cst.SimpleString) and element.key.evaluated_value == key)
        ]
        if kept and len(kept) < len(node.elements) and node.elements[-1].comma is cst.MaybeSentinel.DEFAULT:
            kept[-1] = kept[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
        return node.with_changes(elements=kept)

    return build


def _with_render_fps(node: cst.Dict) -> cst.Dict:
    from gymmigrate.rules.custom_env.cst_edits import (
        _append_element,  # the apply layer: LibCST
    )

    elements: Sequence[cst.BaseDictElement] = node.elements
    first_key = next((el.key for el in elements if isinstance(el, cst.DictElement) and isinstance(el.key, cst.SimpleString)), None)
    quote = first_key.quote if first_key is not None else '"'
    element = cst.DictElement(key=cst.SimpleString(f"{quote}render_fps{quote}"), value=cst.Integer(str(DEFAULT_RENDER_FPS)))
    return node.with_changes(elements=_append_element(elements, element))


def _names_key(node: ast.AST, key: str) -> bool:
    """``node`` spells the string ``key`` somewhere."""
    return any(isinstance(sub, ast.Constant) and sub.value == key for sub in walk(node))
