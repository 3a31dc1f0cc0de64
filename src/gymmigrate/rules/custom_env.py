"""Custom ``Env`` subclasses: the methods Gymnasium calls with a new contract.

* GM501 ``def reset(self)`` -> ``def reset(self, *, seed=None, options=None)`` with
  ``super().reset(seed=seed)`` first and ``(obs, info)`` returned: Gymnasium's wrappers
  (``TimeLimit`` from ``make`` included) always call ``env.reset(seed=..., options=...)``,
  and ``Env.reset`` is what seeds ``self.np_random``.
* GM502 gym 0.22-0.25 ``reset(..., return_info=False)``: the flag is gone in 0.26, the
  ``(obs, info)`` branch is the only one left.
* GM503 ``def seed(self, seed=None)``: removed in 0.26 (seeding happens in ``reset``). The
  canonical ``seeding.np_random`` body is deleted; anything else moves into ``reset``
  under ``if seed is not None:``; ``self.seed()`` calls go.
* GM504 ``step`` returns ``(obs, reward, terminated, truncated, info)``; a step limit the
  env counts itself becomes ``truncated``, everything else ``terminated``.
* GM404 metadata keys ``render.modes`` / ``video.frames_per_second`` became
  ``render_modes`` / ``render_fps`` in gym 0.23 (``gymnasium.make`` checks them).
* GM405 ``def render(self, mode="human")`` -> ``def render(self)`` reading
  ``self.render_mode``, which ``__init__`` takes: ``gymnasium.make(id, render_mode=...)``
  passes it to the constructor.
* GM507 reads of ``reward_range`` (removed from ``Env``/``Wrapper`` in Gymnasium 1.0) and
  GM508 mujoco-py ``MujocoEnv`` subclasses are reported.
* GM509 observations built with ``np.array(...)`` (float64) for a float32 ``Box`` are
  reported: ``check_env`` rejects them as outside the observation space.

Very old ``_step`` / ``_reset`` / ``_seed`` / ``_render`` (gym < 0.9) are renamed first
and then migrated like the modern names. Wrapper subclasses are left to wrappers.py.

Sources: Gymnasium ``core.py`` (``Env.reset`` seeds ``_np_random``), gym 0.26 release
notes, the old migration guide ("replacing ``done`` with ``terminated`` and
``truncated=False`` in step should address most issues"), ``envs/registration.py::make``.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence

import libcst as cst
import libcst.matchers as m
from libcst.codemod.visitors import RemoveImportsVisitor
from libcst.metadata import PositionProvider

from gymmigrate.analysis import env_classes as E
from gymmigrate.analysis.decisions import Action, decide
from gymmigrate.analysis.receivers import METADATA, EnvKind, ReceiverAnalysis
from gymmigrate.analysis.syntax import own_returns
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileProfile, Rule, RulePass

RULES = (
    Rule("GM404", "metadata keys", FixKind.AUTO, "`render.modes` / `video.frames_per_second` become `render_modes` / `render_fps`."),
    Rule("GM405", "custom render(mode)", FixKind.ASSIST, "`render(self, mode)` reads `self.render_mode`, set in `__init__`."),
    Rule("GM501", "custom reset", FixKind.AUTO, "`reset` takes `seed`/`options`, calls `super().reset(seed=seed)`, returns `(obs, info)`."),
    Rule("GM502", "reset return_info", FixKind.ASSIST, "`return_info` and its branches are removed; reset always returns `(obs, info)`."),
    Rule("GM503", "custom seed()", FixKind.AUTO, "`seed()` methods are removed; their seeding moves into `reset`."),
    Rule("GM504", "custom step", FixKind.ASSIST, "`step` returns `(obs, reward, terminated, truncated, info)`."),
    Rule("GM507", "reward_range", FixKind.FLAG, "Reads of `reward_range`, removed from `Env` and `Wrapper`, are reported."),
    Rule("GM508", "mujoco-py MujocoEnv", FixKind.FLAG, "Subclasses of the mujoco-py `MujocoEnv` are reported for a manual port."),
    Rule("GM509", "float64 observations", FixKind.FLAG, "`np.array(...)` observations for a float32 `Box` are reported."),
)

LEGACY_METADATA_KEYS = {"render.modes": "render_modes", "video.frames_per_second": "render_fps"}
DEFAULT_RENDER_FPS = 30
# gym < 0.9 spelled the API methods with a leading underscore.
UNDERSCORE_METHODS = {"_step": "step", "_reset": "reset", "_seed": "seed", "_render": "render"}
UNDERSCORE_RULE = {"step": "GM504", "reset": "GM501", "seed": "GM503", "render": "GM405"}

# Identifiers that count steps or time (``self.steps >= self.max_steps``, ``self.t > 200``).
_STEP_LIMIT_WORD = re.compile(
    r"(^|_)(t|ts|step|steps|timestep|timesteps|tick|ticks|iter|iters|iteration|iterations|horizon|"
    r"time|time_limit|ep_len|episode_len|episode_length|counter)(_|$)"
)
_LIMIT_OPS = (cst.GreaterThan, cst.GreaterThanEqual, cst.LessThan, cst.LessThanEqual, cst.Equal)

SUPER_RESET = "super().reset(seed=seed)"


class CustomEnvPass(RulePass):
    RULES = RULES
    ORDER = 40
    METADATA_DEPENDENCIES = (PositionProvider, *METADATA)

    @classmethod
    def applies_to(cls, source: str, profile: FileProfile) -> bool:
        return "gym" in source or "render.modes" in source or "reward_range" in source

    def visit_Module(self, node: cst.Module) -> None:
        self.analysis = ReceiverAnalysis(node, self.metadata)

    # -- GM404: metadata keys -----------------------------------------------------------

    def leave_SimpleString(self, original_node: cst.SimpleString, updated_node: cst.SimpleString) -> cst.SimpleString:
        value = original_node.evaluated_value
        if value not in LEGACY_METADATA_KEYS or not self._is_metadata_key(original_node):
            return updated_node
        new = LEGACY_METADATA_KEYS[value]  # type: ignore[index]
        self.report(original_node, "GM404", f"metadata key {value!r} -> {new!r}")
        return updated_node.with_changes(value=updated_node.value.replace(value, new))  # type: ignore[arg-type]

    def _is_metadata_key(self, string: cst.SimpleString) -> bool:
        parent = self.analysis.parent(string)
        if isinstance(parent, cst.DictElement) and parent.key is string:
            holder = self.analysis.parent(self.analysis.parent(parent))
            return _is_metadata_store(holder)
        if isinstance(parent, cst.Index):
            subscript = self.analysis.parent(self.analysis.parent(parent))
            return isinstance(subscript, cst.Subscript) and _is_metadata_expr(subscript.value)
        if isinstance(parent, cst.Arg):
            call = self.analysis.parent(parent)
            return (
                isinstance(call, cst.Call)
                and m.matches(call.func, m.Attribute(attr=m.Name("get")))
                and _is_metadata_expr(call.func.value)  # type: ignore[union-attr]
                and call.args[0] is parent
            )
        if isinstance(parent, cst.Comparison) and parent.left is string:
            return any(isinstance(t.operator, (cst.In, cst.NotIn)) and _is_metadata_expr(t.comparator) for t in parent.comparisons)
        return False

    def leave_Dict(self, original_node: cst.Dict, updated_node: cst.Dict) -> cst.Dict:
        if not _is_metadata_store(self.analysis.parent(original_node)):
            return updated_node
        keys = {_string_key(el) for el in updated_node.elements}
        modes = next(
            (el.value for el in updated_node.elements if _string_key(el) == "render_modes"), None
        )
        legacy = any(_string_key(el) in LEGACY_METADATA_KEYS for el in original_node.elements)
        if modes is None or "render_fps" in keys or not legacy:
            return updated_node  # modern metadata may set render_fps elsewhere (Gymnasium's MuJoCo envs do)
        if isinstance(modes, (cst.List, cst.Tuple)) and not modes.elements:
            return updated_node  # no render modes: the checker needs no fps
        first_key = next((el.key for el in updated_node.elements if isinstance(el, cst.DictElement) and isinstance(el.key, cst.SimpleString)), None)
        quote = first_key.quote if first_key is not None else '"'
        element = cst.DictElement(
            key=cst.SimpleString(f"{quote}render_fps{quote}"), value=cst.Integer(str(DEFAULT_RENDER_FPS))
        )
        self.report(
            original_node,
            "GM404",
            f"added \"render_fps\": {DEFAULT_RENDER_FPS} because render modes are declared without a frame rate; set the rate the env really draws at",
            FixKind.ASSIST,
        )
        return updated_node.with_changes(elements=_append_element(updated_node.elements, element))

    # -- GM507: reward_range ------------------------------------------------------------------

    def visit_Attribute(self, node: cst.Attribute) -> None:
        if node.attr.value != "reward_range" or self._is_store(node):
            return
        owner = node.value
        classdef = self.analysis.enclosing(node, cst.ClassDef)
        if isinstance(owner, cst.Name) and owner.value == "self" and isinstance(classdef, cst.ClassDef):
            if self.analysis.is_gym_wrapper_class(classdef):
                self.report(node, "GM507", "Wrapper.reward_range was removed in Gymnasium 1.0; read `self.env.unwrapped.reward_range` if the env defines it")
            elif E.is_custom_env_class(self.analysis, classdef) and not _defines_reward_range(classdef):
                self.report(node, "GM507", "Env.reward_range was removed in Gymnasium 1.0; define `reward_range` on this class or drop the read")
            return
        kind = self.analysis.kind_of(owner)
        decision = decide(kind, owner, self.context.profile)
        if decision.action is not Action.LEAVE or kind is EnvKind.GYM_ENV:
            self.report(
                node,
                "GM507",
                "reward_range was removed from Env and Wrapper in Gymnasium 1.0 (reads through a wrapper raise AttributeError); use `env.unwrapped.reward_range` if the env defines it",
            )

    def _is_store(self, node: cst.Attribute) -> bool:
        parent = self.analysis.parent(node)
        return isinstance(parent, (cst.AssignTarget,)) or (isinstance(parent, cst.AnnAssign) and parent.target is node)

    # -- classes -----------------------------------------------------------------------------

    def leave_ClassDef(self, original_node: cst.ClassDef, updated_node: cst.ClassDef) -> cst.ClassDef:
        if not E.is_custom_env_class(self.analysis, original_node):
            return updated_node
        if E.mujoco_base(self.analysis, original_node) and _uses_mujoco_py(original_node):
            self.report(
                original_node,
                "GM508",
                "mujoco-py MujocoEnv: Gymnasium's MujocoEnv needs observation_space (and render settings) in __init__, and self.sim.data becomes self.data; port by hand",
            )
        return _EnvClassMigration(self, original_node, updated_node).run()


class _EnvClassMigration:
    """Rewrites the methods of one custom env class; reports through the pass."""

    def __init__(self, rule_pass: CustomEnvPass, original: cst.ClassDef, updated: cst.ClassDef) -> None:
        self.rule_pass = rule_pass
        self.original = original
        self.updated = updated
        self.orig_methods = E.class_methods(original)
        self.methods = E.class_methods(updated)
        self.renamed: dict[str, str] = {}  # new name -> old name
        for old, new in UNDERSCORE_METHODS.items():
            if old in self.methods and new not in self.methods:
                self.renamed[new] = old
        self.replacements: dict[str, cst.FunctionDef | None] = {}  # by *updated* name
        self.seed_folded: list[cst.BaseStatement] = []
        self.extra_init: cst.FunctionDef | None = None

    def report(self, node: cst.CSTNode, code: str, message: str, kind: FixKind | None = None) -> None:
        self.rule_pass.report(node, code, message, kind)

    def method(self, name: str) -> tuple[cst.FunctionDef, cst.FunctionDef] | None:
        old = self.renamed.get(name, name)
        if old not in self.methods or old not in self.orig_methods:
            return None
        fn = self.replacements.get(old, self.methods[old])
        assert fn is not None
        return self.orig_methods[old], fn

    def set_method(self, name: str, fn: cst.FunctionDef | None) -> None:
        self.replacements[self.renamed.get(name, name)] = fn

    def run(self) -> cst.ClassDef:
        for new, old in self.renamed.items():
            self.report(self.orig_methods[old], UNDERSCORE_RULE[new], f"gym < 0.9 method `{old}` renamed `{new}`")
            self.replacements[old] = self.methods[old].with_changes(name=cst.Name(new))
        self._migrate_seed()
        self._migrate_reset()
        self._migrate_step()
        self._migrate_render()
        self._migrate_internal_calls()
        self._check_float64_observations()
        return self._rebuild()

    def _rebuild(self) -> cst.ClassDef:
        body = self.updated.body
        if not isinstance(body, cst.IndentedBlock):
            return self.updated  # ``class E(gym.Env): pass``: no methods to migrate
        if self.renamed:
            # Internal calls of a renamed gym < 0.9 method (``self._seed()``) follow the rename.
            calls = _SelfMethodCallRenamer({old: new for new, old in self.renamed.items()})
            for name, fn in self.methods.items():
                current = self.replacements.get(name, fn)
                if current is not None:
                    self.replacements[name] = current.visit(calls)  # type: ignore[assignment]
        statements: list[cst.BaseStatement] = []
        carried: Sequence[cst.EmptyLine] | None = None  # blank lines of a deleted method
        for stmt in body.body:
            if isinstance(stmt, cst.FunctionDef) and stmt.name.value in self.replacements:
                new = self.replacements[stmt.name.value]
                if new is None:
                    carried = stmt.leading_lines if carried is None else carried
                    continue
                stmt = new
            if carried is not None:
                stmt = stmt.with_changes(leading_lines=carried)  # type: ignore[union-attr]
                carried = None
            if self.extra_init is not None and isinstance(stmt, cst.FunctionDef):
                statements.append(self.extra_init)
                self.extra_init = None
            statements.append(stmt)
        if self.extra_init is not None:
            statements.append(self.extra_init)
        if not statements:
            statements.append(cst.SimpleStatementLine([cst.Pass()]))
        return self.updated.with_changes(body=body.with_changes(body=statements))

    # -- GM503: seed() -------------------------------------------------------------------

    def _migrate_seed(self) -> None:
        pair = self.method("seed")
        if pair is None:
            return
        orig, fn = pair
        if not self._seed_calls_removable():
            self.report(orig, "GM503", "seed() is gone in Gymnasium but its result is used in this class; seed through reset(seed=...) and rewrite those uses", FixKind.FLAG)
            return
        param = _param_names(fn)[1:2]
        seed_name = param[0] if param else "seed"
        body = _body_statements(fn)
        moved: list[cst.BaseStatement] = []
        canonical_names: set[str] = set()
        # Qualified names are known for the input tree only: classify the original statements.
        for index, (original, stmt) in enumerate(zip(_body_statements(orig), body)):
            if index == 0 and _is_docstring(stmt):
                continue
            target = _np_random_seeding(original, self.rule_pass.analysis)
            if target is not None:
                canonical_names.update(target)
                continue
            if index == len(body) - 1 and m.matches(stmt, m.SimpleStatementLine([m.Return()])):
                continue
            if m.matches(stmt, m.SimpleStatementLine([m.Expr(m.Call())])) and E.is_super_method_call(stmt.body[0].value, "seed"):  # type: ignore[attr-defined]
                continue
            moved.append(stmt)
        if any(_contains(s, m.Return()) for s in moved):
            self.report(orig, "GM503", "seed() returns from the middle of its body; move its seeding into reset() under `if seed is not None:` by hand", FixKind.FLAG)
            return
        if moved and self.method("reset") is None:
            self.report(orig, "GM503", "seed() does more than seed np_random and this class has no reset(); move that code into reset() under `if seed is not None:`", FixKind.FLAG)
            return
        seed_names = {seed_name} | canonical_names
        # Statements that do not touch the seed build state (spaces, simulators): they must keep
        # running at construction, where __init__ called seed(), not only on seeded resets.
        setup = [s for s in moved if not _is_seeding_statement(s, seed_names)]
        moved = [s for s in moved if s not in setup]
        init_call = self._single_init_seed_call()
        if setup and init_call is None:
            self.report(orig, "GM503", "seed() also builds state that does not depend on the seed; move it into __init__ and the seeding into reset() by hand", FixKind.FLAG)
            return
        self._remove_seed_calls(setup)
        if setup:
            self.report(init_call, "GM503", "the set-up seed() did besides seeding (spaces, objects) now runs here in __init__ instead of the self.seed() call", FixKind.ASSIST)  # type: ignore[arg-type]
        if not moved:
            self.set_method("seed", None)
            self.report(orig, "GM503", "seed() removed: super().reset(seed=seed) in reset() seeds self.np_random")
            self._drop_seeding_import()
            return
        renames = {n: "seed" for n in seed_names if n != "seed"}
        self.seed_folded = [_rename_names(s, renames) for s in moved]
        self.set_method("seed", None)
        self.report(
            orig,
            "GM503",
            "seed() removed: its extra seeding moved into reset() under `if seed is not None:`; it now runs only when a seed is given",
            FixKind.ASSIST,
        )
        self._drop_seeding_import()

    def _drop_seeding_import(self) -> None:
        context = self.rule_pass.context.codemod
        for module in ("gymnasium.utils", "gym.utils"):
            RemoveImportsVisitor.remove_unused_import(context, module, "seeding")

    def _seed_call_sites(self) -> list[tuple[cst.Call, cst.CSTNode | None]]:
        finder = _SelfCallFinder({"seed", self.renamed.get("seed", "seed")})
        self.original.visit(finder)
        return [(call, self.rule_pass.analysis.parent(call)) for call in finder.calls]

    def _seed_calls_removable(self) -> bool:
        for call, parent in self._seed_call_sites():
            if not isinstance(parent, cst.Expr):
                return False
        return True

    def _single_init_seed_call(self) -> cst.Call | None:
        sites = self._seed_call_sites()
        init = self.orig_methods.get("__init__")
        if len(sites) == 1 and init is not None and self.rule_pass.analysis.enclosing(sites[0][0], cst.FunctionDef) is init:
            return sites[0][0]
        return None

    def _remove_seed_calls(self, setup: list[cst.BaseStatement] | None = None) -> None:
        seed_method = self.orig_methods.get(self.renamed.get("seed", "seed"))
        init_call = self._single_init_seed_call() if setup else None
        for call, _ in self._seed_call_sites():
            if self.rule_pass.analysis.enclosing(call, cst.FunctionDef) is seed_method or call is init_call:
                continue
            argument = call.args[0].value if call.args else None
            given = argument is not None and not m.matches(argument, m.Name("None"))
            message = (
                "self.seed(...) removed: pass that seed to the first reset(seed=...) instead"
                if given
                else "self.seed() removed: reset(seed=None) picks a random seed itself"
            )
            self.report(call, "GM503", message, FixKind.ASSIST if given else FixKind.AUTO)
        for name, fn in list(self.methods.items()):
            current = self.replacements.get(name, fn)
            if current is None or name in (self.renamed.get("seed", "seed"),):
                continue
            new = current.visit(_SelfSeedCallRemover(setup if name == "__init__" else None))
            if new is not current:
                self.replacements[name] = new  # type: ignore[assignment]

    # -- GM501 / GM502: reset -----------------------------------------------------------

    def _migrate_reset(self) -> None:
        pair = self.method("reset")
        if pair is None:
            return
        orig, fn = pair
        names = _param_names(fn)
        legacy_flag = "return_info" in names
        modern = "seed" in names and "options" in names and not legacy_flag
        if not modern:
            fn = _modern_reset_params(fn)
        if legacy_flag:
            fn = _drop_return_info(fn)
            self.report(orig, "GM502", "return_info removed: reset() always returns (obs, info) now; check callers that expected a bare observation")
        elif not modern:
            fn, base_info = self._unpack_super_reset(orig, fn)
            fn = self._return_info_pairs(orig, fn, base_info)
            if fn.returns is not None and not _is_tuple_annotation(fn.returns.annotation, 2):
                # ``-> np.ndarray`` -> ``-> tuple[np.ndarray, dict]`` (Gymnasium needs Python >= 3.10)
                pair = cst.parse_expression(f"tuple[{_code(fn.returns.annotation).strip()}, dict]")
                fn = fn.with_changes(returns=fn.returns.with_changes(annotation=pair))
        if E.extends_gym_env_directly(self.rule_pass.analysis, self.original) or _calls_super_reset(fn):
            fn, inserted = _ensure_super_reset(fn)
        else:
            inserted = False
            self.report(
                orig,
                "GM501",
                "reset() must seed np_random, but super().reset() here would also run the base env's own reset; call Env.reset(self, seed=seed) first by hand",
                FixKind.FLAG,
            )
        if self.seed_folded:
            fn = _insert_after_super_reset(fn, self.seed_folded)
        if not modern or inserted:
            star_kwarg = fn.params.star_kwarg.name.value if fn.params.star_kwarg else None
            extra = [n for n in names[1:] if n not in ("seed", "options", "return_info", star_kwarg)]
            if extra and not legacy_flag:
                self.report(orig, "GM501", f"reset keeps its own parameters ({', '.join(extra)}) before seed/options; Gymnasium code passes such settings in options", FixKind.ASSIST)
            elif not legacy_flag:
                seeds = ", and calls super().reset(seed=seed) first to seed np_random" if inserted else ""
                self.report(orig, "GM501", f"reset takes seed and options (wrappers always pass them){seeds}")
        self.set_method("reset", fn)

    def _unpack_super_reset(self, orig: cst.FunctionDef, fn: cst.FunctionDef) -> tuple[cst.FunctionDef, str | None]:
        """``obs = super().reset()`` -> ``obs, info = super().reset()``: the base env is migrated too."""
        info_name: str | None = None
        for call in m.findall(orig, m.Call()):
            if not E.is_super_method_call(call, "reset"):
                continue
            parent = self.rule_pass.analysis.parent(call)
            if m.matches(parent, m.Assign(targets=[m.AssignTarget(m.Name())])) and info_name is None:
                info_name = "info" if not _uses_name(orig, "info") else "base_info"
                self.report(call, "GM501", f"super().reset() returns (obs, info) now: unpacked, and reset returns that {info_name}", FixKind.ASSIST)
            elif not isinstance(parent, (cst.Expr, cst.Return)):
                self.report(call, "GM501", "super().reset(...) returns (obs, info) now: unpack it where its result is used", FixKind.FLAG)
        if info_name is None:
            return fn, None
        name = info_name

        class Unpack(cst.CSTTransformer):
            def leave_Assign(self, original_node: cst.Assign, updated_node: cst.Assign) -> cst.Assign:
                if not E.is_super_method_call(updated_node.value, "reset") or not m.matches(updated_node.targets[0].target, m.Name()):
                    return updated_node
                target = cst.Tuple([cst.Element(updated_node.targets[0].target), cst.Element(cst.Name(name))], lpar=[], rpar=[])
                return updated_node.with_changes(targets=[updated_node.targets[0].with_changes(target=target)])

        return fn.with_changes(body=fn.body.visit(Unpack())), info_name

    def _return_info_pairs(self, orig: cst.FunctionDef, fn: cst.FunctionDef, base_info: str | None = None) -> cst.FunctionDef:
        info_expr: cst.BaseExpression = cst.Dict([])
        kind = FixKind.AUTO
        why = "returns (obs, {})"
        if base_info is not None:
            info_expr, kind, why = cst.Name(base_info), FixKind.ASSIST, f"returns (obs, {base_info}) with the info of super().reset()"
        elif _assigns_name(fn, "info"):
            info_expr, kind, why = cst.Name("info"), FixKind.ASSIST, "returns (obs, info) with the info dict reset() already builds"
        elif "_get_info" in self.methods:
            info_expr, kind, why = (
                cst.parse_expression("self._get_info()"),
                FixKind.ASSIST,
                "returns (obs, self._get_info()), the info the class already builds",
            )
        originals = own_returns(orig)
        for ret in originals:
            if ret.value is not None and not E.is_super_method_call(ret.value, "reset"):
                self.report(ret, "GM501", f"reset {why}", kind)

        def pair(ret: cst.Return) -> cst.Return:
            if ret.value is None or E.is_super_method_call(ret.value, "reset"):
                return ret  # the base reset already returns (obs, info)
            value = ret.value
            if isinstance(value, cst.Tuple) and not value.lpar:
                value = value.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])
            return ret.with_changes(value=cst.Tuple([cst.Element(value), cst.Element(info_expr)], lpar=[], rpar=[]))

        return fn.with_changes(body=fn.body.visit(_ReturnRewriter(pair)))

    # -- GM504: step ---------------------------------------------------------------------

    def _migrate_step(self) -> None:
        pair = self.method("step")
        if pair is None:
            return
        orig, fn = pair
        orig_returns = own_returns(orig)
        returns = own_returns(fn)
        if any(_tuple_len(r.value) == 5 for r in returns):
            return  # already the five-value API
        splits: dict[str, tuple[list[cst.BaseExpression], list[cst.BaseExpression]]] = {}
        plans: list[Callable[[cst.Return], cst.Return] | None] = []
        rename_done = False
        limit_hint = _step_limit_text(fn)
        for original, ret in zip(orig_returns, returns):
            if ret.value is None:
                plans.append(None)
                continue
            if _tuple_len(ret.value) != 4:
                self.report(original, "GM504", "step returns something other than a 4-tuple literal; return (obs, reward, terminated, truncated, info) by hand", FixKind.FLAG)
                plans.append(None)
                continue
            done = ret.value.elements[2].value  # type: ignore[union-attr]
            if isinstance(done, cst.Name) and _assigns_name(fn, done.value):
                assigned = _single_assignment(fn, done.value)
                split = _split_done(assigned) if assigned is not None else None
                if split is not None:
                    splits[done.value] = split
                    plans.append(_five(cst.Name("terminated"), cst.Name("truncated")))
                    self.report(original, "GM504", f"`{done.value}` split: the step-limit test became truncated, the rest terminated", FixKind.ASSIST)
                    continue
                if done.value == "done" and not _uses_name(fn, "terminated") and not _declares_global(fn, "done"):
                    rename_done = True
                    plans.append(_five(cst.Name("terminated"), cst.Name("False")))
                else:
                    plans.append(_five(done, cst.Name("False")))
                self.report(original, "GM504", _truncated_false_message(limit_hint), FixKind.ASSIST)
                continue
            split = _split_done(done)
            if split is not None:
                task, limit = split
                plans.append(_five(_bool_of(task), _bool_of(limit)))
                self.report(original, "GM504", "done split: the step-limit test became truncated, the rest terminated", FixKind.ASSIST)
                continue
            terminated = _bool_of([done]) if _needs_bool(done) else done
            plans.append(_five(terminated, cst.Name("False")))
            self.report(original, "GM504", _truncated_false_message(limit_hint), FixKind.ASSIST)
        if not any(plans):
            return
        iterator = iter(plans)

        def rewrite(ret: cst.Return) -> cst.Return:
            plan = next(iterator)
            return plan(ret) if plan is not None else ret

        body = fn.body.visit(_ReturnRewriter(rewrite))
        if fn.returns is not None and _is_tuple_annotation(fn.returns.annotation, 4):
            # ``-> Tuple[obs, float, bool, dict]``: one more bool for truncated
            annotation = fn.returns.annotation
            elements = list(annotation.slice)  # type: ignore[attr-defined]
            elements.insert(3, elements[2])
            fn = fn.with_changes(returns=fn.returns.with_changes(annotation=annotation.with_changes(slice=elements)))
        for name, (task, limit) in splits.items():
            body = body.visit(_DoneSplitter(name, task, limit, keep_done=_reads_name_outside_returns(fn, name)))
        if rename_done:
            body = body.visit(_NameRenamer({"done": "terminated"}))
            body = _bool_wrap_assignments(body, "terminated")
        self.set_method("step", fn.with_changes(body=body))

    # -- the class calling its own reset / step ----------------------------------------------

    def _migrate_internal_calls(self) -> None:
        """``obs = self.reset()`` in the class itself: reset() returns (obs, info) now."""
        analysis = self.rule_pass.analysis
        unpackable = False
        for name, orig in self.orig_methods.items():
            if self.replacements.get(name, orig) is None or name in ("reset", "_reset"):
                continue
            for method, code in (("reset", "GM501"), ("step", "GM504")):
                for call in m.findall(orig, m.Call(func=m.Attribute(value=m.Name("self"), attr=m.Name(method) | m.Name("_" + method)))):
                    parent = analysis.parent(call)
                    if isinstance(parent, cst.Expr):
                        continue
                    if method == "reset" and m.matches(parent, m.Assign(targets=[m.AssignTarget(m.Name() | m.Attribute())])):
                        unpackable = True
                        self.report(call, code, "self.reset() returns (obs, info) now: unpacked as `obs, _ = self.reset()`", FixKind.ASSIST)
                    else:
                        what = "(obs, info)" if method == "reset" else "(obs, reward, terminated, truncated, info)"
                        self.report(call, code, f"self.{method}() returns {what} now: update how its result is used", FixKind.FLAG)
        if not unpackable:
            return
        for name, fn in self.methods.items():
            current = self.replacements.get(name, fn)
            if current is None or name in ("reset", "_reset"):
                continue
            new = current.visit(_SelfResetUnpacker())
            if new is not current:
                self.replacements[name] = new  # type: ignore[assignment]

    # -- GM405: render -------------------------------------------------------------------

    def _migrate_render(self) -> None:
        pair = self.method("render")
        if pair is None:
            return
        orig, fn = pair
        params = list(fn.params.params)
        mode_index = next((i for i, p in enumerate(params) if p.name.value == "mode"), None)
        if mode_index is None:
            return
        removed = params.pop(mode_index)
        old_default = f" (the old default was {_code(removed.default)}: pass render_mode={_code(removed.default)} to gymnasium.make to keep it)" if removed.default else ""
        if params:
            params[-1] = params[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
        new_params = fn.params.with_changes(params=params)
        if _rebinds_name(fn, "mode"):
            body = _insert_at_top(fn.body, [cst.parse_statement("mode = self.render_mode")])
        else:
            body = fn.body.visit(_ModeReader())
        none_check = m.Comparison(
            left=m.Attribute(value=m.Name("self"), attr=m.Name("render_mode")),
            comparisons=[m.ComparisonTarget(operator=m.Is(), comparator=m.Name("None"))],
        )
        if not _contains(body, none_check):
            # Gymnasium's convention: without a render mode, render() draws nothing. The old
            # body was written for a mode string and may misbehave on None (e.g. write to stdout).
            body = _insert_at_top(body, [cst.parse_statement("if self.render_mode is None:\n    return None\n")])
        fn = fn.with_changes(params=new_params, body=body)
        self.set_method("render", fn)
        self.report(orig, "GM405", f"render() takes no mode: it reads self.render_mode, fixed when the env is made, and draws nothing when that is None{old_default}")
        self._add_render_mode_to_init()

    def _add_render_mode_to_init(self) -> None:
        pair = self.method("__init__")
        if pair is None:
            if E.has_local_env_base(self.rule_pass.analysis, self.original):
                self.report(self.original, "GM405", "render_mode must reach __init__: add a render_mode=None parameter to the base class and store self.render_mode", FixKind.FLAG)
                return
            self.extra_init = cst.parse_statement(
                "def __init__(self, render_mode=None):\n    self.render_mode = render_mode\n",
                config=cst.PartialParserConfig(),
            ).with_changes(leading_lines=[cst.EmptyLine(indent=False)])  # type: ignore[assignment]
            self.report(self.original, "GM405", "added __init__(self, render_mode=None) storing self.render_mode: gymnasium.make passes render_mode to the constructor")
            return
        orig, fn = pair
        if "render_mode" not in _param_names(fn):
            fn = fn.with_changes(params=_add_keyword_param(fn.params, "render_mode"))
            self.report(orig, "GM405", "__init__ takes render_mode=None (gymnasium.make passes it) and stores self.render_mode")
        if not _contains(fn, m.Attribute(value=m.Name("self"), attr=m.Name("render_mode"))):
            fn = fn.with_changes(body=_insert_after_super_init(fn.body, cst.parse_statement("self.render_mode = render_mode")))
        self.set_method("__init__", fn)

    # -- GM509 -------------------------------------------------------------------------------

    def _check_float64_observations(self) -> None:
        if not _declares_float32_box(self.original):
            return
        for name in ("reset", "step"):
            old = self.renamed.get(name, name)
            orig = self.orig_methods.get(old)
            if orig is None:
                continue
            for ret in own_returns(orig):
                obs = _observation_of(ret.value, name)
                if obs is not None and _is_float64_array(obs) and not _state_is_float32(self.original):
                    self.report(obs, "GM509", "observation built with np.array(...) is float64 but observation_space is a float32 Box; pass dtype=np.float32 (check_env rejects it)")


# -- pure helpers -----------------------------------------------------------------------------


def _is_metadata_expr(expr: cst.BaseExpression) -> bool:
    return m.matches(expr, m.Attribute(attr=m.Name("metadata")) | m.Name("metadata"))


def _is_metadata_store(node: cst.CSTNode | None) -> bool:
    """``metadata = {...}`` in a class body or ``self.metadata = {...}``."""
    if isinstance(node, cst.Assign):
        return any(_is_metadata_expr(t.target) for t in node.targets)
    if isinstance(node, cst.AnnAssign):
        return _is_metadata_expr(node.target)
    return False


def _string_key(element: cst.BaseDictElement) -> str | None:
    if isinstance(element, cst.DictElement) and isinstance(element.key, cst.SimpleString):
        value = element.key.evaluated_value
        return value if isinstance(value, str) else None
    return None


def _append_element(elements: Sequence[cst.BaseDictElement], new: cst.DictElement) -> list[cst.BaseDictElement]:
    """Append keeping the layout: a one-line dict stays one line, a multi-line one gets a new line."""
    items = list(elements)
    if not items:
        return [new]
    last = items[-1]
    if isinstance(last.comma, cst.Comma):  # trailing comma: the new element takes over the closing layout
        between = items[-2].comma if len(items) > 1 and isinstance(items[-2].comma, cst.Comma) else cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
        items[-1] = last.with_changes(comma=between)
        return [*items, new.with_changes(comma=last.comma)]
    items[-1] = last.with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
    return [*items, new]


def _defines_reward_range(classdef: cst.ClassDef) -> bool:
    return _contains(classdef, m.AssignTarget(m.Name("reward_range") | m.Attribute(value=m.Name("self"), attr=m.Name("reward_range"))))


def _uses_mujoco_py(classdef: cst.ClassDef) -> bool:
    if _contains(classdef, m.Attribute(value=m.Attribute(value=m.Name("self"), attr=m.Name("sim")))):
        return True
    return not _contains(classdef, m.Name("observation_space") | m.Arg(keyword=m.Name("observation_space")))


def _contains(node: cst.CSTNode, matcher: m.BaseMatcherNode) -> bool:
    return bool(m.findall(node, matcher))


def _param_names(fn: cst.FunctionDef) -> list[str]:
    params = fn.params
    found = [p.name.value for p in (*params.posonly_params, *params.params)]
    if isinstance(params.star_arg, cst.Param):
        found.append(params.star_arg.name.value)
    found += [p.name.value for p in params.kwonly_params]
    if params.star_kwarg is not None:
        found.append(params.star_kwarg.name.value)
    return found


def _body_statements(fn: cst.FunctionDef) -> list[cst.BaseStatement]:
    return list(fn.body.body) if isinstance(fn.body, cst.IndentedBlock) else []


def _is_docstring(stmt: cst.CSTNode) -> bool:
    return m.matches(stmt, m.SimpleStatementLine([m.Expr(m.SimpleString() | m.ConcatenatedString())]))


def _np_random_seeding(stmt: cst.BaseStatement, analysis: ReceiverAnalysis) -> set[str] | None:
    """``self.np_random, seed = seeding.np_random(seed)``: the names bound besides np_random."""
    if not m.matches(stmt, m.SimpleStatementLine([m.Assign()])):
        return None
    assign = stmt.body[0]  # type: ignore[attr-defined]
    if len(assign.targets) != 1 or not E.is_seeding_np_random(analysis, assign.value):
        return None
    target = assign.targets[0].target
    if m.matches(target, m.Attribute(value=m.Name("self"), attr=m.Name("np_random") | m.Name("_np_random"))):
        return set()
    if isinstance(target, (cst.Tuple, cst.List)) and target.elements:
        first = target.elements[0].value
        if m.matches(first, m.Attribute(value=m.Name("self"), attr=m.Name("np_random") | m.Name("_np_random"))):
            return {el.value.value for el in target.elements[1:] if isinstance(el.value, cst.Name)}
    return None


def _is_seeding_statement(stmt: cst.BaseStatement, seed_names: set[str]) -> bool:
    """Uses the seed, or seeds something (``random.seed()``, ``space.seed()``, ``sim.set_seed()``)."""
    if any(m.findall(stmt, m.Name(name)) for name in seed_names):
        return True
    return _contains(stmt, m.Call(func=m.Attribute(attr=m.MatchIfTrue(lambda n: "seed" in n.value))))


def _modern_reset_params(fn: cst.FunctionDef) -> cst.FunctionDef:
    params = fn.params
    keep = [p for p in params.params if p.name.value not in ("seed", "options", "return_info")]
    old = {p.name.value: p for p in (*params.params, *params.kwonly_params)}
    kwonly = [p for p in params.kwonly_params if p.name.value not in ("seed", "options", "return_info")]
    for name in ("seed", "options"):
        param = old.get(name) or cst.Param(cst.Name(name), default=cst.Name("None"))
        param = param.with_changes(
            default=param.default or cst.Name("None"),
            equal=cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace(""))
            if param.annotation is None
            else param.equal,
            comma=cst.MaybeSentinel.DEFAULT,
            whitespace_after_param=cst.SimpleWhitespace(""),
        )
        kwonly.append(param)
    keep = [p.with_changes(comma=cst.MaybeSentinel.DEFAULT) for p in keep]
    star_arg = params.star_arg if isinstance(params.star_arg, cst.Param) else cst.ParamStar()
    star_kwarg = params.star_kwarg.with_changes(comma=cst.MaybeSentinel.DEFAULT) if params.star_kwarg else None
    return fn.with_changes(
        params=params.with_changes(params=keep, star_arg=star_arg, kwonly_params=kwonly, star_kwarg=star_kwarg)
    )


def _add_keyword_param(params: cst.Parameters, name: str) -> cst.Parameters:
    new = cst.Param(
        cst.Name(name),
        default=cst.Name("None"),
        equal=cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace("")),
    )
    if isinstance(params.star_arg, cst.Param) or params.kwonly_params:
        return params.with_changes(kwonly_params=_append_param(params.kwonly_params, new))
    return params.with_changes(params=_append_param(params.params, new))


def _append_param(existing: Sequence[cst.Param], new: cst.Param) -> list[cst.Param]:
    items = list(existing)
    if not items:
        return [new]
    last = items[-1]
    if isinstance(last.comma, cst.Comma):
        between = items[-2].comma if len(items) > 1 and isinstance(items[-2].comma, cst.Comma) else cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))
        items[-1] = last.with_changes(comma=between)
        return [*items, new.with_changes(comma=last.comma)]
    return [*items, new]


def _insert_at_top(body: cst.BaseSuite, statements: list[cst.BaseStatement]) -> cst.BaseSuite:
    if not isinstance(body, cst.IndentedBlock):
        return body
    existing = list(body.body)
    at = 1 if existing and _is_docstring(existing[0]) else 0
    return body.with_changes(body=[*existing[:at], *statements, *existing[at:]])


def _insert_after_super_init(body: cst.BaseSuite, statement: cst.BaseStatement) -> cst.BaseSuite:
    if not isinstance(body, cst.IndentedBlock):
        return body
    existing = list(body.body)
    at = 1 if existing and _is_docstring(existing[0]) else 0
    for index, stmt in enumerate(existing[at:], start=at):
        if _contains(stmt, m.Call(func=m.Attribute(attr=m.Name("__init__")))):
            at = index + 1
            break
        if index > at + 2:
            break
    return body.with_changes(body=[*existing[:at], statement, *existing[at:]])


def _is_tuple_annotation(annotation: cst.BaseExpression, length: int) -> bool:
    return (
        isinstance(annotation, cst.Subscript)
        and m.matches(annotation.value, m.Name("Tuple") | m.Name("tuple") | m.Attribute(attr=m.Name("Tuple")))
        and len(annotation.slice) == length
    )


def _calls_super_reset(fn: cst.FunctionDef) -> bool:
    return any(E.is_super_method_call(c, "reset") for c in m.findall(fn.body, m.Call()))


def _ensure_super_reset(fn: cst.FunctionDef) -> tuple[cst.FunctionDef, bool]:
    """Insert ``super().reset(seed=seed)`` first, or add ``seed=seed`` to an existing call."""
    calls = [c for c in m.findall(fn.body, m.Call()) if E.is_super_method_call(c, "reset")]
    if calls:
        return fn.with_changes(body=fn.body.visit(_SuperResetFixer())), False
    return fn.with_changes(body=_insert_at_top(fn.body, [cst.parse_statement(SUPER_RESET)])), True


def _insert_after_super_reset(fn: cst.FunctionDef, statements: list[cst.BaseStatement]) -> cst.FunctionDef:
    body = fn.body
    if not isinstance(body, cst.IndentedBlock):
        return fn
    existing = list(body.body)
    guard = cst.If(
        test=cst.parse_expression("seed is not None"),
        body=cst.IndentedBlock([s.with_changes(leading_lines=[]) if i == 0 else s for i, s in enumerate(statements)]),  # type: ignore[union-attr]
    )
    for index, stmt in enumerate(existing):
        if any(E.is_super_method_call(c, "reset") for c in m.findall(stmt, m.Call())):
            return fn.with_changes(body=body.with_changes(body=[*existing[: index + 1], guard, *existing[index + 1 :]]))
    return fn.with_changes(body=_insert_at_top(body, [guard]))


def _drop_return_info(fn: cst.FunctionDef) -> cst.FunctionDef:
    return fn.with_changes(body=fn.body.visit(_ReturnInfoRemover()))


def _tuple_len(value: cst.BaseExpression | None) -> int | None:
    if isinstance(value, cst.Tuple) and not any(isinstance(el, cst.StarredElement) for el in value.elements):
        return len(value.elements)
    return None


def _assigns_name(fn: cst.CSTNode, name: str) -> bool:
    return _contains(fn, m.AssignTarget(m.Name(name)) | m.AssignTarget(m.Tuple([m.ZeroOrMore(), m.Element(m.Name(name)), m.ZeroOrMore()])))


def _single_assignment(fn: cst.FunctionDef, name: str) -> cst.BaseExpression | None:
    assigns = m.findall(fn, m.Assign(targets=[m.AssignTarget(m.Name(name))]))
    others = m.findall(fn, m.AugAssign(target=m.Name(name)) | m.AnnAssign(target=m.Name(name)) | m.For(target=m.Name(name)))
    if len(assigns) != 1 or others or _assigns_in_tuple(fn, name):
        return None
    return assigns[0].value  # type: ignore[attr-defined]


def _assigns_in_tuple(fn: cst.FunctionDef, name: str) -> bool:
    return _contains(fn, m.AssignTarget(m.Tuple([m.ZeroOrMore(), m.Element(m.Name(name)), m.ZeroOrMore()])))


def _uses_name(fn: cst.CSTNode, name: str) -> bool:
    return _contains(fn, m.Name(name))


def _declares_global(fn: cst.FunctionDef, name: str) -> bool:
    return _contains(fn, m.Global(names=[m.ZeroOrMore(), m.NameItem(m.Name(name)), m.ZeroOrMore()]) | m.Nonlocal())


def _rebinds_name(fn: cst.FunctionDef, name: str) -> bool:
    return _assigns_name(fn.body, name) or _contains(fn.body, m.AugAssign(target=m.Name(name)) | m.For(target=m.Name(name)))


def _reads_name_outside_returns(fn: cst.FunctionDef, name: str) -> bool:
    total = len(m.findall(fn.body, m.Name(name)))
    in_returns = sum(len(m.findall(r, m.Name(name))) for r in own_returns(fn))
    stores = len(m.findall(fn.body, m.AssignTarget(m.Name(name))))
    return total - in_returns - stores > 0


def _identifiers(node: cst.CSTNode) -> list[str]:
    found = [n.value for n in m.findall(node, m.Name())]  # type: ignore[attr-defined]
    return found


def _is_step_limit(expr: cst.BaseExpression) -> bool:
    if not isinstance(expr, cst.Comparison) or not all(isinstance(t.operator, _LIMIT_OPS) for t in expr.comparisons):
        return False
    return any(_STEP_LIMIT_WORD.search(word) and "beyond" not in word for word in _identifiers(expr))


def _or_operands(expr: cst.BaseExpression) -> list[cst.BaseExpression]:
    if isinstance(expr, cst.BooleanOperation) and isinstance(expr.operator, cst.Or) and not expr.lpar:
        return _or_operands(expr.left) + _or_operands(expr.right)
    if isinstance(expr, cst.BooleanOperation) and isinstance(expr.operator, cst.Or):
        return _or_operands(expr.with_changes(lpar=[], rpar=[]))
    return [expr]


def _split_done(expr: cst.BaseExpression) -> tuple[list[cst.BaseExpression], list[cst.BaseExpression]] | None:
    """``bool(task or self.steps >= self.max_steps)`` -> ([task], [limit]); None if no clear limit."""
    if m.matches(expr, m.Call(func=m.Name("bool"), args=[m.Arg(keyword=None)])):
        expr = expr.args[0].value  # type: ignore[attr-defined]
    operands = _or_operands(expr)
    limit = [op for op in operands if _is_step_limit(op)]
    if not limit:
        return None
    task = [op for op in operands if not _is_step_limit(op)]
    return task, limit


def _code(node: cst.CSTNode) -> str:
    return cst.Module([]).code_for_node(node)


def _bool_of(parts: list[cst.BaseExpression]) -> cst.BaseExpression:
    if not parts:
        return cst.Name("False")
    text = " or ".join(_code(p.with_changes(lpar=[], rpar=[]) if len(parts) == 1 else p).strip() for p in parts)  # type: ignore[call-arg]
    return cst.parse_expression(f"bool({text})")


def _needs_bool(expr: cst.BaseExpression) -> bool:
    return isinstance(expr, (cst.Comparison, cst.BooleanOperation, cst.UnaryOperation))


def _five(terminated: cst.BaseExpression, truncated: cst.BaseExpression) -> Callable[[cst.Return], cst.Return]:
    def rewrite(ret: cst.Return) -> cst.Return:
        value = ret.value
        assert isinstance(value, cst.Tuple)
        elements = list(value.elements)
        third = elements[2]
        elements[2:3] = [
            third.with_changes(value=terminated, comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" "))),
            cst.Element(truncated, comma=third.comma),
        ]
        return ret.with_changes(value=value.with_changes(elements=elements))

    return rewrite


def _step_limit_text(fn: cst.FunctionDef) -> str | None:
    for comparison in m.findall(fn.body, m.Comparison()):
        if _is_step_limit(comparison):  # type: ignore[arg-type]
            return _code(comparison).strip()
    return None


def _truncated_false_message(limit_hint: str | None) -> str:
    if limit_hint:
        return f"step returns truncated=False, but `{limit_hint}` looks like a step limit: return it as truncated, not terminated"
    return "step returns terminated (the old done) and truncated=False; set truncated if the env stops episodes on a step limit"


def _bool_wrap_assignments(body: cst.BaseSuite, name: str) -> cst.BaseSuite:
    """``terminated = x > 1`` -> ``terminated = bool(x > 1)``: check_env wants a Python bool."""

    class Wrap(cst.CSTTransformer):
        def leave_Assign(self, original_node: cst.Assign, updated_node: cst.Assign) -> cst.Assign:
            if m.matches(updated_node, m.Assign(targets=[m.AssignTarget(m.Name(name))])) and _needs_bool(updated_node.value):
                return updated_node.with_changes(value=_bool_of([updated_node.value]))
            return updated_node

    return body.visit(Wrap())


def _rename_names(node: cst.CSTNodeT, renames: dict[str, str]) -> cst.CSTNodeT:
    if not renames:
        return node
    return node.visit(_NameRenamer(renames))  # type: ignore[return-value]


def _declares_float32_box(classdef: cst.ClassDef) -> bool:
    for assign in m.findall(classdef, m.Assign(targets=[m.AssignTarget(m.Attribute(value=m.Name("self"), attr=m.Name("observation_space")))])):
        value = assign.value  # type: ignore[attr-defined]
        if not m.matches(value, m.Call(func=m.Name("Box") | m.Attribute(attr=m.Name("Box")))):
            continue
        dtype = next((a.value for a in value.args if m.matches(a.keyword, m.Name("dtype"))), None)
        if dtype is None or m.matches(dtype, m.Attribute(attr=m.Name("float32")) | m.Name("float32")):
            return True
    return False


def _state_is_float32(classdef: cst.ClassDef) -> bool:
    """``self.state`` is stored as a float32 array somewhere, so ``np.array(self.state)`` keeps float32."""
    stores = m.findall(classdef, m.Assign(targets=[m.AssignTarget(m.Attribute(value=m.Name("self"), attr=m.Name("state")))]))
    return any("float32" in _code(assign.value) for assign in stores)  # type: ignore[attr-defined]


def _observation_of(value: cst.BaseExpression | None, method: str) -> cst.BaseExpression | None:
    if value is None:
        return None
    if method == "step":
        return value.elements[0].value if _tuple_len(value) in (4, 5) else None  # type: ignore[union-attr]
    if _tuple_len(value) == 2:
        return None  # (obs, info) or a tuple observation: cannot tell
    return value


def _is_float64_array(expr: cst.BaseExpression) -> bool:
    if not m.matches(expr, m.Call(func=m.Attribute(value=m.Name("np") | m.Name("numpy"), attr=m.Name("array") | m.Name("asarray")))):
        return False
    call: cst.Call = expr  # type: ignore[assignment]
    if any(m.matches(a.keyword, m.Name("dtype")) for a in call.args) or len(call.args) != 1:
        return False
    # A physics state (tuple of Python floats) or a literal list: float64 unless told otherwise.
    return m.matches(call.args[0].value, m.Attribute(value=m.Name("self"), attr=m.Name("state")) | m.List() | m.Tuple())


# -- transformers ---------------------------------------------------------------------------------


class _ReturnRewriter(cst.CSTTransformer):
    def __init__(self, rewrite: Callable[[cst.Return], cst.Return]) -> None:
        self.rewrite = rewrite

    def visit_FunctionDef(self, node: cst.FunctionDef) -> bool:
        return False

    def visit_ClassDef(self, node: cst.ClassDef) -> bool:
        return False

    def visit_Lambda(self, node: cst.Lambda) -> bool:
        return False

    def leave_Return(self, original_node: cst.Return, updated_node: cst.Return) -> cst.Return:
        return self.rewrite(updated_node)


class _NameRenamer(cst.CSTTransformer):
    """Renames variables, not attributes, keywords or parameters spelled the same."""

    def __init__(self, renames: dict[str, str]) -> None:
        self.renames = renames

    def leave_Name(self, original_node: cst.Name, updated_node: cst.Name) -> cst.Name:
        new = self.renames.get(updated_node.value)
        return updated_node.with_changes(value=new) if new else updated_node

    def leave_Attribute(self, original_node: cst.Attribute, updated_node: cst.Attribute) -> cst.Attribute:
        return updated_node.with_changes(attr=original_node.attr)

    def leave_Arg(self, original_node: cst.Arg, updated_node: cst.Arg) -> cst.Arg:
        return updated_node.with_changes(keyword=original_node.keyword)

    def leave_Param(self, original_node: cst.Param, updated_node: cst.Param) -> cst.Param:
        return updated_node.with_changes(name=original_node.name)


class _ModeReader(cst.CSTTransformer):
    """``mode`` -> ``self.render_mode`` in a render body; ``super().render(mode)`` loses its argument."""

    def visit_FunctionDef(self, node: cst.FunctionDef) -> bool:
        return False

    def leave_Name(self, original_node: cst.Name, updated_node: cst.Name) -> cst.BaseExpression:  # type: ignore[override]
        if updated_node.value == "mode":
            return cst.Attribute(value=cst.Name("self"), attr=cst.Name("render_mode"))
        return updated_node

    def leave_Attribute(self, original_node: cst.Attribute, updated_node: cst.Attribute) -> cst.Attribute:
        return updated_node.with_changes(attr=original_node.attr)

    def leave_Arg(self, original_node: cst.Arg, updated_node: cst.Arg) -> cst.Arg:
        return updated_node.with_changes(keyword=original_node.keyword)

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.Call:
        if E.is_super_method_call(original_node, "render"):
            return updated_node.with_changes(args=[])
        return updated_node


class _SuperResetFixer(cst.CSTTransformer):
    """An existing ``super().reset(...)``: pass ``seed=seed`` and drop ``return_info``."""

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.Call:
        if not E.is_super_method_call(original_node, "reset"):
            return updated_node
        args = [a for a in updated_node.args if not m.matches(a.keyword, m.Name("return_info"))]
        changed = len(args) != len(updated_node.args)
        if not any(m.matches(a.keyword, m.Name("seed")) for a in args) and not any(a.star for a in args):
            if args:
                args[-1] = args[-1].with_changes(comma=cst.Comma(whitespace_after=cst.SimpleWhitespace(" ")))
            args.append(cst.Arg(cst.Name("seed"), keyword=cst.Name("seed"), equal=cst.AssignEqual(cst.SimpleWhitespace(""), cst.SimpleWhitespace(""))))
            changed = True
        if not changed:
            return updated_node
        if args:
            args[-1] = args[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
        return updated_node.with_changes(args=args)


class _ReturnInfoRemover(cst.CSTTransformer):
    """Keeps the ``return_info=True`` branch of ``if return_info:`` / ``... if return_info else ...``."""

    def visit_FunctionDef(self, node: cst.FunctionDef) -> bool:
        return False

    def leave_IndentedBlock(self, original_node: cst.IndentedBlock, updated_node: cst.IndentedBlock) -> cst.IndentedBlock:
        statements: list[cst.BaseStatement] = []
        # Tests are read on the original nodes: leave_Name has already replaced return_info below.
        for original, stmt in zip(original_node.body, updated_node.body):
            branch = _return_info_branch(original, stmt)
            if branch is None:
                statements.append(stmt)
                continue
            kept = list(branch.body) if isinstance(branch, cst.IndentedBlock) else []
            if kept:
                kept[0] = kept[0].with_changes(leading_lines=stmt.leading_lines)  # type: ignore[union-attr]
            statements.extend(kept)
            if kept and m.matches(kept[-1], m.SimpleStatementLine([m.Return()])):
                break  # what followed was the return_info=False path
        if not statements:
            statements = [cst.SimpleStatementLine([cst.Pass()])]
        return updated_node.with_changes(body=statements)

    def leave_IfExp(self, original_node: cst.IfExp, updated_node: cst.IfExp) -> cst.BaseExpression:
        if m.matches(original_node.test, m.Name("return_info")):
            return updated_node.body
        if m.matches(original_node.test, m.UnaryOperation(operator=m.Not(), expression=m.Name("return_info"))):
            return updated_node.orelse
        return updated_node

    def leave_Name(self, original_node: cst.Name, updated_node: cst.Name) -> cst.Name:
        return cst.Name("True") if updated_node.value == "return_info" else updated_node

    def leave_Arg(self, original_node: cst.Arg, updated_node: cst.Arg) -> cst.Arg:
        return updated_node.with_changes(keyword=original_node.keyword)

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.Call:
        args = [a for a in updated_node.args if not m.matches(a.keyword, m.Name("return_info"))]
        if len(args) == len(updated_node.args):
            return updated_node
        if args:
            args[-1] = args[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
        return updated_node.with_changes(args=args)


def _return_info_branch(original: cst.BaseStatement, stmt: cst.BaseStatement) -> cst.BaseSuite | None:
    """For ``if return_info:`` (or ``if not return_info:``) the suite that runs when it is True."""
    if not isinstance(original, cst.If) or not isinstance(stmt, cst.If):
        return None
    if m.matches(original.test, m.Name("return_info")):
        return stmt.body
    if m.matches(original.test, m.UnaryOperation(operator=m.Not(), expression=m.Name("return_info"))):
        if isinstance(stmt.orelse, cst.Else):
            return stmt.orelse.body
        return cst.IndentedBlock([])
    return None


class _DoneSplitter(cst.CSTTransformer):
    """``done = bool(task or limit)`` -> ``terminated = bool(task)`` / ``truncated = bool(limit)``."""

    def __init__(self, name: str, task: list[cst.BaseExpression], limit: list[cst.BaseExpression], keep_done: bool) -> None:
        self.name = name
        self.task = task
        self.limit = limit
        self.keep_done = keep_done

    def leave_SimpleStatementLine(
        self, original_node: cst.SimpleStatementLine, updated_node: cst.SimpleStatementLine
    ) -> cst.BaseStatement | cst.FlattenSentinel[cst.BaseStatement]:
        if not m.matches(updated_node, m.SimpleStatementLine([m.Assign(targets=[m.AssignTarget(m.Name(self.name))])])):
            return updated_node
        lines = [
            updated_node.with_changes(body=[cst.Assign([cst.AssignTarget(cst.Name("terminated"))], _bool_of(self.task))]),
            cst.SimpleStatementLine([cst.Assign([cst.AssignTarget(cst.Name("truncated"))], _bool_of(self.limit))]),
        ]
        if self.keep_done:
            lines.append(cst.parse_statement(f"{self.name} = terminated or truncated"))  # type: ignore[arg-type]
        return cst.FlattenSentinel(lines)


class _SelfCallFinder(cst.CSTVisitor):
    def __init__(self, methods: set[str]) -> None:
        self.methods = methods
        self.calls: list[cst.Call] = []

    def visit_Call(self, node: cst.Call) -> None:
        if m.matches(node.func, m.Attribute(value=m.Name("self"))) and node.func.attr.value in self.methods:  # type: ignore[attr-defined]
            self.calls.append(node)


class _SelfSeedCallRemover(cst.CSTTransformer):
    """Drops ``self.seed(...)`` statements, or puts ``replacement`` statements in their place."""

    def __init__(self, replacement: list[cst.BaseStatement] | None = None) -> None:
        self.replacement = replacement or []

    def leave_IndentedBlock(self, original_node: cst.IndentedBlock, updated_node: cst.IndentedBlock) -> cst.IndentedBlock:
        kept: list[cst.BaseStatement] = []
        carried: Sequence[cst.EmptyLine] = ()
        for stmt in updated_node.body:
            if m.matches(stmt, m.SimpleStatementLine([m.Expr(m.Call(func=m.Attribute(value=m.Name("self"), attr=m.Name("seed") | m.Name("_seed"))))])):
                carried = stmt.leading_lines  # type: ignore[attr-defined]
                if self.replacement:
                    kept.extend([self.replacement[0].with_changes(leading_lines=carried), *self.replacement[1:]])  # type: ignore[union-attr]
                    carried = ()
                continue
            if carried:
                stmt = stmt.with_changes(leading_lines=[*carried, *stmt.leading_lines])  # type: ignore[union-attr]
                carried = ()
            kept.append(stmt)
        if len(kept) == len(updated_node.body) and not self.replacement:
            return updated_node
        if not kept:
            kept = [cst.SimpleStatementLine([cst.Pass()])]
        return updated_node.with_changes(body=kept)


class _SelfMethodCallRenamer(cst.CSTTransformer):
    def __init__(self, renames: dict[str, str]) -> None:
        self.renames = renames

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.Call:
        func = updated_node.func
        if m.matches(func, m.Attribute(value=m.Name("self"))) and func.attr.value in self.renames:  # type: ignore[attr-defined]
            return updated_node.with_changes(func=func.with_changes(attr=cst.Name(self.renames[func.attr.value])))  # type: ignore[attr-defined]
        return updated_node


class _SelfResetUnpacker(cst.CSTTransformer):
    """``x = self.reset()`` -> ``x, _ = self.reset()``."""

    def leave_Assign(self, original_node: cst.Assign, updated_node: cst.Assign) -> cst.Assign:
        reset = m.Call(func=m.Attribute(value=m.Name("self"), attr=m.Name("reset") | m.Name("_reset")))
        if not m.matches(updated_node, m.Assign(targets=[m.AssignTarget(m.Name() | m.Attribute())], value=reset)):
            return updated_node
        target = cst.Tuple([cst.Element(updated_node.targets[0].target), cst.Element(cst.Name("_"))], lpar=[], rpar=[])
        return updated_node.with_changes(targets=[updated_node.targets[0].with_changes(target=target)])
