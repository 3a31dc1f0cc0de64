"""Planning the sites make by make: the mode each make ends with (its own, another
family's, or the one its sites agree on), the makes that cannot take one (two modes,
``**kwargs``, a registered class without ``render_mode``), human renders that run on a
condition (``render_schedule.py``), and each site's finding and edit.

What the made env's uses say (where it is stepped, whether its loops render) is read in
``env_uses.py``; the renders of envs made out of this file's reach are reported from
``untraced.py``; both are mixed in here."""

from __future__ import annotations

import ast
from collections import defaultdict

from gymmigrate.facts.class_shapes import wrapped_env_renders
from gymmigrate.facts.decisions import Action, Decision
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.made_holders import is_make
from gymmigrate.facts.module import keyword, string_value
from gymmigrate.facts.render_modes import steps_draw_on_own_flags
from gymmigrate.facts.summaries.defs import registered_ids
from gymmigrate.facts.version_checks import reads_version
from gymmigrate.findings import (
    FixKind,
    Tier,
    gym_only_question,
    recorder_mode_question,
)
from gymmigrate.rules.env_ids.catalog import known_elsewhere
from gymmigrate.rules.render_calls import without_mode_argument
from gymmigrate.rules.render_schedule import never_run_guard, render_condition, schedule
from gymmigrate.rules.rendering.common import (
    HUMAN,
    LEGACY_SINGLE_FRAME,
    RGB_ARRAY,
    RenderSite,
    forwards_to_first_argument,
)
from gymmigrate.rules.rendering.env_uses import EnvUses
from gymmigrate.rules.rendering.untraced import UntracedEnvs


def _literal_mode(make: ast.Call) -> str | None:
    existing = keyword(make, "render_mode")
    return string_value(existing.value) if existing is not None else None


class SitePlanning(EnvUses, UntracedEnvs):
    """The sites planned by make (mixed into the family)."""

    def _plan_sites(self, sites: list[RenderSite]) -> None:
        by_make: dict[int, list[RenderSite]] = defaultdict(list)
        makes: dict[int, ast.Call] = {}
        for site in sites:
            if site.creation.found:
                for make in site.creation.calls:
                    by_make[id(make)].append(site)
                    makes[id(make)] = make
        # The mode each make will have: its own render_mode, the one another family gives
        # it, or the one its sites agree on.
        final_mode: dict[int, str | None] = {}
        blocked: dict[int, str] = {}  # id(make) -> why its sites cannot be rewritten
        kept_default: dict[int, str] = {}  # id(make) -> the class whose render() keeps its default mode
        for key, make_sites in by_make.items():
            make = makes[key]
            existing = keyword(make, "render_mode")
            if existing is not None:
                value = string_value(existing.value)
                final_mode[key] = RGB_ARRAY if value == LEGACY_SINGLE_FRAME else value
                if value is None:
                    blocked[key] = "its gym.make passes a render_mode that is not a literal"
                continue
            if key in self._noted:
                final_mode[key] = self._noted[key]
                continue
            if any(k.arg is None for k in make.keywords):
                final_mode[key] = None
                blocked[key] = "its gym.make passes **kwargs that may already hold render_mode: set it there by hand"
                continue
            unready = self._registered_without_render_mode(make)
            if unready is not None and self._bare_renders_keep_default(make, make_sites):
                # Gymnasium's wrappers call render() with no arguments, and the class's own
                # render() still takes them with its default mode: these renders draw as they
                # did. Porting that render to render_mode is the class's design question,
                # not these calls'.
                final_mode[key] = None
                kept_default[key] = unready
                continue
            if unready is not None:
                final_mode[key] = None
                blocked[key] = (
                    f"the id may name {unready}, registered in this run, whose __init__ takes no render_mode "
                    "(make would raise TypeError): give it a render_mode parameter first"
                )
                continue
            if self._frames_over_bare_renders(make_sites):
                idle = {id(s.node): self._recorder_idle(s.node, make, make_sites) for s in make_sites if s.code == "GM407"}
                if all(idle.values()):
                    # Every recorder is switched off as the code stands: the renders that run
                    # decide the make, as if the recorders were not there.
                    self._idle_recorders.update((node, str(why)) for node, why in idle.items())
                    make_sites = [s for s in make_sites if s.code != "GM407"]
            wanted = {s.mode for s in make_sites}
            # An env whose class draws in render() alone draws only where render() is called, in
            # human mode too: its renders keep their schedule by themselves.
            if (
                wanted == {HUMAN}
                and not any(s.variable for s in make_sites)
                and not self._draws_only_in_render([key], makes)
                and self._keeps_schedule(make, make_sites, final_mode, blocked)
            ):
                continue
            if len(wanted) == 1:
                mode = final_mode[key] = wanted.pop()
                variable = any(s.variable for s in make_sites)
                self._add_mode(make, mode, "" if variable else self._quote_style(make, make_sites))
            elif self._frames_over_bare_renders(make_sites):
                recorder = next(s for s in make_sites if s.code == "GM407")
                final_mode[key] = RGB_ARRAY
                self._framed[key] = (recorder.consumer, recorder.node.lineno)
                self._add_mode(make, RGB_ARRAY, self._quote_style(make, make_sites))
            else:
                final_mode[key] = None
                modes = " and ".join(sorted(f'"{m}"' for m in wanted))
                blocked[key] = (
                    f"the env is rendered in {modes}, but a Gymnasium env has one render_mode: "
                    "create two envs (e.g. a training env and an eval env with its own render_mode)"
                )
        self._makes_by_id = makes
        self._rendered_nodes = {id(site.node) for site in sites}
        self._kept_default = kept_default
        for site in sites:
            self._plan_site(site, makes, final_mode, blocked)

    def _bare_renders_keep_default(self, make: ast.Call, sites: list[RenderSite]) -> bool:
        """Every render of the make is a bare ``render()``, and its literal id names a class of
        the run that takes no render_mode but whose render() gives ``mode`` a default."""
        project = self.receivers.project
        first = make.args[0] if make.args else None
        return (
            project is not None
            and isinstance(first, ast.Constant)
            and project.bare_render_keeps_default(string_value(first))
            and all(s.code == "GM402" and not s.node.args and not s.node.keywords for s in sites)
        )

    @staticmethod
    def _frames_over_bare_renders(sites: list[RenderSite]) -> bool:
        """A recorder (GM407) and bare legacy renders (GM402, "human") on one make, every other
        site asking a mode the recorders take: the make gets "rgb_array". The recorder raises
        without a frame mode, while a bare render() is Gymnasium's API in any mode; and once
        migrated nothing in the code says it meant "human" any more, so a run over the output
        gives the recorder its mode: this run must give it too, or a second run changes the file.
        A render that passes "human" itself keeps the conflict (it stays, and asks again); a
        recorder that never runs as the code stands leaves the make to the renders
        (``_recorder_idle``)."""
        recorders = [s for s in sites if s.code == "GM407"]
        if not recorders or any(s.variable for s in sites):
            return False
        bare = [s for s in sites if s.code == "GM402"]
        rest = [s for s in sites if s.code not in ("GM402", "GM407")]
        return (
            bool(bare)
            and all(s.mode == HUMAN for s in bare)
            and all(RGB_ARRAY in s.accepted for s in recorders)
            and all(s.mode == RGB_ARRAY for s in rest)
        )

    def _keeps_schedule(
        self, make: ast.Call, sites: list[RenderSite], final_mode: dict[int, str | None], blocked: dict[int, str]
    ) -> bool:
        """Human renders that run only on a condition (render_schedule.py): the condition
        moves to the make when it is fixed at creation, else the sites are reported.
        False when a render runs on every pass (human mode then draws as before)."""
        key = id(make)
        trained = self._used_where_nothing_renders(make, sites)
        if trained is not None:
            # Train, then watch: human mode would draw every training step too.
            final_mode[key] = None
            self._unscheduled[key] = f"the watch loop runs (the env is also {trained}, where nothing renders)"
            return True
        home = self._stepping_function(make, [site.node for site in sites])
        how, condition = schedule(self.facts, [site.node for site in sites], make, home)
        if how == "always":
            mixed = self._mixed_schedules(make, sites, home)
            if mixed is not None:
                # A demo loop that draws every step and a training loop that draws only
                # once the agent is good: human mode would draw every training step too.
                final_mode[key] = None
                self._unscheduled[key] = mixed
                return True
        if how == "always" or condition is None:  # the condition is None only "always"
            return False
        off = [self._switched_off_by(site.node, make, home) for site in sites]
        if all(off):
            # ``render = False`` at the top of the script: nothing draws as the code stands,
            # and nothing needs deciding until someone turns it on.
            final_mode[key] = None
            self._switched_off[key] = str(off[0])
            return True
        if how == "fixed" and all(self._version_fallback_flag(make, site.node) == condition for site in sites):
            # ``if <gym version test> and show: make(..., render_mode="human") else: make(...)``:
            # the human make already serves the renders on Gymnasium (the site says so).
            final_mode[key] = None
            self._unscheduled[key] = condition
            return True
        if how == "fixed":
            quote = self._quote_style(make, sites)
            final_mode[key] = HUMAN
            self._added[key] = HUMAN
            func = self.facts.segment(make.func)
            self._give_mode(make, func, f"{quote}{HUMAN}{quote} if {condition} else None")
            self._scheduled[key] = condition
            return True
        final_mode[key] = None
        self._unscheduled[key] = condition
        return True

    def _recorder_idle(self, recorder: ast.Call, make: ast.Call, sites: list[RenderSite]) -> str | None:
        """Why ``recorder`` never runs as the code stands (``if record:`` with ``record = False``
        bound once, or a flag every call of the def passes False), else None. Its make then
        serves the renders that run; the recorder would need "rgb_array" if it were turned on,
        and a second run finds the same switch, so the choice stays."""
        home = self._stepping_function(make, [site.node for site in sites])
        switch = self._switch(recorder, make, home)
        if switch is not None:
            name, value, line, _ = switch
            return f"`{name}` is bound once, to {value!r}, at line {line}"
        flag = never_run_guard(self.facts, recorder)
        function = self.facts.enclosing_function(recorder)
        if flag is not None and isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            return f"every call of `{function.name}` passes `{flag.id}` False"
        return None

    def _switched_off_by(self, render: ast.Call, make: ast.Call, home: ast.AST | None) -> str | None:
        """``if worker == 0 and render:`` with ``render = False`` bound once at module level:
        the render never runs. The constant, as ``render (False, line 3)``, or None."""
        switch = self._switch(render, make, home)
        if switch is None:
            return None
        name, value, line, test = switch
        return (
            f"`{name}` is bound once, to {value!r}, at line {line}; if you turn it on, pass "
            f'render_mode="human" if {self.facts.segment(test)} else None to {self._call_summary(make)}'
        )

    def _switch(self, call: ast.Call, make: ast.Call, home: ast.AST | None) -> tuple[str, object, int, ast.AST] | None:
        """A test between ``make`` and ``call`` that reads a name bound once, at module level, to
        False, None or 0, so ``call`` never runs: (the name, its value, the line binding it, the
        test), or None."""
        for test, negated in render_condition(self.facts, call, make, home):
            if negated:
                continue
            operands = test.values if isinstance(test, ast.BoolOp) and isinstance(test.op, ast.And) else [test]
            for operand in operands:
                if not isinstance(operand, ast.Name):
                    continue
                bindings = self.facts.bindings_of(operand)
                if len(bindings) != 1 or not isinstance(bindings[0], ast.Name) or self.facts.enclosing_function(bindings[0]) is not None:
                    continue
                statement = self.facts.parent(bindings[0])
                if (
                    isinstance(statement, ast.Assign)
                    and statement.targets == [bindings[0]]
                    and isinstance(statement.value, ast.Constant)
                    and statement.value.value in (False, None, 0)
                    and not isinstance(statement.value.value, float)
                ):
                    return operand.id, statement.value.value, statement.lineno, test
        return None

    def _mixed_schedules(self, make: ast.Call, sites: list[RenderSite], home: ast.AST | None) -> str | None:
        """The renders of one env on different schedules, some on every pass and some under
        a condition: ``"<condition> at line N (the render at line M runs on every pass)"``,
        or None."""
        conditional = [(site, guards) for site in sites if (guards := render_condition(self.facts, site.node, make, home))]
        always = [site for site in sites if not render_condition(self.facts, site.node, make, home)]
        if not conditional or not always:
            return None
        steps = self._steps_of_make(make) or []
        drawn = {id(site.node) for site in always}
        if steps and all(self._loop_renders(call, drawn) for call in steps):
            # Every step of the env is drawn by a render that runs on every pass (a render
            # when done only redraws the last frame): human mode draws as the code did.
            return None
        site, guards = conditional[0]
        _, text = schedule(self.facts, [site.node], make, home)
        return f"{text} at line {site.node.lineno} (the render at line {always[0].node.lineno} runs on every pass)"

    def _bound_in_def(self, name: ast.Name, call: ast.Call) -> bool:
        """Every binding of ``name`` is in the def around ``call`` (a parameter, a local)."""
        function = self.facts.enclosing_function(call)
        bindings = self.facts.bindings_of(name)
        return function is not None and bool(bindings) and all(
            (self.facts.parent(self.facts.parent(b)) if isinstance(b, ast.arg) else self.facts.enclosing_function(b)) is function
            for b in bindings
        )

    def _plan_site(
        self,
        site: RenderSite,
        makes: dict[int, ast.Call],
        final_mode: dict[int, str | None],
        blocked: dict[int, str],
    ) -> None:
        code, call = site.code, site.node
        target = f"render_mode={site.mode}" if site.variable else f'render_mode="{site.mode}"'
        if not site.creation.found and code == "GM402" and (
            self._rendered_by_wrapper(site) or self._settled_elsewhere(site) or self._report_made_elsewhere(site)
        ):
            return
        if not site.creation.found and self._moved_to_handed_make(site):
            return
        if not site.creation.found:
            func = call.func
            library = self._gym_only_library(func.value) if isinstance(func, ast.Attribute) else None
            if library is not None and isinstance(func, ast.Attribute):
                # an env of a library still on gym (MPE's MultiAgentEnv): its render(mode) is
                # that library's own API and stays; the library's port (GM107) decides it
                self.report(
                    call,
                    code,
                    f"not rewritten: `{self.facts.segment(func.value)}` is an env built on {library}, a library still on gym "
                    "(GM107): its render keeps its own signature until that library is ported",
                    FixKind.FLAG,
                    tier=Tier.NOTE,
                    question=gym_only_question(library),
                )
                return
            where = site.creation.gap or "no gym.make was found"
            # On an env the run does not show to be a Gym env, where it is made matters only if
            # it is one: the receiver's question ("is it a Gym env?"), asked by its reset and
            # step too, decides this render as well (one decision per receiver). A name bound
            # outside the def (a module's env drawn from several callbacks) keeps the render
            # question of its bindings, which is already one for all of them.
            receiver = func.value if site.decision is Action.REPORT and isinstance(func, ast.Attribute) else None
            if isinstance(receiver, ast.Name) and not self._bound_in_def(receiver, call):
                receiver = None
            asked = self.receiver_question(receiver, Decision(site.decision, where)) if receiver is not None else None
            self.report(
                call,
                code,
                f"{site.consumer} needs the env created with {target}, but its creation site was not found "
                f"({where}); add it there by hand",
                FixKind.FLAG,
                question=asked
                or self._untraced_question(site, where)
                or (recorder_mode_question(call.lineno, call.col_offset) if code == "GM407" else None),
            )
            return
        idle = self._idle_recorders.get(id(call))
        if idle is not None:
            self._report_idle_recorder(site, idle)
            return
        keys = [id(m) for m in site.creation.calls]
        # The render calls of one env ask one question (which mode it is made with).
        def question(outcome: str) -> tuple[object, ...]:
            return ("render", code, tuple(sorted(keys)), outcome)

        if code == "GM402" and all(keyword(makes[k], "render_mode") is not None for k in keys):
            return  # the make already chose a mode: this bare render() is Gymnasium's API
        off = [self._switched_off[k] for k in keys if k in self._switched_off]
        if off:
            # nothing changes (FLAG), and nothing needs deciding now (a note)
            self.report(call, code, f"not rewritten: this render never runs as the code stands ({off[0]})", FixKind.FLAG, tier=Tier.NOTE)
            return
        unscheduled = [self._unscheduled[k] for k in keys if k in self._unscheduled]
        human = next((makes[k] for k in keys if _literal_mode(makes[k]) == HUMAN), None)
        if unscheduled and code == "GM402" and human is not None:
            fallback = [makes[k] for k in keys if keyword(makes[k], "render_mode") is None]
            flag = next((f for f in map(lambda m: self._version_fallback_flag(m, call), fallback) if f), None)
            if flag is not None and all(self._version_fallback_flag(m, call) == flag for m in fallback):
                # ``if <gym version test> and render: make(..., render_mode="human") else: make(...)``
                # with the render under ``if render:``: the code already picks the human make
                # whenever it draws on Gymnasium; the other make is the old gym's fallback.
                self.report(
                    call,
                    code,
                    f'not rewritten: render() runs only when {flag}, and then the env comes from '
                    f'{self._call_summary(human)}, which already passes render_mode="human" (the make without it is '
                    "reached with it only when the gym version test fails)",
                    FixKind.FLAG,
                    tier=Tier.NOTE,
                )
                return
        if unscheduled:
            choice = (
                f"render() runs only when {unscheduled[0]}, but render_mode=\"human\" would draw every step: keep "
                'the schedule by creating the env with render_mode="rgb_array" and showing the frame render() '
                'returns here, or choose render_mode="human" if drawing every step is intended'
            )
            if code == "GM401":  # render(mode=...) raises TypeError in Gymnasium: the mode goes
                self.plan.replace(call, without_mode_argument)
                self._mode_dropped.add(id(call))
                self.report(call, code, f"mode dropped, no render_mode added (it draws nothing until you choose): {choice}")
            else:
                self.report(call, code, f"not rewritten: {choice}", FixKind.FLAG, question=question("unscheduled"))
            return
        kept = [self._kept_default[k] for k in keys if k in self._kept_default]
        if kept and len(kept) == len(keys):
            self.report(
                call,
                code,
                f"not rewritten: the env is {kept[0]} (registered in this run), whose render() keeps its default mode; "
                "Gymnasium's wrappers call render() with no arguments, so this bare render() still reaches that default",
                FixKind.FLAG,
                tier=Tier.NOTE,
            )
            return
        reasons = [blocked[k] for k in keys if k in blocked]
        if reasons:
            # the make's one question, whichever render or recorder meets it
            self.report(call, code, f"not rewritten: {reasons[0]}", FixKind.FLAG, question=("render", tuple(sorted(keys)), reasons[0]))
            return
        framed = [self._framed[k] for k in keys if k in self._framed]
        if code == "GM402" and framed:
            consumer, line = framed[0]
            where = " and ".join(self._call_summary(makes[k]) for k in keys if k in self._framed)
            self.report(
                call,
                code,
                f'not rewritten: legacy render() meant "human" (a window), but {consumer} at line {line} records only '
                f'an env made with render_mode="rgb_array", which {where} now gets: this render() returns a frame and '
                'draws nothing; to watch the env, make a second env with render_mode="human"',
                FixKind.FLAG,
                question=question("framed"),
            )
            return
        accepted = site.accepted or (site.mode,)
        conflicting = [final_mode[k] for k in keys if final_mode[k] not in accepted]
        if conflicting and code == "GM407" and len(keys) == 1:
            # A make that serves the renders (a run over this output finds it so): a recorder
            # that never runs asks nothing of it.
            idle = self._recorder_idle(call, makes[keys[0]], [site])
            if idle is not None:
                self._report_idle_recorder(site, idle)
                return
        if conflicting:
            self.report(
                call,
                code,
                f'not rewritten: the env is created with render_mode="{conflicting[0]}" but {site.consumer} needs '
                f'"{site.mode}"; create a separate env for it',
                FixKind.FLAG,
                question=question("conflict"),
            )
            return
        where = " and ".join(self._call_summary(makes[k]) for k in keys)
        added = any(k in self._added for k in keys)
        if site.legacy_spelling:
            self.report(call, "GM403", 'gym 0.25 "single_rgb_array" is "rgb_array" in Gymnasium')
        if code == "GM407":
            if added:
                self._claim_makes(keys)
                self.report(call, code, f"added {target} to {where} so {site.consumer} gets frames", tier=Tier.NOTE)
            return
        scheduled = [self._scheduled[k] for k in keys if k in self._scheduled]
        if scheduled:
            # Rendered in the same loop as every step of the env: it drew each step before,
            # and does now; only a render away from the steps (once an episode) is a question.
            per_step = all(self._steps_render(k) for k in keys)
            self._claim_makes(keys)
            self.report(
                call,
                code,
                f'render() ran only when {scheduled[0]}, which is known when the env is made: added render_mode="human" '
                f"if {scheduled[0]} else None to {where}; that env now draws every step inside step()/reset()"
                + (", as it drew every step here" if per_step else ""),
                tier=Tier.NOTE if per_step else None,
            )
            if code == "GM401":
                self.plan.replace(call, without_mode_argument)
                self._mode_dropped.add(id(call))
            return
        if code == "GM402":
            if added:
                # Rendered in the loop that steps the env: it drew each step before and
                # does now, so the line only explains the rewrite.
                per_step = all(self._steps_render(k) for k in keys)
                self._claim_makes(keys)
                if self._draws_only_in_render(keys, makes):
                    # the env's class draws in render() alone: human mode adds no drawing to
                    # step(), and the call draws as it did
                    self.report(
                        call,
                        code,
                        f'legacy render() meant "human": added {target} to {where}; the env\'s class draws only in '
                        "render() (its step() and reset() call none), so this call is still what draws",
                        tier=Tier.NOTE,
                    )
                    return
                if self._steps_draw_on_own_flags(keys, makes):
                    # the env's class is built here and its step() draws only under flags of
                    # its own, never by render_mode: human mode adds no drawing to step()
                    self.report(
                        call,
                        code,
                        f'legacy render() meant "human": added {target} to {where}; the env\'s class does not draw by '
                        "render_mode in step() or reset() (only under conditions of its own), so this call is still what draws",
                        tier=Tier.NOTE,
                    )
                    return
                unknown = self._unknown_id(keys, makes)
                if unknown is not None:
                    # Nothing tells what the class behind the id draws, or where: no ground
                    # for calling the render redundant, and keeping it is right either way.
                    self.report(
                        call,
                        code,
                        f'legacy render() meant "human": added {target} to {where}; the id {unknown!r} names no env of '
                        "Gymnasium or of this run, so whether it draws inside step() is not known: keep this call",
                        tier=Tier.NOTE,
                    )
                    return
                self.report(
                    call,
                    code,
                    f'legacy render() meant "human": added {target} to {where}; a human-mode env '
                    "now draws every step inside step()/reset(), so this call is redundant (keep or remove it)",
                    tier=Tier.NOTE if per_step else None,
                )
            return
        self.plan.replace(call, without_mode_argument)
        self._mode_dropped.add(id(call))
        if self._legacy_025 and site.mode == RGB_ARRAY and not site.legacy_spelling:
            self.report(
                call,
                "GM403",
                'in gym 0.25 "rgb_array" returned a list of frames; if this code expects a list, use "rgb_array_list"',
                FixKind.FLAG,
            )
        if added:
            message = f"render mode moved to {where} ({target}); render() takes no arguments"
            inferred = (
                site.decision is Action.REWRITE_FOR_REVIEW or site.decision is Action.REPORT
            ) and not self._forwarded_from_make_in_scope(call, site)
            if inferred:
                message += "; the env's origin was inferred, check it"
            # A frame or text mode draws nothing by itself: the env renders when render() is
            # called, as before, so the move explains itself. "human" draws every step.
            # An env whose class draws in render() alone draws only when render() is called, in
            # human mode as in any: the call keeps drawing as it did.
            render_only = site.mode == HUMAN and not site.variable and self._draws_only_in_render(keys, makes)
            every_step = site.mode == HUMAN and not site.variable and not render_only and self._drawn_every_step(call, keys)
            if render_only:
                message += "; the env's class draws only in render() (its step() and reset() call none), so this call is still what draws"
            elif every_step:
                message += "; it drew every step here, as a human-mode env does inside step()"
            exact = not inferred and not site.variable and (site.mode != HUMAN or every_step or render_only)
            if site.variable:
                message += f'; the mode is read once per env now: where {site.mode} is "human", that env draws every step inside step()/reset()'
            self._claim_makes(keys)
            self.report(call, code, message, tier=Tier.NOTE if exact else None, question=question("moved"))
        else:
            self.report(call, code, f"{where} already has {target}; render() takes no arguments", FixKind.AUTO)

    def _report_idle_recorder(self, site: RenderSite, idle: str) -> None:
        self.report(
            site.node,
            site.code,
            f"not rewritten: this {site.consumer} never runs as the code stands ({idle}), so the renders that run "
            'decide how the env is made; if you turn it on, it needs the env made with render_mode="rgb_array"',
            FixKind.FLAG,
            tier=Tier.NOTE,
        )

    def _draws_only_in_render(self, keys: list[int], makes: dict[int, ast.Call]) -> bool:
        """Every make of ``keys`` builds, by a literal id the run registers, an env class of
        the run whose drawing is its render() alone (``ProjectView.draws_only_in_render``)."""
        project = self.receivers.project
        if project is None:
            return False
        for key in keys:
            first = makes[key].args[0] if makes[key].args else keyword(makes[key], "id")
            env_id = string_value(first) if first is not None else None
            if env_id is None or not project.draws_only_in_render(env_id):
                return False
        return True

    def _unknown_id(self, keys: list[int], makes: dict[int, ast.Call]) -> str | None:
        """The literal id of a ``gym.make`` of ``keys`` that neither Gymnasium (nor a package
        registered with it) nor the run registers (an id the run may register through a
        registration it does not spell as a literal counts as registered): the class it
        builds, and so whether human mode makes its step() draw, is not known."""
        project = self.receivers.project
        for key in keys:
            make = makes[key]
            if not is_make(self.facts, make):
                continue
            first = make.args[0] if make.args else keyword(make, "id")
            env_id = string_value(first) if first is not None else None
            if env_id is None or known_elsewhere(env_id):
                continue
            if project is not None:
                if project.may_register(env_id) or project.facts.registers_from_data:
                    continue
            else:
                here = registered_ids(self.facts)
                if env_id in here or None in here:
                    continue
            return env_id
        return None

    def _steps_draw_on_own_flags(self, keys: list[int], makes: dict[int, ast.Call]) -> bool:
        """Every make of ``keys`` calls the constructor of an env class of the run (this
        module's or imported) whose step() and reset() draw only under conditions of its own
        (``render_modes.steps_draw_on_own_flags``)."""
        project = self.receivers.project
        for key in keys:
            func = makes[key].func
            local = self.receivers.local_class(func)
            if local is not None:
                if not steps_draw_on_own_flags(self.facts, self.receivers, local):
                    return False
            elif project is None or not any(project.steps_draw_on_own_flags(q) for q in self.facts.qualified_names(func)):
                return False
        return True

    def _forwarded_from_make_in_scope(self, call: ast.Call, site: RenderSite) -> bool:
        """``env = gym.make(...)``; ``env = Adapter(env)``; ``env.render(mode)`` in one scope,
        each adapter a class of this module with no render() of its own whose ``__getattr__``
        forwards to the env its constructor stores: the render reached is the make's env's, a
        fact and not an inference (no receiver question to check)."""
        if len(site.creation.calls) != 1 or not site.creation.complete or not isinstance(call.func, ast.Attribute):
            return False
        make = site.creation.calls[0]
        scope = self.facts.enclosing_function(call)
        if self.facts.enclosing_function(make) is not scope:
            return False
        expr: ast.expr = call.func.value
        for _ in range(_MAX_ADAPTERS + 1):
            if not isinstance(expr, ast.Name):
                return False
            bindings = Flow.of(self.facts).reaching(expr)
            statement = self.facts.parent(bindings[0]) if bindings is not None and len(bindings) == 1 else None
            if not (isinstance(statement, ast.Assign) and statement.targets == bindings):
                return False
            if self.facts.enclosing_function(statement) is not scope:
                return False
            value = statement.value
            if value is make:
                return True
            if not (isinstance(value, ast.Call) and len(value.args) == 1 and not value.keywords):
                return False
            classdef = self.receivers.local_class(value.func)
            if classdef is None or not forwards_to_first_argument(classdef):
                return False
            expr = value.args[0]
        return False

    def _version_fallback_flag(self, make: ast.Call, render: ast.Call) -> str | None:
        """``else: env = make(...)`` of an ``if`` whose test is ``<version test> and flag``,
        where ``flag`` (one binding) also guards ``render`` and is not rebound in between:
        the flag's name, else None. A version test reads ``gym.__version__`` or calls a
        function named for the version (``is_gym_version_ge("0.26.0")``)."""
        statement = self.facts.statement_of(make)
        branch = self.facts.parent(statement)
        if not (isinstance(branch, ast.If) and statement in branch.orelse):
            return None
        test = branch.test
        if not (isinstance(test, ast.BoolOp) and isinstance(test.op, ast.And)):
            return None
        names = [v for v in test.values if isinstance(v, ast.Name)]
        if not any(reads_version(v, self.facts, any_module=True) for v in test.values):
            return None
        guards = [g for g, negated in render_condition(self.facts, render, make) if not negated]
        for name in names:
            bindings = self.facts.bindings_of(name)
            if len(bindings) != 1:
                continue
            if any(isinstance(g, ast.Name) and g.id == name.id and self.facts.bindings_of(g) == bindings for g in guards):
                return name.id
        return None

    def _rendering_wrappers(self) -> list[tuple[str, list[str], ast.Call, ast.Call]]:
        """``env = Show(gym.make(id))`` with a Gym wrapper whose reset/step call
        ``self.env.render(...)`` (of this file, or of another module of the run): (the
        wrapper's name, those methods or [] when defined elsewhere, the build, the make
        without a render_mode)."""
        found: list[tuple[str, list[str], ast.Call, ast.Call]] = []
        self._wraps_untraced: set[int] = set()  # wrapper classes also built on envs not traced to a make
        self._local_wrappers: set[int] = set()
        project = self.receivers.project
        builds: list[tuple[str, list[str], ast.Call, ast.ClassDef | None]] = []
        for classdef in self.facts.all_classes:
            if not self.receivers.is_gym_wrapper_class(classdef):
                continue
            methods = wrapped_env_renders(self.facts, classdef)
            if not methods:
                continue
            self._local_wrappers.add(id(classdef))
            if project is not None and project.built_elsewhere(classdef.name):
                self._wraps_untraced.add(id(classdef))  # other modules wrap their envs in it too
            builds += [
                (classdef.name, methods, build, classdef)
                for build in self.facts.calls_by_name.get(classdef.name, ())
                if self.receivers.local_class(build.func) is classdef
            ]
        if project is not None:
            for call in (*(c for calls in self.facts.calls_by_name.values() for c in calls), *(c for calls in self.facts.attribute_calls.values() for c in calls)):
                if self.receivers.local_class(call.func) is None and any(project.renders_wrapped_env(q) for q in self.facts.qualified_names(call.func)):
                    builds.append((self.facts.segment(call.func), [], call, None))
        for name, methods, build, wrapper in builds:
            wrapped = build.args[0] if build.args else next((k.value for k in build.keywords if k.arg == "env"), None)
            creation = self.finder.find(wrapped) if wrapped is not None and not isinstance(wrapped, ast.Starred) else None
            if creation is None or not creation.found:
                if wrapper is not None:
                    self._wraps_untraced.add(id(wrapper))
                continue
            for make in creation.calls:
                if self._is_gym_make(make) and keyword(make, "render_mode") is None and not any(k.arg is None for k in make.keywords):
                    found.append((name, methods, build, make))
        return found

    def _report_rendering_wrappers(self) -> None:
        """Legacy render() in a wrapper's reset/step drew ("human" by default) each time, and
        an env made without a render_mode draws nothing now: the make is reported. A render
        there that passes arguments is reported where it is too (GM401: they must go)."""
        for name, methods, build, make in self._wrapped:
            if id(make) in self._added or keyword(make, "render_mode") is not None:
                continue
            if methods:
                calls = " and ".join(f"{m}()" for m in methods)
                how = f"whose {calls} call{'s' if len(methods) == 1 else ''} `self.env.render(...)`"
            else:
                how = "whose reset/step call `self.env.render(...)` (another module of this run)"
            self.report(
                make,
                "GM402",
                f"the env made here is rendered by `{name}` (line {build.lineno}), {how}: legacy render() drew "
                '("human" unless told otherwise) each time, and an env made without a render_mode draws nothing '
                'now: pass the mode it renders in (render_mode="human" draws every step) to this gym.make',
                FixKind.FLAG,
                question=("render-wrapper", id(make)),
            )

    def _rendered_by_wrapper(self, site: RenderSite) -> bool:
        """A bare ``self.env.render()`` in a wrapper built on makes of this file: the mode
        those makes need is its one question, asked at them (``_report_rendering_wrappers``)."""
        call = site.node
        if call.args or call.keywords:
            return False
        classdef = self.facts.enclosing_class(call)
        if classdef is None or id(classdef) not in self._local_wrappers or id(classdef) in self._wraps_untraced:
            return False
        return any(build.func is not None and self.receivers.local_class(build.func) is classdef for _, _, build, _ in self._wrapped)


# Adapters followed from a render back to the make (``Outer(Adapter(env))``).
_MAX_ADAPTERS = 3
