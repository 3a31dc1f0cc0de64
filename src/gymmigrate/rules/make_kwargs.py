"""Keywords that ``make`` and the wrapper constructors no longer accept (GM305, GM801).

Gymnasium 1.x ``make(id, max_episode_steps=None, disable_env_checker=None, **kwargs)``
forwards any keyword it does not know to the environment's constructor, so a removed
keyword fails far from its cause: ``TypeError: CartPoleEnv.__init__() got an
unexpected keyword argument 'autoreset'`` (``make`` docstring: "v1.0.0 - `autoreset`
and `apply_api_compatibility` was removed").

* GM305 ``new_step_api=`` (gym 0.25 only; removed in 0.26, where the five-value step
  became the only API) is deleted from ``make``, ``vector.make``, ``SyncVectorEnv`` /
  ``AsyncVectorEnv``, every ``gym.wrappers`` constructor and ``super().__init__`` in Gym
  wrapper subclasses. GM305 owns this keyword everywhere, ``make`` included; the
  four-value unpacks it governed are GM301's job.
* GM801 the other removed ``make`` keywords: ``autoreset=True`` becomes
  ``gym.wrappers.Autoreset(gym.make(...))`` (review: since 1.0 it resets on the step
  *after* the episode ends and there is no ``final_observation``);
  ``apply_api_compatibility=`` is deleted (review: the env must be a Gymnasium env, or
  go through Shimmy's ``GymV21Environment-v0``); ``return_info=`` (never a ``make``
  keyword) is deleted. ``disable_env_checker``, ``max_episode_steps`` and
  ``render_mode`` are still valid and stay.
"""

from __future__ import annotations

import ast
from collections.abc import Sequence

from gymmigrate.edits.lazy import cst
from gymmigrate.facts import ModuleFacts
from gymmigrate.facts import names as N
from gymmigrate.facts.env_classes import is_super_method_call
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily

RULES = (
    Rule(
        "GM305",
        "new_step_api keyword",
        FixKind.AUTO,
        "`new_step_api=` is deleted from `make`, vector constructors and wrapper constructors.",
    ),
    Rule(
        "GM801",
        "removed make keywords",
        FixKind.ASSIST,
        "`autoreset=True` becomes an `Autoreset` wrapper; `apply_api_compatibility=` and `return_info=` are deleted.",
    ),
)

NEW_STEP_API = "new_step_api"
REMOVED_MAKE_KEYWORDS = ("autoreset", "apply_api_compatibility", "return_info")
# Callables (under gym/gymnasium) that accepted ``new_step_api`` in gym 0.25.
_VECTOR_CONSTRUCTORS = frozenset({"vector.make", "make_vec"}) | N.GYM_VEC_FACTORIES


class MakeKeywords(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        return any(keyword in facts.text for keyword in (NEW_STEP_API, *REMOVED_MAKE_KEYWORDS))

    def decide(self) -> None:
        for calls in (*self.facts.calls_by_name.values(), *self.facts.attribute_calls.values()):
            for call in calls:
                if any(kw.arg in (NEW_STEP_API, *REMOVED_MAKE_KEYWORDS) for kw in call.keywords):
                    self._decide_call(call)

    def _decide_call(self, call: ast.Call) -> None:
        callee = self._callee(call)
        if callee is None:
            return
        drop: set[str] = set()
        wrap_autoreset = False
        for kw in call.keywords:
            if kw.arg == NEW_STEP_API:
                drop.add(kw.arg)
                self.report(kw, "GM305", f"`{NEW_STEP_API}=` was removed in gym 0.26: step always returns five values")
            elif callee == "make" and kw.arg in REMOVED_MAKE_KEYWORDS:
                handled, wrap = self._removed_make_keyword(kw, kw.arg)
                if handled:
                    drop.add(kw.arg)
                    wrap_autoreset = wrap_autoreset or wrap
        if not drop:
            return
        wrapper = self._autoreset_wrapper(call) if wrap_autoreset else None

        def build(node: cst.Call) -> cst.BaseExpression:
            node = node.with_changes(args=_without_keywords(node.args, drop))
            if wrapper is None:
                return node
            return cst.Call(
                func=cst.parse_expression(wrapper),
                args=[cst.Arg(value=node.with_changes(lpar=(), rpar=()))],
                lpar=node.lpar,
                rpar=node.rpar,
            )

        self.plan.replace(call, build)

    # -- which calls ----------------------------------------------------------------------

    def _callee(self, call: ast.Call) -> str | None:
        """``make`` for env factories, ``other`` for vector/wrapper constructors, else None."""
        for qualified in self.facts.qualified_names(call.func):
            rest = N.strip_gym_prefix(qualified)
            if rest is None:
                continue
            if rest in N.GYM_ENV_FACTORIES:
                return "make"
            if rest in _VECTOR_CONSTRUCTORS or rest.startswith(("wrappers.", "vector.")):
                return "other"
        func = call.func
        if isinstance(func, ast.Attribute) and func.attr == "make" and isinstance(func.value, ast.Call):
            if any(N.strip_gym_prefix(q) in ("spec", "envs.spec") for q in self.facts.qualified_names(func.value.func)):
                return "make"  # gym.spec(id).make(...)
        if self._is_wrapper_super_init(call):
            return "other"
        return None

    def _is_wrapper_super_init(self, call: ast.Call) -> bool:
        """``super().__init__(env, new_step_api=...)`` inside a Gym wrapper subclass."""
        if not is_super_method_call(call, "__init__"):
            return False
        classdef = self.facts.enclosing_class(call)
        return classdef is not None and self.receivers.is_gym_wrapper_class(classdef)

    # -- GM801 ------------------------------------------------------------------------------

    def _removed_make_keyword(self, kw: ast.keyword, keyword: str) -> tuple[bool, bool]:
        """Report one removed ``make`` keyword; (delete it?, wrap the call in Autoreset?)."""
        value = kw.value.value if isinstance(kw.value, ast.Constant) and isinstance(kw.value.value, bool) else None
        if keyword == "return_info":
            self.report(kw, "GM801", "`return_info=` is not a `make` keyword (the env constructor rejects it): deleted", FixKind.AUTO)
            return True, False
        if keyword == "apply_api_compatibility":
            if value is False:
                self.report(kw, "GM801", "`apply_api_compatibility=False` was the default and is gone: deleted", FixKind.AUTO)
            else:
                self.report(
                    kw,
                    "GM801",
                    "`apply_api_compatibility=` was removed in Gymnasium 1.0: deleted; the env must follow the "
                    'Gymnasium API, or create a legacy one with gym.make("GymV21Environment-v0", env_id=...) from Shimmy',
                )
            return True, False
        if value is False:
            self.report(kw, "GM801", "`autoreset=False` was the default and is gone: deleted", FixKind.AUTO)
            return True, False
        if value is True:
            self.report(
                kw,
                "GM801",
                "`autoreset=True` became the `Autoreset` wrapper; since Gymnasium 1.0 it resets on the step after "
                "the episode ends (that step returns the reset obs with reward 0) and sets no final_observation: review",
            )
            return True, True
        self.report(
            kw,
            "GM801",
            "`autoreset=` was removed in Gymnasium 1.0 and its value is not a constant: wrap the env in "
            "gymnasium.wrappers.Autoreset where it was true",
            FixKind.FLAG,
        )
        return False, False

    def _autoreset_wrapper(self, call: ast.Call) -> str:
        """The wrapper's name through the user's alias (``gym.wrappers.Autoreset``), or an import."""
        func = call.func
        if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name):
            return f"{func.value.id}.wrappers.Autoreset"
        return self.plan.ensure_import("gymnasium.wrappers", "Autoreset")


def _without_keywords(args: Sequence[cst.Arg], keywords: set[str]) -> list[cst.Arg]:
    """Drop keyword arguments, keeping the user's commas and line breaks for the rest."""
    kept: list[cst.Arg] = []
    for arg in args:
        if arg.keyword is not None and arg.keyword.value in keywords:
            if kept and arg is args[-1]:
                # The previous argument takes over the dropped one's trailing comma (or none).
                kept[-1] = kept[-1].with_changes(comma=arg.comma, whitespace_after_arg=arg.whitespace_after_arg)
            continue
        kept.append(arg)
    return kept
