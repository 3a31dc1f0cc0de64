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

import libcst as cst
from libcst.codemod.visitors import AddImportsVisitor
from libcst.helpers import get_full_name_for_node
from libcst.metadata import ParentNodeProvider, PositionProvider, QualifiedNameProvider, ScopeProvider

from gymmigrate.analysis import names as N
from gymmigrate.analysis.receivers import ReceiverAnalysis
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileProfile, Rule, RulePass

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


class MakeKeywordsPass(RulePass):
    RULES = RULES
    ORDER = 30
    METADATA_DEPENDENCIES = (PositionProvider, ScopeProvider, ParentNodeProvider, QualifiedNameProvider)

    @classmethod
    def applies_to(cls, source: str, profile: FileProfile) -> bool:
        return any(keyword + "=" in source or keyword + " =" in source for keyword in (NEW_STEP_API, *REMOVED_MAKE_KEYWORDS))

    def visit_Module(self, node: cst.Module) -> None:
        self.analysis = ReceiverAnalysis(node, self.metadata)

    def leave_Call(self, original_node: cst.Call, updated_node: cst.Call) -> cst.BaseExpression:
        callee = self._callee(original_node)
        if callee is None:
            return updated_node
        drop: set[str] = set()
        wrap_autoreset = False
        for arg in original_node.args:
            keyword = arg.keyword.value if arg.keyword is not None else None
            if keyword == NEW_STEP_API:
                drop.add(keyword)
                self.report(arg, "GM305", f"`{NEW_STEP_API}=` was removed in gym 0.26: step always returns five values")
            elif callee == "make" and keyword in REMOVED_MAKE_KEYWORDS:
                handled, wrap = self._removed_make_keyword(arg, keyword)  # type: ignore[arg-type]
                if handled:
                    drop.add(keyword)  # type: ignore[arg-type]
                    wrap_autoreset = wrap_autoreset or wrap
        if not drop:
            return updated_node
        call = updated_node.with_changes(args=_without_keywords(updated_node.args, drop))
        return self._autoreset(call) if wrap_autoreset else call

    # -- which calls ----------------------------------------------------------------------

    def _callee(self, call: cst.Call) -> str | None:
        """``make`` for env factories, ``other`` for vector/wrapper constructors, else None."""
        for qualified in self.analysis.qualified_names(call.func):
            rest = N.strip_gym_prefix(qualified)
            if rest is None:
                continue
            if rest in N.GYM_ENV_FACTORIES:
                return "make"
            if rest in _VECTOR_CONSTRUCTORS or rest.startswith(("wrappers.", "vector.")):
                return "other"
        if isinstance(call.func, cst.Attribute) and call.func.attr.value == "make" and isinstance(call.func.value, cst.Call):
            if any(N.strip_gym_prefix(q) in ("spec", "envs.spec") for q in self.analysis.qualified_names(call.func.value.func)):
                return "make"  # gym.spec(id).make(...)
        if self._is_wrapper_super_init(call):
            return "other"
        return None

    def _is_wrapper_super_init(self, call: cst.Call) -> bool:
        """``super().__init__(env, new_step_api=...)`` inside a Gym wrapper subclass."""
        func = call.func
        if not (
            isinstance(func, cst.Attribute)
            and func.attr.value == "__init__"
            and isinstance(func.value, cst.Call)
            and get_full_name_for_node(func.value.func) == "super"
        ):
            return False
        classdef = self.analysis.enclosing(call, cst.ClassDef)
        return isinstance(classdef, cst.ClassDef) and self.analysis.is_gym_wrapper_class(classdef)

    # -- GM801 ------------------------------------------------------------------------------

    def _removed_make_keyword(self, arg: cst.Arg, keyword: str) -> tuple[bool, bool]:
        """Report one removed ``make`` keyword; (delete it?, wrap the call in Autoreset?)."""
        value = _constant(arg.value)
        if keyword == "return_info":
            self.report(arg, "GM801", "`return_info=` is not a `make` keyword (the env constructor rejects it): deleted", FixKind.AUTO)
            return True, False
        if keyword == "apply_api_compatibility":
            if value is False:
                self.report(arg, "GM801", "`apply_api_compatibility=False` was the default and is gone: deleted", FixKind.AUTO)
            else:
                self.report(
                    arg,
                    "GM801",
                    "`apply_api_compatibility=` was removed in Gymnasium 1.0: deleted; the env must follow the "
                    'Gymnasium API, or create a legacy one with gym.make("GymV21Environment-v0", env_id=...) from Shimmy',
                )
            return True, False
        if value is False:
            self.report(arg, "GM801", "`autoreset=False` was the default and is gone: deleted", FixKind.AUTO)
            return True, False
        if value is True:
            self.report(
                arg,
                "GM801",
                "`autoreset=True` became the `Autoreset` wrapper; since Gymnasium 1.0 it resets on the step after "
                "the episode ends (that step returns the reset obs with reward 0) and sets no final_observation: review",
            )
            return True, True
        self.report(
            arg,
            "GM801",
            "`autoreset=` was removed in Gymnasium 1.0 and its value is not a constant: wrap the env in "
            "gymnasium.wrappers.Autoreset where it was true",
            FixKind.FLAG,
        )
        return False, False

    def _autoreset(self, call: cst.Call) -> cst.Call:
        """``gym.make(...)`` -> ``gym.wrappers.Autoreset(gym.make(...))``, through the user's alias."""
        func = call.func
        if isinstance(func, cst.Attribute) and isinstance(func.value, cst.Name):
            wrapper: cst.BaseExpression = cst.parse_expression(f"{func.value.value}.wrappers.Autoreset")
        else:
            AddImportsVisitor.add_needed_import(self.context.codemod, "gymnasium.wrappers", "Autoreset")
            wrapper = cst.Name("Autoreset")
        return cst.Call(func=wrapper, args=[cst.Arg(value=call.with_changes(lpar=(), rpar=()))], lpar=call.lpar, rpar=call.rpar)


def _constant(value: cst.BaseExpression) -> bool | None:
    if isinstance(value, cst.Name) and value.value in ("True", "False"):
        return value.value == "True"
    return None


def _without_keywords(args: tuple[cst.Arg, ...] | list[cst.Arg], keywords: set[str]) -> list[cst.Arg]:
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
