"""When does a legacy ``env.render()`` run? (GM401/GM402 keep a render's schedule.)

A legacy human render draws when it is called. Gymnasium's ``render_mode="human"``
draws inside every ``step()``/``reset()``. Where the render call runs only on a
condition (``if step % 30 == 0:``, ``if rank == 0:``, ``if args.render:``), adding
``render_mode="human"`` to the make would draw every frame in every worker: a training
script slowed down or a display opened where none was. So:

* a condition that is fixed when the env is made (it reads only parameters of the
  function that makes the env, module names bound once, never rebound, or local names
  bound once before the make and outside any loop) moves to the make:
  ``render_mode="human" if rank == 0 else None``;
* any other condition (a step counter, an episode flag) cannot be known at creation:
  the site is reported and the make is left as it was.
"""

from __future__ import annotations

import ast

from gymmigrate.facts import ModuleFacts, same_tests
from gymmigrate.facts.module import walk

# Expressions a creation-time condition may be built of: comparisons, boolean logic,
# constants, names and attribute reads of names (``args.render``); no calls, no
# subscripts (they may read state that changes while the env runs).
_PLAIN = (ast.Compare, ast.BoolOp, ast.UnaryOp, ast.Constant, ast.Name, ast.Attribute, ast.Load, ast.cmpop, ast.boolop, ast.unaryop)


# One guard of a render call: the expression, and whether the render runs when it is
# false (an ``else`` branch, the right side of ``or``).
Guard = tuple[ast.AST, bool]


def render_condition(facts: ModuleFacts, render: ast.Call, make: ast.AST, home: ast.AST | None = None) -> list[Guard]:
    """The guards of ``render`` that do not guard ``make``: the tests of the ``if``
    statements and expressions, and the operands of ``and``/``or`` before it, between the
    render call and the nearest node that also encloses the make."""
    around_make = {id(node) for node in facts.ancestors(make)}
    # ``if MODE == "cart": env = gym.make(...)`` and ``if MODE == "cart": env.render()``
    # later, the test unchanged: it already holds wherever the make runs.
    settled = same_tests.guards(facts, make)
    guards: list[Guard] = []
    child: ast.AST = render
    for ancestor in facts.ancestors(render):
        if id(ancestor) in around_make:
            break
        if isinstance(ancestor, (ast.If, ast.IfExp)) and child is not ancestor.test:
            in_else = child in ancestor.orelse if isinstance(ancestor, ast.If) else child is ancestor.orelse
            if (same_tests.test_key(facts, ancestor.test), not in_else) in settled:
                pass
            elif not (_main_guard(ancestor.test) and not in_else) and not (not in_else and _always_true(facts, ancestor.test)):
                guards.append((ancestor.test, in_else))
        elif isinstance(ancestor, ast.BoolOp):
            before = ancestor.values[: next(i for i, v in enumerate(ancestor.values) if v is child)]
            guards.extend((value, isinstance(ancestor.op, ast.Or)) for value in before)
        elif isinstance(ancestor, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            # Rendered from another function (a callback): its schedule is its caller's,
            # unless the env is stepped only in that function (``home``): human mode draws
            # inside step(), so whether the function runs is then the same question.
            if ancestor is not home:
                guards.append((ancestor, False))
            break
        child = ancestor
    return guards


def _always_true(facts: ModuleFacts, test: ast.AST) -> bool:
    """``if render:`` where ``render`` is a parameter of a module-level def, never rebound,
    whose name is read only to call it, and every call passes ``True`` for it (by keyword or
    by position): the test holds on every run, so it sets no schedule."""
    passed = _flag_values(facts, test, default=False)
    return passed is not None and all(isinstance(v, ast.Constant) and v.value is True for v in passed)


def never_run_guard(facts: ModuleFacts, call: ast.AST) -> ast.Name | None:
    """``if render: env.render()`` where ``render`` is such a parameter and every call of the
    def passes ``False`` for it or leaves its default ``False``: the test that keeps the
    call from ever running (``_flag_values``). None otherwise."""
    child: ast.AST = call
    for ancestor in facts.ancestors(call):
        if isinstance(ancestor, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
            return None
        if isinstance(ancestor, ast.If) and child in ancestor.body and isinstance(ancestor.test, ast.Name):
            passed = _flag_values(facts, ancestor.test, default=True)
            if passed and all(isinstance(v, ast.Constant) and v.value is False for v in passed):
                return ancestor.test
        child = ancestor
    return None


def _flag_values(facts: ModuleFacts, test: ast.AST, default: bool) -> list[ast.expr] | None:
    """What every call of a module-level def passes for the parameter ``test`` reads (never
    rebound; the def's name read only to call it), by keyword or by position, or, with
    ``default``, the parameter's default where a call leaves it out. None when one call
    shows nothing or the def is not called."""
    if not isinstance(test, ast.Name):
        return None
    bindings = facts.bindings_of(test)
    if len(bindings) != 1 or not isinstance(bindings[0], ast.arg):
        return None
    param = bindings[0]
    function = facts.enclosing_function(test)
    if function is None or facts.functions.get(function.name) is not function:
        return None
    args = function.args
    positional = [*args.posonlyargs, *args.args]
    if param not in positional and param not in args.kwonlyargs:
        return None
    position = positional.index(param) if param in positional else None
    if position is not None:
        defaults = args.defaults
        offset = position - (len(positional) - len(defaults))
        fallback = defaults[offset] if offset >= 0 else None
    else:
        fallback = args.kw_defaults[args.kwonlyargs.index(param)]
    reads = facts.reads_of(function.name, function)
    if not reads:
        return None
    found: list[ast.expr] = []
    for read in reads:
        call = facts.parent(read)
        if not (isinstance(call, ast.Call) and call.func is read):
            return None
        if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords):
            return None
        passed = next((k.value for k in call.keywords if k.arg == param.arg), None)
        if passed is None and position is not None and position < len(call.args):
            passed = call.args[position]
        if passed is None and default:
            passed = fallback
        if passed is None:
            return None
        found.append(passed)
    return found


def _main_guard(test: ast.AST) -> bool:
    """``__name__ == "__main__"``: the script runs as a program. That decides whether the
    program runs at all, not which of its steps draw."""
    return (
        isinstance(test, ast.Compare)
        and len(test.ops) == 1
        and isinstance(test.ops[0], ast.Eq)
        and {_plain(test.left), _plain(test.comparators[0])} == {"__name__", "'__main__'"}
    )


def _plain(node: ast.AST) -> str:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return repr(node.value)
    return ""


def fixed_at_creation(facts: ModuleFacts, test: ast.AST, make: ast.Call) -> bool:
    """``test`` has the same value when ``make`` runs as when the render call runs."""
    if not all(isinstance(node, _PLAIN) for node in walk(test)):
        return False
    function = facts.enclosing_function(make)
    held = {id(node.value) for node in walk(test) if isinstance(node, ast.Attribute) and _set_once_before(facts, node, make)}
    for node in walk(test):
        if not isinstance(node, ast.Name) or id(node) in held:
            continue
        bindings = facts.bindings_of(node)
        if len(bindings) != 1:
            return False  # unbound, or rebound (a counter, a flag that changes)
        binding = bindings[0]
        if isinstance(binding, ast.arg):
            if function is None or facts.enclosing_function(binding) is not function:
                return False  # a parameter of some other function
        elif isinstance(binding, ast.Name) and function is not None and facts.enclosing_function(binding) is function:
            if not _bound_once_before(facts, binding, make, function):
                return False  # a local variable that may change between make and render
        elif not (isinstance(binding, ast.Name) and facts.enclosing_function(binding) is None):
            return False  # a local variable: it may change between make and render
        elif function is None and binding.lineno >= make.lineno:
            return False  # bound after the env is made
    return True


def _set_once_before(facts: ModuleFacts, node: ast.Attribute, make: ast.Call) -> bool:
    """``self.render`` read in another method of the class whose method makes the env, and
    stored once in the module: in that method's own body, before the make, from a value fixed
    at creation (``self.render = render``, a parameter there). It holds that value on every
    later call, and ``self.render`` reads it at the make already."""
    if not isinstance(node.value, ast.Name):
        return False
    function = facts.enclosing_function(make)
    classdef = facts.enclosing_class(make)
    reader = facts.enclosing_function(node)
    if function is None or classdef is None or reader is None or facts.parent(function) is not classdef:
        return False
    if facts.parent(reader) is not classdef or not _first_param_is(reader, node.value.id) or not _first_param_is(function, node.value.id):
        return False
    stores = [
        n for n in walk(facts.tree) if isinstance(n, ast.Attribute) and n.attr == node.attr and isinstance(n.ctx, (ast.Store, ast.Del))
    ]
    if len(stores) != 1:
        return False
    statement = facts.parent(stores[0])
    return (
        isinstance(statement, ast.Assign)
        and statement.targets == [stores[0]]
        and isinstance(stores[0].value, ast.Name)
        and stores[0].value.id == node.value.id
        and facts.parent(statement) is function
        and statement.lineno < make.lineno
        and fixed_at_creation(facts, statement.value, make)
    )


def _first_param_is(function: ast.AST, name: str) -> bool:
    args = getattr(function, "args", None)
    return bool(args is not None and args.args and args.args[0].arg == name and not getattr(function, "decorator_list", None))


def _bound_once_before(facts: ModuleFacts, binding: ast.Name, make: ast.Call, function: ast.AST) -> bool:
    """A local name's only binding (``render = True``) is a statement of the function's own
    body, on an earlier line than the make: it has run, once, when the env is made (not in
    a loop, where it would take a new value each pass, nor in a branch that may not run)."""
    statement = facts.statement_of(binding)
    return binding.lineno < make.lineno and isinstance(statement, ast.Assign) and facts.parent(statement) is function


def schedule(facts: ModuleFacts, renders: list[ast.Call], make: ast.Call, home: ast.AST | None = None) -> tuple[str, str | None]:
    """How the human renders of one make run: ``("always", None)``; ``("fixed", text)``
    when they all run under one condition known at creation (``text`` is its source);
    ``("varies", text)`` otherwise (``text`` names the condition)."""
    conditions = [render_condition(facts, render, make, home) for render in renders]
    if any(not guards for guards in conditions):
        return "always", None  # one render runs on every pass: human mode draws as before
    # In source order, not a set's: the message must not change from one run to the next.
    texts = list(dict.fromkeys(" and ".join(_text(facts, guard) for guard in guards) for guards in conditions))
    first = texts[0]
    if len(texts) == 1 and all(fixed_at_creation(facts, test, make) for test, _ in conditions[0]):
        return "fixed", first
    return "varies", first


def local_condition(facts: ModuleFacts, render: ast.Call) -> str | None:
    """The condition under which ``render`` runs within its own function (``self.args.render``
    in an agent's method), or None when it runs on every call of it: a render whose make is
    in another module, where only the flag can be named."""
    function = facts.enclosing_function(render)
    if function is None:
        return None
    guards = render_condition(facts, render, function, home=function)
    return " and ".join(_text(facts, guard) for guard in guards) or None


def _text(facts: ModuleFacts, guard: Guard) -> str:
    test, negated = guard
    if isinstance(test, (ast.FunctionDef, ast.AsyncFunctionDef)):
        owner = facts.enclosing_class(test)
        if owner is not None and test.name == "render":
            # ``def render(self): return self.env.render()`` in a class holding the env: the
            # class's own render() forwards it, so its callers set the schedule ("render()
            # runs only when render() is called" says nothing)
            return f"`{owner.name}.render()`, which forwards it, is called"
        return f"`{owner.name}.{test.name}()` is called" if owner is not None else f"{test.name}() is called"
    if isinstance(test, ast.Lambda):
        return "a lambda is called"
    text = facts.segment(test)
    if negated:
        return f"not {text}" if isinstance(test, (ast.Name, ast.Attribute)) else f"not ({text})"
    return f"({text})" if isinstance(test, (ast.BoolOp, ast.IfExp)) else text


def same_value_at_make(facts: ModuleFacts, name: ast.Name, render: ast.Call, make: ast.Call) -> bool:
    """``name``, read by ``render``, holds the value it had when ``make`` ran, so it can be
    the make's ``render_mode``: bound once, and either fixed at creation (a parameter of
    the function that makes the env and renders it, a module name bound once before the
    make) or the target of a ``for`` loop whose body makes the env and renders it
    (``for mode in modes: env = make(...); env.render(mode=mode)``)."""
    bindings = facts.bindings_of(name)
    if len(bindings) != 1:
        return False
    function = facts.enclosing_function(make)
    if facts.enclosing_function(render) is not function:
        return False  # rendered from another function: any value may reach it
    binding = bindings[0]
    if isinstance(binding, ast.arg):
        return fixed_at_creation(facts, name, make)
    loop = facts.parent(binding)
    if isinstance(loop, (ast.For, ast.AsyncFor)) and loop.target is binding:
        return facts.enclosing_function(loop) is function and _in_body(facts, loop, make) and _in_body(facts, loop, render)
    return function is None and fixed_at_creation(facts, name, make)


def _in_body(facts: ModuleFacts, loop: ast.For | ast.AsyncFor, node: ast.AST) -> bool:
    """``node`` runs in ``loop``'s body (not its ``else``), in the loop's own frame."""
    child: ast.AST = node
    for ancestor in facts.ancestors(node):
        if ancestor is loop:
            return any(child is statement for statement in loop.body)
        if isinstance(ancestor, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
            return False
        child = ancestor
    return False
