"""The one reading of "done used as a collection" (facts/collection_reads.py) and the five
questions asked of it: a batch of envs (``done_read_per_env``), agents' flags
(``per_agent_done``), an element-wise join (``reads_as_batch``), a wrapper's reduction of its
inner step's per-agent flags (``_reads_per_agent``) and RLlib's dict of agents' flags
(``_per_agent_flags``)."""

from __future__ import annotations

import ast
import textwrap

import pytest

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.batched_steps import done_read_per_env
from gymmigrate.facts.collection_reads import (
    CollectionRead,
    Shape,
    collection_read,
    named,
    named_in,
)
from gymmigrate.facts.own_api import _per_agent_flags
from gymmigrate.facts.per_agent_flags import PerAgent, per_agent_done
from gymmigrate.rules.step_done.unpack import reads_as_batch
from gymmigrate.rules.wrappers.step_inner import _reads_per_agent


def _reads(expression: str) -> list[CollectionRead]:
    tree = ast.parse(textwrap.dedent(expression))
    is_done = named("done")
    return [read for node in ast.walk(tree) if (read := collection_read(node, is_done)) is not None]


@pytest.mark.parametrize(
    ("code", "expected"),
    [
        pytest.param("done[0]", CollectionRead(Shape.INDEXED), id="index"),
        pytest.param("done[1:]", CollectionRead(Shape.INDEXED), id="slice"),
        pytest.param('done["__all__"]', CollectionRead(Shape.KEYED, key="__all__"), id="a dict of flags by name"),
        pytest.param("for d in done: pass", CollectionRead(Shape.ITERATED), id="loop"),
        pytest.param("async def f():\n    async for d in done: pass", CollectionRead(Shape.ITERATED), id="async loop"),
        pytest.param("[d for d in done]", CollectionRead(Shape.ITERATED), id="comprehension"),
        pytest.param("all(done)", CollectionRead(Shape.PASSED, "all", only_argument=True), id="reduction"),
        pytest.param("zip(obs, done)", CollectionRead(Shape.PASSED, "zip"), id="paired"),
        pytest.param("done.tolist()", CollectionRead(Shape.METHOD, "tolist"), id="own method"),
        pytest.param("np.logical_or(t, done)", CollectionRead(Shape.ARRAY_CALL, "logical_or"), id="numpy call"),
        pytest.param("np.any(done)", CollectionRead(Shape.ARRAY_CALL, "any", only_argument=True), id="numpy reduction"),
        pytest.param("isinstance(done)", CollectionRead(Shape.TYPE_TEST), id="malformed type test: no types"),
    ],
)
def test_shapes(code: str, expected: CollectionRead) -> None:
    assert _reads(code) == [expected]


def test_any_of_several_names() -> None:
    tree = ast.parse("all(terminated) or truncated[0] or done")
    is_flag = named_in({"terminated", "truncated"})
    reads = [read for node in ast.walk(tree) if (read := collection_read(node, is_flag)) is not None]
    assert sorted(read.shape for read in reads) == [Shape.INDEXED, Shape.PASSED]


def test_type_test_keeps_the_types() -> None:
    (read,) = _reads("isinstance(done, (list, tuple))")
    assert read.shape is Shape.TYPE_TEST and read.types is not None and ast.unparse(read.types) == "(list, tuple)"


@pytest.mark.parametrize(
    "code",
    [
        pytest.param("if done: pass", id="one flag"),
        pytest.param("x[done]", id="an index, not the indexed"),
        pytest.param("for done in xs: pass", id="the loop's target"),
        pytest.param("zip(*done)", id="unpacked into the call"),
        pytest.param("f(key=done)", id="a keyword"),
        pytest.param("1 - done", id="arithmetic: not this module's question"),
    ],
)
def test_not_a_collection_read(code: str) -> None:
    assert _reads(code) == []


def _facts(body: str) -> ModuleFacts:
    code = f"def step(env, a, obs, np):\n    obs, r, done, info = env.step(a)\n    {body}\n"
    return ModuleFacts(ast.parse(code), code)


def _function(body: str) -> ast.FunctionDef:
    function = _facts(body).tree.body[0]
    assert isinstance(function, ast.FunctionDef)
    return function


def _per_env(body: str) -> bool:
    facts = _facts(body)
    function = facts.tree.body[0]
    assert isinstance(function, ast.FunctionDef)
    assign = function.body[0]
    assert isinstance(assign, ast.Assign) and isinstance(assign.targets[0], ast.Tuple)
    target = assign.targets[0]
    return done_read_per_env(facts, target.elts[2], target)


def _wrapper_reduces(body: str) -> bool:
    """A wrapper's step asks of the expressions it returns or assigns, not of statements."""
    statement = _function(body).body[1]
    return any(_reads_per_agent(node, {"done"}) for node in ast.walk(statement) if isinstance(node, ast.expr))


def _rllib_dict(body: str) -> bool:
    function = _function(body)
    return _per_agent_flags(ast.Name("done"), function, {})


# Each question takes its own shapes: (batch of envs, agents' flags, element-wise join, a
# wrapper's reduction of per-agent flags, RLlib's dict of agents).
@pytest.mark.parametrize(
    ("body", "per_env", "per_agent", "elementwise", "wrapper", "rllib"),
    [
        pytest.param("x = done[0]", True, PerAgent(), True, True, False, id="index: all but RLlib's"),
        pytest.param("for d in done: pass", True, PerAgent(), True, False, False, id="loop: no expression"),
        pytest.param("x = [d for d in done]", True, PerAgent(), True, True, False, id="comprehension"),
        pytest.param("x = all(done)", True, PerAgent(), False, True, False, id="all(): not element-wise"),
        pytest.param("x = len(done)", True, None, False, True, False, id="len(): no agents' evidence"),
        pytest.param("x = sum(done)", True, None, False, True, False, id="sum(): a batch or a wrapper's count"),
        pytest.param("x = zip(obs, done)", True, PerAgent(), False, False, False, id="zip(): not a reduction"),
        pytest.param("x = done.any()", False, None, True, False, False, id="an array's method"),
        pytest.param("x = list(done.values())", False, None, False, True, False, id="a dict's view"),
        pytest.param("x = np.logical_not(done)", False, None, True, False, False, id="numpy call"),
        pytest.param("x = np.all(done)", False, None, True, False, False, id="numpy reduction: one flag passes"),
        pytest.param("x = np.stack(done)", False, None, False, False, False, id="numpy call, not element-wise"),
        pytest.param(
            "x = [done] if isinstance(done, bool) else done", False, None, True, False, False, id="type test for one flag"
        ),
        pytest.param(
            "x = done[0] if isinstance(done, (list, tuple)) else done",
            True,
            PerAgent("(list, tuple)"),
            True,
            True,
            False,
            id="list guard",
        ),
        pytest.param('x = done["__all__"]', True, PerAgent(by_name=True), True, True, True, id="keyed"),
        pytest.param('done["__all__"] = True', True, PerAgent(by_name=True), True, True, True, id="keyed store"),
        pytest.param('x = done["agent_0"]', True, PerAgent(by_name=True), True, True, False, id="keyed by an agent"),
        pytest.param("if isinstance(info, list): x = done[0]", False, None, True, True, False, id="a VecEnv's branch"),
        pytest.param("if done: pass", False, None, False, False, False, id="one flag"),
    ],
)
def test_each_question(
    body: str, per_env: bool, per_agent: PerAgent | None, elementwise: bool, wrapper: bool, rllib: bool
) -> None:
    assert _per_env(body) is per_env
    assert per_agent_done(_function(body), "done") == per_agent
    assert reads_as_batch(_function(body), "done") is elementwise
    assert _wrapper_reduces(body) is wrapper
    assert _rllib_dict(body) is rllib
