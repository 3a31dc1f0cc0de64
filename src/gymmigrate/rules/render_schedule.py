"""When does a legacy ``env.render()`` run? (GM401/GM402 keep a render's schedule.)

A legacy human render draws when it is called. Gymnasium's ``render_mode="human"``
draws inside every ``step()``/``reset()``. Where the render call runs only on a
condition (``if step % 30 == 0:``, ``if rank == 0:``, ``if args.render:``), adding
``render_mode="human"`` to the make would draw every frame in every worker: a training
script slowed down or a display opened where none was. So:

* a condition that is fixed when the env is made (it reads only parameters of the
  function that makes the env, or module names bound once, never rebound) moves to the
  make: ``render_mode="human" if rank == 0 else None``;
* any other condition (a step counter, an episode flag) cannot be known at creation:
  the site is reported and the make is left as it was.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts

# Expressions a creation-time condition may be built of: comparisons, boolean logic,
# constants, names and attribute reads of names (``args.render``); no calls, no
# subscripts (they may read state that changes while the env runs).
_PLAIN = (ast.Compare, ast.BoolOp, ast.UnaryOp, ast.Constant, ast.Name, ast.Attribute, ast.Load, ast.cmpop, ast.boolop, ast.unaryop)


def render_condition(facts: ModuleFacts, render: ast.Call, make: ast.Call) -> list[ast.expr]:
    """The conditions that guard ``render`` but not ``make``: the tests of the ``if``
    statements (or the other operands of ``and``/``or``, or an ``if`` expression) that
    enclose the render call below the nearest node that also encloses the make."""
    around_make = {id(node) for node in facts.ancestors(make)}
    tests: list[ast.expr] = []
    child: ast.AST = render
    for ancestor in facts.ancestors(render):
        if id(ancestor) in around_make:
            break
        if isinstance(ancestor, ast.If) and child is not ancestor.test:
            tests.append(ancestor.test)
        elif isinstance(ancestor, ast.IfExp) and child is not ancestor.test:
            tests.append(ancestor.test)
        elif isinstance(ancestor, ast.BoolOp) and child is not ancestor.values[0]:
            # `render and env.render()`; under `or` the whole expression stands (it holds a call).
            tests.append(ancestor.values[0] if isinstance(ancestor.op, ast.And) else ancestor)
        elif isinstance(ancestor, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            # Rendered from another function (a callback): its schedule is its caller's.
            tests.append(ancestor)  # type: ignore[arg-type]
            break
        child = ancestor
    return tests


def fixed_at_creation(facts: ModuleFacts, test: ast.expr, make: ast.Call) -> bool:
    """``test`` has the same value when ``make`` runs as when the render call runs."""
    if not all(isinstance(node, _PLAIN) for node in ast.walk(test)):
        return False
    function = facts.enclosing_function(make)
    for node in ast.walk(test):
        if not isinstance(node, ast.Name):
            continue
        bindings = facts.bindings_of(node)
        if len(bindings) != 1:
            return False  # unbound, or rebound (a counter, a flag that changes)
        binding = bindings[0]
        if isinstance(binding, ast.arg):
            if function is None or facts.enclosing_function(binding) is not function:
                return False  # a parameter of some other function
        elif not (isinstance(binding, ast.Name) and facts.enclosing_function(binding) is None):
            return False  # a local variable: it may change between make and render
        elif function is None and binding.lineno >= make.lineno:
            return False  # bound after the env is made
    return True


def schedule(facts: ModuleFacts, renders: list[ast.Call], make: ast.Call) -> tuple[str, str | None]:
    """How the human renders of one make run: ``("always", None)``; ``("fixed", text)``
    when they all run under one condition known at creation (``text`` is its source);
    ``("varies", text)`` otherwise (``text`` names the condition)."""
    conditions = [render_condition(facts, render, make) for render in renders]
    if any(not tests for tests in conditions):
        return "always", None  # one render runs on every pass: human mode draws as before
    texts = {" and ".join(_text(facts, t) for t in tests) for tests in conditions}
    first = next(iter(texts))
    if len(texts) == 1 and all(fixed_at_creation(facts, t, make) for t in conditions[0]):
        return "fixed", first
    return "varies", first


def _text(facts: ModuleFacts, test: ast.AST) -> str:
    if isinstance(test, (ast.FunctionDef, ast.AsyncFunctionDef)):
        return f"{test.name}() is called"
    if isinstance(test, ast.Lambda):
        return "a lambda is called"
    text = facts.segment(test)
    return f"({text})" if isinstance(test, (ast.BoolOp, ast.IfExp)) else text
