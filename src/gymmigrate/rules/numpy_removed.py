"""GM914: NumPy names that NumPy 1.24 and 2.0 removed, in the files the run migrates.

Gymnasium 1.4 installs with NumPy 2, so a migrated module whose legacy code still says
``np.float`` (a Box dtype, an ``astype``) or ``np.NaN`` dies with ``AttributeError`` at import
or construction, although every Gym site was migrated. The names below were removed with a
replacement that is the same object or behaves the same (NumPy 1.24 release notes,
"expired deprecations"; NumPy 2.0 migration guide, "Python API removals"; each checked on
NumPy 2: the old name raises ``AttributeError``, the new one exists):

* ``np.float``, ``np.int``, ``np.object``, ``np.str``, ``np.complex``: aliases of the builtins
  (removed in 1.24) -> the builtin. Not ``np.bool``, ``np.long``, ``np.ulong``: NumPy 2 defines
  them again, with another meaning, so the old spelling no longer fails.
* ``np.float_`` -> ``np.float64``, ``np.complex_`` -> ``np.complex128``, ``np.bool8`` ->
  ``np.bool_``, ``np.unicode_`` -> ``np.str_``, ``np.string_`` -> ``np.bytes_``, ``np.NaN`` /
  ``np.NAN`` -> ``np.nan``, ``np.Inf`` / ``np.Infinity`` / ``np.infty`` / ``np.PINF`` ->
  ``np.inf``, ``np.NINF`` -> ``-np.inf``, ``np.product`` -> ``np.prod``, ``np.cumproduct`` ->
  ``np.cumprod``, ``np.alltrue`` -> ``np.all``, ``np.sometrue`` -> ``np.any``, ``np.round_`` ->
  ``np.round`` (all removed in 2.0; the new names exist since NumPy 1.x, so the output runs on
  both).

Removed names without an exact spelling (``np.cast[t](x)``, ``np.asfarray``) are reported
with the replacement to write. A name imported from numpy (``from numpy import float_``) is
reported at its import: its uses read the imported name.

Only where the name resolves to the numpy module through the file's imports (never a text
match: a project's own ``np`` object is left alone), in files that use Gym, Gymnasium or an
RL stack, like every rule. A module that sets the name on numpy itself (a shim) reads what it set:
left. A builtin replacement is written only where the file does not
bind that name itself.
"""

from __future__ import annotations

import ast

from gymmigrate.edits.lazy import cst
from gymmigrate.facts.module import ModuleFacts, full_name
from gymmigrate.findings import FixKind
from gymmigrate.rules.base import FileContext, Rule, RuleFamily

RULES = (
    Rule(
        "GM914",
        "NumPy names removed in 1.24 and 2.0",
        FixKind.AUTO,
        "`np.float`, `np.float_`, `np.NaN`, `np.product`... fail on the NumPy 2 that Gymnasium 1.4 installs: each becomes the builtin or NumPy name that is the same object or behaves the same.",
    ),
)

# aliases of the builtins, removed in NumPy 1.24
_BUILTINS = {"float": "float", "int": "int", "object": "object", "str": "str", "complex": "complex"}
# removed in NumPy 2.0: the NumPy name that replaces each
_RENAMED = {
    "float_": "float64",
    "complex_": "complex128",
    "bool8": "bool_",
    "unicode_": "str_",
    "string_": "bytes_",
    "NaN": "nan",
    "NAN": "nan",
    "Inf": "inf",
    "Infinity": "inf",
    "infty": "inf",
    "PINF": "inf",
    "NINF": "inf",  # negated
    "product": "prod",
    "cumproduct": "cumprod",
    "alltrue": "all",
    "sometrue": "any",
    "round_": "round",
}
# removed, with no spelling that is the same everywhere: what to write instead
_NO_EXACT = {
    "cast": "`np.asarray(x, dtype=...)` (`np.cast[t](x)` was `np.asarray(x).astype(t)`)",
    "asfarray": "`np.asarray(x, dtype=float)` where `x` is real (`asfarray` kept an inexact dtype such as complex)",
}
_ALL = frozenset({*_BUILTINS, *_RENAMED, *_NO_EXACT})


class NumpyRemoved(RuleFamily):
    RULES = RULES

    @classmethod
    def may_fire(cls, facts: ModuleFacts, context: FileContext) -> bool:
        profile = context.profile
        uses_rl = profile.imports_gym or profile.imports_gymnasium or profile.imports_sb3 or profile.imports_pettingzoo
        return uses_rl and "numpy" in facts.text

    def decide(self) -> None:
        sites = [node for name in _ALL for node in self.facts.attributes.get(name, ())]
        sites.sort(key=lambda node: (node.lineno, node.col_offset))
        on_numpy = [node for node in sites if self.facts.qualified_names(node) == {f"numpy.{node.attr}"}]
        # a module that sets the name on numpy itself (``np.float = float``, a shim for NumPy
        # 1.24) reads what it set, whatever that is: its reads do not fail and stay
        shimmed = {node.attr for node in on_numpy if not isinstance(node.ctx, ast.Load)}
        for node in on_numpy:
            if isinstance(node.ctx, ast.Load) and node.attr not in shimmed:
                self._attribute(node)
        imported = [alias for alias, qualified in self.facts.imports.items() if qualified == f"numpy.{alias.name}" and alias.name in _ALL]
        for alias in sorted(imported, key=lambda alias: (alias.lineno, alias.col_offset)):
            statement = self.facts.statement_of(alias)
            if isinstance(statement, ast.ImportFrom):
                self._import_from(statement, alias)

    def _attribute(self, node: ast.Attribute) -> None:
        name, spelled = node.attr, full_name(node) or f"np.{node.attr}"
        if name in _NO_EXACT:
            self.report(
                node,
                "GM914",
                f"`{spelled}` was removed in NumPy 2, which Gymnasium 1.4 installs: write {_NO_EXACT[name]}",
                FixKind.FLAG,
                question=("GM914", name),  # one answer for every use of the name in the file
            )
            return
        if name in _BUILTINS:
            builtin = _BUILTINS[name]
            if self.facts.resolve(builtin, self.facts.scope_of(node))[1]:
                self.report(
                    node,
                    "GM914",
                    f"`{spelled}` (the builtin `{builtin}`) was removed in NumPy 1.24; this file binds `{builtin}` itself: "
                    f"write the builtin `{builtin}` where the code means it",
                    FixKind.FLAG,
                )
                return
            self.plan.replace(node, lambda _node, builtin=builtin: cst.Name(builtin))
            self.report(node, "GM914", f"`{spelled}` was the builtin `{builtin}` (removed in NumPy 1.24): `{builtin}`")
            return
        new = _RENAMED[name]
        if name == "NINF":
            parenthesised = self._binds_tighter_than_minus(node)
            self.plan.replace(node, lambda cst_node, parenthesised=parenthesised: _negated_inf(cst_node, parenthesised))
            self.report(node, "GM914", f"`{spelled}` was removed in NumPy 2: `-{spelled[: -len(name)]}inf`")
            return
        self.plan.replace(node, lambda cst_node, new=new: cst_node.with_changes(attr=cst.Name(new)))
        self.report(node, "GM914", f"`{spelled}` was removed in NumPy 2: `{spelled[: -len(name)]}{new}`, the same object")

    def _binds_tighter_than_minus(self, node: ast.Attribute) -> bool:
        """``-np.inf`` needs parentheses where its place binds tighter than a unary minus:
        ``np.NINF.real``, ``np.NINF[0]``, ``np.NINF()``, ``np.NINF ** 2``."""
        parent = self.facts.parent(node)
        if isinstance(parent, (ast.Attribute, ast.Subscript)) and parent.value is node:
            return True
        if isinstance(parent, ast.Call) and parent.func is node:
            return True
        return isinstance(parent, ast.BinOp) and isinstance(parent.op, ast.Pow) and parent.left is node

    def _import_from(self, statement: ast.ImportFrom, alias: ast.alias) -> None:
        """Reported, not rewritten: the uses read the imported name, and a builtin cannot be
        imported from numpy under it."""
        name = alias.name
        if name in _NO_EXACT:
            instead = _NO_EXACT[name]
        elif name in _BUILTINS:
            instead = f"the builtin `{_BUILTINS[name]}`"
        elif name == "NINF":
            instead = "`-np.inf`"
        else:
            instead = f"`{_RENAMED[name]}`, the same object (`from numpy import {_RENAMED[name]} as {alias.asname or name}`)"
        self.report(
            statement,
            "GM914",
            f"`from numpy import {name}` fails on NumPy 2, which Gymnasium 1.4 installs ({name} was removed): use {instead}",
            FixKind.FLAG,
        )


def _negated_inf(node: cst.Attribute, parenthesised: bool) -> cst.BaseExpression:
    inf = node.with_changes(attr=cst.Name("inf"), lpar=(), rpar=())
    negated = cst.UnaryOperation(operator=cst.Minus(), expression=inf)
    if parenthesised or node.lpar:
        return negated.with_changes(lpar=(cst.LeftParen(),), rpar=(cst.RightParen(),))
    return negated
