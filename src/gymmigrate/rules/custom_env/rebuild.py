"""Carry out what the family decided for one env class, on its LibCST node (the apply
layer: ``env_class.py`` loads it when the class's build first runs).

``plans.ClassPlan`` holds the decisions taken on ``ast`` (which methods are renamed, what
``seed()`` moves where, whether ``super().reset`` may seed...). ``rewrite_class`` is the
``build`` of the class's ``plan.replace``: it gets the class as other edits left it and
rewrites its methods in the order the rules depend on each other (``seed`` folds into
``reset``; ``render`` adds ``render_mode`` to ``__init__``). It reports nothing.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence

import libcst as cst
import libcst.matchers as m

from gymmigrate.edits.arguments import append_keyword
from gymmigrate.rules.custom_env.cst_edits import (
    _add_keyword_param,
    _body_statements,
    _bool_of,
    _bool_wrap_assignments,
    _calls_super_reset,
    _code,
    _DoneSplitter,
    _drop_return_info,
    _ensure_super_reset,
    _five,
    _HelperReturnUnpacker,
    _insert_after_super_init,
    _insert_after_super_reset,
    _insert_at_top,
    _is_step_limit,
    _is_tuple_annotation,
    _ModeReader,
    _modern_reset_params,
    _NameRenamer,
    _needs_bool,
    _param_names,
    _PerAgentSplitter,
    _rename_names,
    _ReturnRewriter,
    _SelfMethodCallRenamer,
    _SelfResetUnpacker,
    _SelfSeedCallRemover,
    _split_done,
    _tuple_len,
    is_base_reset,
    pair_untested_returns,
    visit_suite,
)
from gymmigrate.rules.custom_env.cst_queries import (
    OwnBodyOnly,
    _assigns_name,
    _checks_is_none,
    _declares_global,
    _index,
    _reads_name_outside_returns,
    _rebinds_name,
    _single_assignment,
    _uses_name,
    _uses_self_attribute,
    own_returns,
)
from gymmigrate.rules.custom_env.plans import ClassPlan, SeedPlan


class ClassRewrite:
    def __init__(self, plan: ClassPlan, updated: cst.ClassDef) -> None:
        self.plan = plan
        self.updated = updated
        self.methods = _class_methods(updated)
        self.renamed = plan.renamed
        self.replacements: dict[str, cst.FunctionDef | None] = {}
        self.seed_folded: list[cst.BaseStatement] = []
        self.extra_init: cst.FunctionDef | None = None
        self.after_method: dict[str, list[cst.FunctionDef]] = {}  # new methods, by the method they follow

    def method(self, name: str) -> cst.FunctionDef | None:
        old = self.renamed.get(name, name)
        if old not in self.methods:
            return None
        fn = self.replacements.get(old, self.methods[old])
        assert fn is not None
        return fn

    def set_method(self, name: str, fn: cst.FunctionDef | None) -> None:
        self.replacements[self.renamed.get(name, name)] = fn

    def run(self) -> cst.ClassDef:
        for new, old in self.renamed.items():
            self.replacements[old] = self.methods[old].with_changes(name=cst.Name(new))
        for name in self.plan.dropped:
            self.replacements[name] = None
        if self.plan.seed is not None:
            self._seed(self.plan.seed)
        if not self.plan.reset_kept:  # kept with the class's own four-field step (GM504 reports both)
            self._reset()
        if not self.plan.batched_step:  # a batch's step keeps its stacked four fields (GM504 reports it)
            self._step()
        if self.plan.render:
            self._render()
        if self.plan.render_init_only:
            self._add_render_mode_to_init()
        if self.plan.pass_render_mode:
            self._pass_render_mode()
        if self.plan.unpack_self_reset:
            self._unpack_self_reset()
        rebuilt = self._rebuild()
        if self.plan.declare_render_modes:
            rebuilt = _declare_render_modes(rebuilt, self.plan.declare_render_modes)
        if self.plan.reset_alias is not None:
            rebuilt = _replace_reset_alias(rebuilt, *self.plan.reset_alias)
        return rebuilt

    def _rebuild(self) -> cst.ClassDef:
        body = self.updated.body
        if not isinstance(body, cst.IndentedBlock):
            return self.updated
        if self.renamed:
            calls = _SelfMethodCallRenamer({old: new for new, old in self.renamed.items()})
            for name, fn in self.methods.items():
                current = self.replacements.get(name, fn)
                if current is not None and name in self.plan.rename_callers:
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
                stmt = stmt.with_changes(leading_lines=carried)
                carried = None
            if self.extra_init is not None and isinstance(stmt, cst.FunctionDef):
                statements.append(self.extra_init)
                self.extra_init = None
            statements.append(stmt)
            if isinstance(stmt, cst.FunctionDef):
                statements.extend(self.after_method.get(stmt.name.value, ()))
        if self.extra_init is not None:
            statements.append(self.extra_init)
        if not statements:
            statements.append(cst.SimpleStatementLine([cst.Pass()]))
        return self.updated.with_changes(body=body.with_changes(body=statements))

    # -- GM503 ---------------------------------------------------------------------------

    def _seed(self, seed: SeedPlan) -> None:
        if seed.base_calls_only:
            for name in seed.callers:
                current = self.replacements.get(name, self.methods.get(name))
                if current is not None:
                    self.replacements[name] = current.visit(_SelfSeedCallRemover(None))  # type: ignore[assignment]
            return
        fn = self.method("seed")
        assert fn is not None
        if seed.keep:
            self.seed_folded = [cst.parse_statement(f"self.{fn.name.value}(seed)")]
            return
        body = _body_statements(fn)
        moved = [body[i] for i in seed.moved]
        setup = [body[i] for i in seed.setup]
        seed_method = self.renamed.get("seed", "seed")
        for name, method in list(self.methods.items()):
            current = self.replacements.get(name, method)
            if current is None or name == seed_method or name not in seed.callers:
                continue
            new = current.visit(_SelfSeedCallRemover(setup if name == "__init__" else None, seed.reseed))
            if new is not current:
                self.replacements[name] = new  # type: ignore[assignment]
        init = self.replacements.get("__init__", self.methods.get("__init__"))
        if seed.setup_at_init_end and setup and init is not None and isinstance(init.body, cst.IndentedBlock):
            # the comments above the first set-up line spoke of the seeding that went
            appended = [setup[0].with_changes(leading_lines=[]), *setup[1:]]
            self.replacements["__init__"] = init.with_changes(body=init.body.with_changes(body=[*init.body.body, *appended]))
        if moved:
            self.seed_folded = [_rename_names(s, seed.renames) for s in moved]
        self.set_method("seed", None)

    # -- GM501 / GM502 ---------------------------------------------------------------------

    def _reset(self) -> None:
        fn = self.method("reset")
        if fn is None:
            return
        names = _param_names(fn)
        legacy_flag = "return_info" in names
        modern = "seed" in names and "options" in names and not legacy_flag
        if not modern and not self.plan.reset_forwards_keywords:
            fn = _modern_reset_params(fn)
        if legacy_flag:
            if self.plan.reset_pairs_untested:
                fn = pair_untested_returns(fn)
            fn = _drop_return_info(fn)
        elif not modern and not self.plan.reset_returns_pairs:
            fn, base_info = (fn, None) if self.plan.reset_base_kept else _unpack_super_reset(fn, self.plan.reset_bases)
            fn = self._return_info_pairs(fn, base_info, frozenset(self.plan.reset_helpers), own=True)
            for helper in self.plan.reset_helpers:
                helper_fn = self.method(helper)
                if helper_fn is not None:
                    self.set_method(helper, self._return_info_pairs(helper_fn, None))
            if fn.returns is not None and not _is_tuple_annotation(fn.returns.annotation, 2):
                pair = cst.parse_expression(f"tuple[{_code(fn.returns.annotation).strip()}, dict]")
                fn = fn.with_changes(returns=fn.returns.with_changes(annotation=pair))
        bases = self.plan.reset_bases
        if not self.plan.reset_base_kept and (self.plan.reset_super_seeds or _calls_super_reset(fn, bases)):
            fn, _ = _ensure_super_reset(fn, bases)
        if self.plan.reset_rehands:
            # the object __init__ handed the generator to gets the one the seed just made
            # (first, so it ends up after whatever else is inserted after the super call)
            rehands: list[cst.BaseStatement] = [cst.parse_statement(f"{text}\n") for text in self.plan.reset_rehands]
            fn = _insert_after_super_reset(fn, rehands, bases)
        if self.seed_folded:
            fn = _insert_after_super_reset(fn, self.seed_folded, bases)
        if self.plan.reset_seed_hook is not None:
            # after super().reset(seed=seed), so what the hook seeds is what reset draws from
            call = cst.parse_statement(f"self.{self.plan.reset_seed_hook}(seed)\n")
            fn = _insert_after_super_reset(fn, [call], bases)
        if self.plan.reset_env_seeds is not None:
            # last, so it goes above what the lines before put first (under `if seed is not None:`)
            seeding = cst.parse_statement(f"{self.plan.reset_env_seeds}.Env.reset(self, seed=seed)\n")
            fn = fn.with_changes(body=_insert_at_top(fn.body, [seeding]))
        self.set_method("reset", fn)

    def _return_info_pairs(
        self, fn: cst.FunctionDef, base_info: str | None, helpers: frozenset[str] = frozenset(), own: bool = False
    ) -> cst.FunctionDef:
        info_expr: cst.BaseExpression = cst.Dict([])
        if base_info is not None:
            info_expr = cst.Name(base_info)
        elif _assigns_name(fn, "info"):
            info_expr = cst.Name("info")
        elif self.plan.info_helper:
            info_expr = cst.parse_expression("self._get_info()")

        # ``return self.reset()`` (a retry inside reset) returns the pair already
        retries = frozenset({"reset", self.renamed.get("reset", "reset")}) if own else frozenset()

        def pair(ret: cst.Return) -> cst.Return:
            if ret.value is None or (is_base_reset(ret.value, self.plan.reset_bases) and not self.plan.reset_base_kept):
                return ret  # the base reset already returns (obs, info)
            if _is_self_call(ret.value, helpers | retries):
                return ret  # a helper, or a retry of reset itself, that now returns (obs, info)
            if _is_inner_reset(ret.value, self.plan.inner_reset_receivers):
                # the held env's reset returns (obs, info) itself; a bare call gets the seed
                # and options, or the env could not be reset reproducibly (check_env fails)
                call = ret.value
                if isinstance(call, cst.Call) and not call.args:
                    bare = cst.parse_expression("f(seed=seed, options=options)")
                    assert isinstance(bare, cst.Call)
                    return ret.with_changes(value=call.with_changes(args=bare.args))
                return ret
            value = ret.value
            if isinstance(value, cst.Tuple) and not value.lpar:
                value = value.with_changes(lpar=[cst.LeftParen()], rpar=[cst.RightParen()])
            return ret.with_changes(value=cst.Tuple([cst.Element(value), cst.Element(info_expr)], lpar=[], rpar=[]))

        return fn.with_changes(body=fn.body.visit(_ReturnRewriter(pair)))

    # -- GM504 ---------------------------------------------------------------------------

    def _step(self) -> None:
        self._step_returns("step")
        for helper in self.plan.step_helpers:
            self._step_returns(helper)

    def _step_returns(self, method_name: str) -> None:
        fn = self.method(method_name)
        if fn is None:
            return
        returns = own_returns(fn)
        if any(_tuple_len(r.value) == 5 for r in returns):
            return  # already the five-value API
        planned = self.renamed.get(method_name, method_name)  # the name the plan knows it by
        splits: dict[str, tuple[list[cst.BaseExpression], list[cst.BaseExpression]]] = {}
        plans: list[Callable[[cst.Return], cst.Return] | None] = []
        rename_done = False
        truncating = self.plan.truncating_returns.get(planned, set())
        passing = self.plan.passthrough_returns.get(planned, set())
        task_ending = self.plan.task_end_returns.get(planned, set())
        foreign = self.plan.foreign_returns.get(planned, set())
        per_agent = self.plan.per_agent_returns.get(planned, {})
        per_agent_lines: dict[str, tuple[str, str]] = {}
        unpacked = self.plan.unpacked_helper_returns.get(planned, {})
        kept = self.plan.kept_returns.get(planned, set())
        accumulated = self.plan.accumulated_returns.get(planned, set())
        flagged = self.plan.flagged_limit_returns.get(planned, set())
        accumulating: str | None = None
        flagging: str | None = None
        task_ended: str | None = None
        for position, ret in enumerate(returns):
            if position in kept:
                plans.append(None)  # reported: what the base's step returns is not known
                continue
            if position in unpacked:
                plans.append(None)  # split into an unpack and a return below
                continue
            if not isinstance(ret.value, cst.Tuple) or _tuple_len(ret.value) != 4:  # _tuple_len: only tuples
                plans.append(None)
                continue
            done = ret.value.elements[2].value
            if position in passing:
                plans.append(_five(cst.Name("terminated"), cst.Name("truncated")))
                continue
            if position in foreign:
                plans.append(_five(done, cst.Name("False")))
                continue
            if position in per_agent:
                name, terminated_text, truncated_text = per_agent[position]
                if not name:  # the arrangement is the returned value itself
                    plans.append(_five(cst.parse_expression(terminated_text), cst.parse_expression(truncated_text)))
                    continue
                per_agent_lines[name] = (terminated_text, truncated_text)
                plans.append(_five(cst.Name("terminated"), cst.Name("truncated")))
                continue
            if position in task_ending and isinstance(done, cst.Name):
                # the class's own ends set terminated where they set the done; the step it
                # calls keeps its truncation, even when both fall on the same step
                task_ended = done.value
                plans.append(_five(cst.Name("terminated"), cst.Name("truncated")))
                continue
            if position in accumulated and isinstance(done, cst.Name):
                # ``done = done or <step limit>`` right before: that line becomes truncated
                accumulating = done.value
                if done.value == "done" and not _declares_global(fn, "done"):
                    rename_done = True
                    plans.append(_five(cst.Name("terminated"), cst.Name("truncated")))
                else:
                    plans.append(_five(_bool_of([done]), cst.Name("truncated")))
                continue
            if position in flagged and isinstance(done, cst.Name):
                # ``if <step limit>: done = True`` in the body: that line becomes truncated
                flagging = done.value
                if done.value == "done" and not _declares_global(fn, "done"):
                    rename_done = True
                    plans.append(_five(cst.Name("terminated"), cst.Name("truncated")))
                else:
                    plans.append(_five(_bool_of([done]), cst.Name("truncated")))
                continue
            if position in truncating:
                # The done is only a step limit: terminated=False, truncated=<done>.
                plans.append(_five(cst.Name("False"), _bool_of([done]) if _needs_bool(done) else done))
                continue
            if isinstance(done, cst.Name) and _assigns_name(fn, done.value):
                assigned = _single_assignment(fn, done.value)
                split = _split_done(assigned, self.plan.non_limit_tests) if assigned is not None else None
                if split is not None:
                    splits[done.value] = split
                    plans.append(_five(cst.Name("terminated"), cst.Name("truncated")))
                    continue
                if done.value == "done" and not truncating and not _uses_name(fn, "terminated") and not _declares_global(fn, "done"):
                    rename_done = True
                    plans.append(_five(cst.Name("terminated"), cst.Name("False")))
                else:
                    plans.append(_five(done, cst.Name("False")))
                continue
            split = _split_done(done, self.plan.non_limit_tests)
            if split is not None:
                task, limit = split
                plans.append(_five(_bool_of(task), _bool_of(limit)))
                continue
            terminated = _bool_of([done]) if _needs_bool(done) else done
            plans.append(_five(terminated, cst.Name("False")))
        if not any(plans) and not unpacked:
            return
        iterator = iter(plans)

        def rewrite(ret: cst.Return) -> cst.Return:
            plan = next(iterator)
            return plan(ret) if plan is not None else ret

        body = visit_suite(fn.body, _ReturnRewriter(rewrite))
        none_infos = self.plan.none_infos.get(planned)
        if none_infos:
            body = visit_suite(body, _NoneInfoFiller(none_infos))
        if unpacked:
            body = visit_suite(body, _HelperReturnUnpacker(unpacked))
        if fn.returns is not None and _is_tuple_annotation(fn.returns.annotation, 4):
            annotation = fn.returns.annotation
            elements = list(annotation.slice)  # type: ignore[attr-defined]
            elements.insert(3, elements[2])
            fn = fn.with_changes(returns=fn.returns.with_changes(annotation=annotation.with_changes(slice=elements)))
        for name, (task, limit) in splits.items():
            body = visit_suite(body, _DoneSplitter(name, task, limit, keep_done=_reads_name_outside_returns(fn, name)))
        for name, (terminated_text, truncated_text) in per_agent_lines.items():
            body = visit_suite(body, _PerAgentSplitter(name, terminated_text, truncated_text, keep=_reads_name_outside_returns(fn, name)))
        if accumulating is not None:
            body = _limit_line_to_truncated(body, accumulating, self.plan.non_limit_tests)
        if flagging is not None:
            body = _limit_flag_to_truncated(body, flagging, self.plan.non_limit_tests)
        if task_ended is not None:
            body = visit_suite(body, _TaskEndsTerminate(task_ended, _reads_beside_task_ends(fn, task_ended)))
        if rename_done:
            body = visit_suite(body, _NameRenamer({"done": "terminated"}))
            body = _bool_wrap_assignments(body, "terminated")
        self.set_method(method_name, fn.with_changes(body=body))

    # -- GM501: the class calling its own reset -------------------------------------------

    def _unpack_self_reset(self) -> None:
        for name, fn in self.methods.items():
            current = self.replacements.get(name, fn)
            if current is None or name in ("reset", self.renamed.get("reset")) or name not in self.plan.reset_callers:
                continue
            new = current.visit(_SelfResetUnpacker(self.plan.reset_bases))
            if new is not current:
                self.replacements[name] = new  # type: ignore[assignment]

    # -- GM405 ---------------------------------------------------------------------------

    def _render(self) -> None:
        fn = self.method("render")
        assert fn is not None
        helper = self.plan.render_helper
        if helper is not None:
            self._render_through_helper(fn, helper)
            return
        params = list(fn.params.params)
        mode_index = next(i for i, p in enumerate(params) if p.name.value == "mode")
        if self.plan.render_keeps_mode:
            # render(self, mode=None, ...): a caller's mode wins, else the env's own.
            mode = params[mode_index]
            params[mode_index] = mode.with_changes(
                default=cst.Name("None"), equal=mode.equal if mode.default is not None else cst.AssignEqual(
                    whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace(""))
            )
            lead = cst.parse_statement("if mode is None:\n    mode = self.render_mode\n")
            none = cst.parse_statement("if mode is None:\n    return None\n")
            body = _insert_at_top(fn.body, [lead, none])
            self.set_method("render", fn.with_changes(params=fn.params.with_changes(params=params), body=body))
            self._add_render_mode_to_init()
            return
        params.pop(mode_index)
        if params:
            params[-1] = params[-1].with_changes(comma=cst.MaybeSentinel.DEFAULT)
        new_params = fn.params.with_changes(params=params)
        if _rebinds_name(fn, "mode"):
            body = _insert_at_top(fn.body, [cst.parse_statement("mode = self.render_mode")])
        else:
            body = visit_suite(fn.body, _ModeReader(frozenset(self.plan.render_mode_receivers)))
        if not _checks_is_none(body, "render_mode"):
            body = _insert_at_top(body, [cst.parse_statement("if self.render_mode is None:\n    return None\n")])
        self.set_method("render", fn.with_changes(params=new_params, body=body))
        self._add_render_mode_to_init()

    def _render_through_helper(self, fn: cst.FunctionDef, helper: str) -> None:
        """``render(self, mode)`` becomes ``helper(self, mode)`` as it was; the new
        ``render()`` passes ``self.render_mode``; the class's own mode calls use the helper."""
        kept = fn.with_changes(name=cst.Name(helper), decorators=[], leading_lines=[cst.EmptyLine(indent=False)])
        render = cst.parse_statement(
            f"def render(self):\n    if self.render_mode is None:\n        return None\n"
            f"    return self.{helper}(mode=self.render_mode)\n"
        )
        self.set_method("render", render.with_changes(leading_lines=fn.leading_lines, decorators=fn.decorators))  # type: ignore[arg-type]
        calls = _SelfModeRenderCalls(helper)
        # The other methods' bare calls keep the old default; the old body's own stay render().
        outside = _SelfModeRenderCalls(helper, self.plan.render_helper_default)
        for name, method in self.methods.items():
            current = self.replacements.get(name, method)
            if current is not None and name in self.plan.render_helper_callers and name != self.renamed.get("render", "render"):
                self.replacements[name] = current.visit(outside)  # type: ignore[assignment]
        if self.renamed.get("render", "render") in self.plan.render_helper_callers:
            kept = kept.visit(calls)  # type: ignore[assignment]
        self.after_method.setdefault(self.renamed.get("render", "render"), []).append(kept)
        self._add_render_mode_to_init()

    def _pass_render_mode(self) -> None:
        fn = self.method("__init__")
        assert fn is not None
        fn = fn.with_changes(params=_add_keyword_param(fn.params, "render_mode"))

        class PassOn(cst.CSTTransformer):
            def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.Call:
                if m.matches(updated_node.func, m.Attribute(attr=m.Name("__init__"))):
                    return append_keyword(updated_node, "render_mode", cst.Name("render_mode"))
                return updated_node

        self.set_method("__init__", fn.with_changes(body=fn.body.visit(PassOn())))

    def _add_render_mode_to_init(self) -> None:
        fn = self.method("__init__")
        if fn is None:
            if self.plan.local_env_base:
                return
            self.extra_init = cst.parse_statement(
                "def __init__(self, render_mode=None):\n    self.render_mode = render_mode\n",
                config=cst.PartialParserConfig(),
            ).with_changes(leading_lines=[cst.EmptyLine(indent=False)])  # type: ignore[assignment]
            return
        if "render_mode" not in _param_names(fn):
            fn = fn.with_changes(params=_add_keyword_param(fn.params, "render_mode"))
        if not _uses_self_attribute(fn, "render_mode"):
            fn = fn.with_changes(body=_insert_after_super_init(fn.body, cst.parse_statement("self.render_mode = render_mode")))
        self.set_method("__init__", fn)


class _SelfModeRenderCalls(cst.CSTTransformer):
    """``self.render(mode="x")`` / ``self.render("x")`` -> ``self.<helper>(...)``; calls without
    arguments are the new render(), unless ``default`` is given (the old default mode, which
    they rendered in): then ``self.<helper>(mode=<default>)``."""

    def __init__(self, helper: str, default: str | None = None) -> None:
        self.helper = helper
        self.default = default

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.Call:
        func = updated_node.func
        if not (
            isinstance(func, cst.Attribute)
            and isinstance(func.value, cst.Name)
            and func.value.value == "self"
            and func.attr.value == "render"
        ):
            return updated_node
        if updated_node.args:
            return updated_node.with_changes(func=func.with_changes(attr=cst.Name(self.helper)))
        if self.default is not None:
            mode = cst.Arg(
                keyword=cst.Name("mode"),
                value=cst.parse_expression(self.default),
                equal=cst.AssignEqual(whitespace_before=cst.SimpleWhitespace(""), whitespace_after=cst.SimpleWhitespace("")),
            )
            return updated_node.with_changes(func=func.with_changes(attr=cst.Name(self.helper)), args=[mode])
        return updated_node


def _is_self_call(node: cst.BaseExpression, names: frozenset[str]) -> bool:
    return (
        isinstance(node, cst.Call)
        and isinstance(node.func, cst.Attribute)
        and isinstance(node.func.value, cst.Name)
        and node.func.value.value == "self"
        and node.func.attr.value in names
    )


def _class_methods(classdef: cst.ClassDef) -> dict[str, cst.FunctionDef]:
    body = classdef.body
    if not isinstance(body, cst.IndentedBlock):
        return {}
    return {stmt.name.value: stmt for stmt in body.body if isinstance(stmt, cst.FunctionDef)}


def _unpack_super_reset(fn: cst.FunctionDef, bases: frozenset[str]) -> tuple[cst.FunctionDef, str | None]:
    """``obs = super().reset()`` (or ``Base.reset(self)``) -> ``obs, info = ...``: the base env is migrated too."""
    assigned = [
        a for assigns in _index(fn).single_assigns.values() for a in assigns if is_base_reset(a.value, bases)
    ]
    if not assigned:
        return fn, None
    name = "info" if not _uses_name(fn, "info") else "base_info"

    class Unpack(cst.CSTTransformer):
        def leave_Assign(self, original_node: cst.Assign, updated_node: cst.Assign) -> cst.Assign:
            if not is_base_reset(updated_node.value, bases) or not isinstance(updated_node.targets[0].target, cst.Name):
                return updated_node
            target = cst.Tuple([cst.Element(updated_node.targets[0].target), cst.Element(cst.Name(name))], lpar=[], rpar=[])
            return updated_node.with_changes(targets=[updated_node.targets[0].with_changes(target=target)])

    return fn.with_changes(body=fn.body.visit(Unpack())), name


def _declare_render_modes(classdef: cst.ClassDef, modes: tuple[str, ...]) -> cst.ClassDef:
    listed = ", ".join(json.dumps(mode) for mode in modes)
    statement = cst.parse_statement(f'metadata = {{"render_modes": [{listed}]}}\n')
    body = _insert_at_top(classdef.body, [statement])
    if isinstance(body, cst.IndentedBlock):
        # the method that now follows it keeps a blank line above it
        statements = list(body.body)
        at = statements.index(statement) + 1
        following = statements[at] if at < len(statements) else None
        if isinstance(following, cst.FunctionDef) and not following.leading_lines:
            statements[at] = following.with_changes(leading_lines=[cst.EmptyLine(indent=False)])
        body = body.with_changes(body=statements)
    return classdef.with_changes(body=body)


def rewrite_class(plan: ClassPlan) -> Callable[[cst.ClassDef], cst.ClassDef]:
    def build(node: cst.ClassDef) -> cst.ClassDef:
        return ClassRewrite(plan, node).run()

    return build


def _is_inner_reset(value: cst.BaseExpression, receivers: set[str]) -> bool:
    """``self.env.reset(...)`` for a receiver in ``receivers`` (its source text)."""
    return (
        bool(receivers)
        and isinstance(value, cst.Call)
        and isinstance(value.func, cst.Attribute)
        and value.func.attr.value == "reset"
        and cst.Module(body=[]).code_for_node(value.func.value) in receivers
    )


def _limit_flag_to_truncated(body: cst.BaseSuite, name: str, data_ends: frozenset[str]) -> cst.BaseSuite:
    """``if <step limit>: name = True``, a statement of the body: ``truncated = bool(<step
    limit>)`` in its place (GM504 checked the shape: ``step_limits.flagged_limit``)."""
    if not isinstance(body, cst.IndentedBlock):
        return body
    statements = list(body.body)
    for i, statement in enumerate(statements):
        if not (isinstance(statement, cst.If) and statement.orelse is None and _is_step_limit(statement.test, data_ends)):
            continue
        inner = statement.body.body
        line = inner[0] if len(inner) == 1 else None
        if isinstance(line, cst.SimpleStatementLine):
            line = line.body[0] if len(line.body) == 1 else None
        if not (
            isinstance(line, cst.Assign)
            and len(line.targets) == 1
            and m.matches(line.targets[0].target, m.Name(name))
            and m.matches(line.value, m.Name("True"))
        ):
            continue
        assign = cst.Assign(targets=[cst.AssignTarget(cst.Name("truncated"))], value=_bool_of([statement.test]))
        # the comment of the ``if`` line (else of its one line) stays on the line that replaces them
        suite = statement.body
        header = suite.header if isinstance(suite, cst.IndentedBlock) else suite.trailing_whitespace  # type: ignore[attr-defined]
        trailing = inner[0].trailing_whitespace if isinstance(inner[0], cst.SimpleStatementLine) else header
        comment = header if header.comment is not None else trailing
        statements[i] = cst.SimpleStatementLine(body=[assign], leading_lines=statement.leading_lines, trailing_whitespace=comment)
        return body.with_changes(body=statements)
    return body


def _limit_line_to_truncated(body: cst.BaseSuite, name: str, data_ends: frozenset[str]) -> cst.BaseSuite:
    """``name = name or <step limit>``, the statement before the return: ``truncated =
    bool(<step limit>)`` (GM504 checked the shape: ``step_limits.accumulated_limit``)."""
    if not isinstance(body, cst.IndentedBlock) or len(body.body) < 2:
        return body
    line = body.body[-2]
    if not (isinstance(line, cst.SimpleStatementLine) and len(line.body) == 1 and isinstance(line.body[0], cst.Assign)):
        return body
    assign = line.body[0]
    split = _split_done(assign.value, data_ends)
    if split is None or len(assign.targets) != 1 or not m.matches(assign.targets[0].target, m.Name(name)):
        return body
    _, limit = split
    new = assign.with_changes(targets=[assign.targets[0].with_changes(target=cst.Name("truncated"))], value=_bool_of(limit))
    statements = list(body.body)
    statements[-2] = line.with_changes(body=[new])
    return body.with_changes(body=statements)


def _is_task_end(assign: cst.Assign, name: str) -> bool:
    """``name = True`` or ``name = name or <test>``: GM504 found every such line of the step
    to be the class's own end of the task (``step_delegates.task_ends``)."""
    if len(assign.targets) != 1 or not m.matches(assign.targets[0].target, m.Name(name)):
        return False
    value = assign.value
    return m.matches(value, m.Name("True")) or _or_operand_renamed(value, name, "terminated") is not value


def _or_operand_renamed(expr: cst.BaseExpression, name: str, new: str) -> cst.BaseExpression:
    """``<a> or name or <b>`` with ``name`` read as ``new``: the flag as an operand of the
    ``or`` itself (``facts.limit_tests.added_end_tests``), wherever it stands; ``expr`` itself
    where it is no such ``or``."""
    if not (isinstance(expr, cst.BooleanOperation) and isinstance(expr.operator, cst.Or)):
        return expr
    left, right = expr.left, expr.right
    # ``a or b or c`` nests to the left; a parenthesized ``or`` inside is an operand of its own
    if isinstance(left, cst.Name) and left.value == name:
        left = left.with_changes(value=new)
    elif not left.lpar:
        left = _or_operand_renamed(left, name, new)
    if isinstance(right, cst.Name) and right.value == name:
        right = right.with_changes(value=new)
    if left is expr.left and right is expr.right:
        return expr
    return expr.with_changes(left=left, right=right)


def _reads_beside_task_ends(fn: cst.FunctionDef, name: str) -> bool:
    """``name`` is read somewhere other than the returns and the ``name or <test>`` of its
    own task ends (``if done: self.reset_goal()``): it must keep holding the old done."""
    own = 0

    class Count(cst.CSTVisitor):
        def visit_Assign(self, node: cst.Assign) -> None:
            nonlocal own
            own += _is_task_end(node, name) and not m.matches(node.value, m.Name("True"))

    fn.body.visit(Count())
    index = _index(fn)
    in_returns = sum(_index(r).names.get(name, 0) for r in own_returns(fn))
    return index.names.get(name, 0) - in_returns - index.assign_targets.get(name, 0) - own > 0


class _TaskEndsTerminate(OwnBodyOnly, cst.CSTTransformer):
    """``done = True`` -> ``terminated = True`` and ``done = done or <test>`` -> ``terminated =
    terminated or <test>``: the class's own end is a terminal state on every step, the one a
    base's step limit truncates too. Where ``done`` is read elsewhere, it keeps the old
    meaning: ``done = True`` stays beside the new line, ``done = terminated or truncated``
    follows the other."""

    def __init__(self, name: str, keep: bool) -> None:
        self.name = name
        self.keep = keep

    def _terminating(self, assign: cst.Assign) -> list[cst.BaseSmallStatement]:
        target = [assign.targets[0].with_changes(target=cst.Name("terminated"))]
        if m.matches(assign.value, m.Name("True")):
            new = assign.with_changes(targets=target)
            return [assign, new] if self.keep else [new]
        new = assign.with_changes(targets=target, value=_or_operand_renamed(assign.value, self.name, "terminated"))
        if not self.keep:
            return [new]
        again = cst.parse_statement(f"{self.name} = terminated or truncated\n")
        assert isinstance(again, cst.SimpleStatementLine)
        return [new, again.body[0]]

    def _small_statements(self, statements: Sequence[cst.BaseSmallStatement]) -> list[cst.BaseSmallStatement] | None:
        """The statements with each task end replaced; None when none is one."""
        found: list[cst.BaseSmallStatement] = []
        for statement in statements:
            if isinstance(statement, cst.Assign) and _is_task_end(statement, self.name):
                found += self._terminating(statement.with_changes(semicolon=cst.MaybeSentinel.DEFAULT))
            else:
                found.append(statement)
        if len(found) == len(statements) and all(a is b for a, b in zip(found, statements)):
            return None
        semicolon = cst.Semicolon(whitespace_after=cst.SimpleWhitespace(" "))
        return [s.with_changes(semicolon=semicolon) for s in found[:-1]] + [found[-1].with_changes(semicolon=cst.MaybeSentinel.DEFAULT)]

    def leave_SimpleStatementLine(
        self, original_node: cst.SimpleStatementLine, updated_node: cst.SimpleStatementLine
    ) -> cst.SimpleStatementLine | cst.FlattenSentinel[cst.SimpleStatementLine]:
        if len(updated_node.body) == 1 and isinstance(updated_node.body[0], cst.Assign) and _is_task_end(updated_node.body[0], self.name):
            # a line of its own: the new statements get lines of their own
            first, *rest = self._terminating(updated_node.body[0])
            lines = [updated_node.with_changes(body=[first])]
            lines += [cst.SimpleStatementLine(body=[statement]) for statement in rest]
            return cst.FlattenSentinel(lines) if rest else lines[0]
        body = self._small_statements(updated_node.body)
        return updated_node if body is None else updated_node.with_changes(body=body)

    def leave_SimpleStatementSuite(
        self, original_node: cst.SimpleStatementSuite, updated_node: cst.SimpleStatementSuite
    ) -> cst.SimpleStatementSuite:
        # ``if solved: done = True`` on one line: the new statements stay on it
        body = self._small_statements(updated_node.body)
        return updated_node if body is None else updated_node.with_changes(body=body)


def _replace_reset_alias(classdef: cst.ClassDef, hook: str, seed_hook: str | None, calls_super: bool) -> cst.ClassDef:
    """``reset = <hook>`` in the class body (at its top level or under an ``if``/``try``
    there) -> a reset taking seed and options that seeds and returns the hook's observation
    with an empty info; the hook itself stays as it is for the code that calls it."""
    lines = ["def reset(self, *, seed=None, options=None):"]
    if calls_super:
        lines.append("    super().reset(seed=seed)")
    if seed_hook is not None:
        lines += ["    if seed is not None:", f"        self.{seed_hook}(seed)"]
    lines.append(f"    return self.{hook}(), {{}}")
    method = cst.parse_statement("\n".join(lines) + "\n")
    alias = m.SimpleStatementLine(body=[m.Assign(targets=[m.AssignTarget(target=m.Name("reset"))], value=m.Name(hook))])

    def replace(statements: Sequence[cst.BaseStatement]) -> list[cst.BaseStatement]:
        out: list[cst.BaseStatement] = []
        for statement in statements:
            if m.matches(statement, alias):
                assert isinstance(statement, cst.SimpleStatementLine)
                out.append(method.with_changes(leading_lines=statement.leading_lines))
            elif isinstance(statement, (cst.If, cst.Try)):
                out.append(_replace_in_blocks(statement, replace))
            else:
                out.append(statement)
        return out

    body = classdef.body
    if not isinstance(body, cst.IndentedBlock):
        return classdef
    return classdef.with_changes(body=body.with_changes(body=replace(body.body)))


def _replace_in_blocks(
    statement: cst.If | cst.Try, replace: Callable[[Sequence[cst.BaseStatement]], list[cst.BaseStatement]]
) -> cst.BaseStatement:
    """``statement`` with ``replace`` applied to each of its indented blocks (an ``elif``
    chain, ``else``, handlers and ``finally`` included)."""

    def suite(block: cst.BaseSuite) -> cst.BaseSuite:
        return block.with_changes(body=replace(block.body)) if isinstance(block, cst.IndentedBlock) else block

    if isinstance(statement, cst.If):
        orelse = statement.orelse
        if isinstance(orelse, cst.If):
            orelse = _replace_in_blocks(orelse, replace)  # type: ignore[assignment]
        elif isinstance(orelse, cst.Else):
            orelse = orelse.with_changes(body=suite(orelse.body))
        return statement.with_changes(body=suite(statement.body), orelse=orelse)
    handlers = [h.with_changes(body=suite(h.body)) for h in statement.handlers]
    orelse_try = statement.orelse.with_changes(body=suite(statement.orelse.body)) if statement.orelse else None
    final = statement.finalbody.with_changes(body=suite(statement.finalbody.body)) if statement.finalbody else None
    return statement.with_changes(body=suite(statement.body), handlers=handlers, orelse=orelse_try, finalbody=final)


class _NoneInfoFiller(OwnBodyOnly, cst.CSTTransformer):
    """``info = None`` -> ``info = {}`` for the planned locals (``ClassPlan.none_infos``): each
    is only ever None and only returned as step's info, which Gymnasium asserts is a dict."""

    def __init__(self, names: set[str]) -> None:
        self.names = names

    def leave_Assign(self, original_node: cst.Assign, updated_node: cst.Assign) -> cst.Assign:
        target = updated_node.targets[0].target
        if len(updated_node.targets) == 1 and isinstance(target, cst.Name) and target.value in self.names:
            if m.matches(updated_node.value, m.Name("None")):
                return updated_node.with_changes(value=cst.Dict([]))
        return updated_node
