"""The edit plan and its one-traversal application, independent of any rule."""

from __future__ import annotations

import ast
import textwrap

import libcst as cst
import pytest

from gymmigrate.edits.apply import ApplyError, apply_plan
from gymmigrate.edits.plan import Plan
from gymmigrate.engine import transform_source
from gymmigrate.facts import ModuleFacts
from gymmigrate.findings import FixKind


def planned(code: str) -> tuple[str, Plan]:
    code = textwrap.dedent(code)
    return code, Plan(ModuleFacts(ast.parse(code), code))


def applied(code: str, plan: Plan) -> str:
    result = apply_plan(cst.parse_module(code), plan).code
    ast.parse(result)
    return result


def seeded(node: cst.Call) -> cst.Call:
    return node.with_changes(args=[*node.args, cst.Arg(keyword=cst.Name("seed"), value=cst.Integer("0"))])


def test_calls_in_every_kind_of_block_are_found_and_replaced() -> None:
    code, plan = planned(
        """
        def f(env):
            if a:
                env.reset()
            elif b:
                env.reset()
            else:
                env.reset()
            for _ in x:
                pass
            else:
                env.reset()
            try:
                env.reset()
            except E as e:
                env.reset()
            finally:
                env.reset()
            with m:
                env.reset()
            while c: env.reset()
        """
    )
    for call in plan.facts.attribute_calls["reset"]:
        plan.replace(call, seeded)
    result = applied(code, plan)
    assert result.count("env.reset(seed = 0)") == 9
    assert result.replace("(seed = 0)", "()") == code  # nothing else moved


def test_nested_edits_compose_inner_first() -> None:
    code, plan = planned("x = wrap(env.step(a))\n")
    outer = plan.facts.calls_by_name["wrap"][0]
    inner = plan.facts.attribute_calls["step"][0]
    plan.replace(inner, lambda n: n.with_changes(func=n.func.with_changes(attr=cst.Name("act"))))
    plan.replace(outer, lambda n: n.with_changes(func=cst.Name("wrapped")))
    assert applied(code, plan) == "x = wrapped(env.act(a))\n"


def test_the_nth_of_identical_expressions_is_the_one_edited() -> None:
    code, plan = planned("print(env.reset(), env.reset(), env.reset())\n")
    second = plan.facts.attribute_calls["reset"][1]
    plan.replace(second, seeded)
    assert applied(code, plan) == "print(env.reset(), env.reset(seed = 0), env.reset())\n"


def test_insertions_take_whole_lines_or_join_a_shared_line() -> None:
    code, plan = planned(
        """
        def f():
            a = env.step(0)
            b = 1; c = env.step(1)
            if d: e = env.step(2)
        """
    )
    for call in plan.facts.attribute_calls["step"]:
        plan.insert_after(plan.facts.statement_of(call), "done = terminated or truncated")
    assert applied(code, plan) == textwrap.dedent(
        """
        def f():
            a = env.step(0)
            done = terminated or truncated
            b = 1; c = env.step(1); done = terminated or truncated
            if d: e = env.step(2); done = terminated or truncated
        """
    )


def test_removal_keeps_a_block_valid() -> None:
    code, plan = planned("if x:\n    env.seed(0)\n")
    plan.remove(plan.facts.statement_of(plan.facts.attribute_calls["seed"][0]))
    assert applied(code, plan) == "if x:\n    pass\n"


@pytest.mark.parametrize(
    ("code", "expected"),
    [
        ("import gym\nx = 1\n", "import gym\nimport numpy as np\nx = 1\n"),
        ('"""Doc."""\nx = 1\n', '"""Doc."""\nimport numpy as np\nx = 1\n'),
        ("x = 1\n", "import numpy as np\nx = 1\n"),
        ("", "import numpy as np\n"),
    ],
    ids=["after-imports", "after-docstring", "first", "empty"],
)
def test_new_imports_go_after_the_existing_ones(code: str, expected: str) -> None:
    code, plan = planned(code)
    assert plan.ensure_import("numpy", asname="np") == "np"
    assert applied(code, plan) == expected


def test_an_import_already_there_is_reused() -> None:
    _, plan = planned("import numpy as onp\n")
    assert plan.ensure_import("numpy", asname="np") == "onp"
    assert not plan.has_edits


def test_the_same_finding_twice_is_one_item() -> None:
    _, plan = planned("env.reset()\n")
    call = plan.facts.attribute_calls["reset"][0]
    plan.report(call, "GM201", FixKind.AUTO, "same")
    plan.report(call, "GM201", FixKind.AUTO, "same")
    assert len(plan.findings) == 1


def test_an_edit_that_cannot_be_placed_is_an_error_not_a_wrong_edit() -> None:
    code, plan = planned("x = a or b\n")
    boolop = plan.facts.tree.body[0].value  # type: ignore[attr-defined]
    plan.replace(boolop, lambda n: n)
    with pytest.raises(ApplyError):
        apply_plan(cst.parse_module(code), plan)


def test_a_file_with_nothing_to_change_never_builds_a_libcst_tree(monkeypatch: pytest.MonkeyPatch) -> None:
    import gymmigrate.engine as engine

    def refuse(source: bytes) -> cst.Module:
        raise AssertionError("parsed with LibCST")

    monkeypatch.setattr(engine, "_parse_cst", refuse)
    source = b"import os\n\nprint(os.environ['HOME'])\n"
    assert transform_source(source).rewritten == source


def test_a_parenthesized_tuple_is_found_although_ast_spans_its_parentheses() -> None:
    code, plan = planned("(ob, reward, done, info) = env.step(a)\n")
    target = plan.facts.tree.body[0].targets[0]  # type: ignore[attr-defined]
    plan.replace(target, lambda n: cst.Name("step_result"))
    assert applied(code, plan) == "step_result = env.step(a)\n"
