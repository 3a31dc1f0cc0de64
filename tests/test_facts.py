"""The facts layer: scopes, bindings, imports and receiver kinds from CPython's ast."""

from __future__ import annotations

import ast
import textwrap

import pytest

from gymmigrate.facts import ModuleFacts
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import WORK_BUDGET
from gymmigrate.facts.module import call_argument, full_name, own_returns
from gymmigrate.facts.per_agent_flags import PerAgent, per_agent_done
from gymmigrate.facts.receivers import EnvKind, Receivers
from gymmigrate.facts.wrapper_attributes import lookup_forwarded_to


def facts_of(code: str) -> ModuleFacts:
    code = textwrap.dedent(code)
    return ModuleFacts(ast.parse(code), code)


def name_reads(facts: ModuleFacts, name: str) -> list[ast.Name]:
    reads = [n for n in ast.walk(facts.tree) if isinstance(n, ast.Name) and n.id == name and isinstance(n.ctx, ast.Load)]
    return sorted(reads, key=lambda n: (n.lineno, n.col_offset))


def test_qualified_names_follow_every_import_form() -> None:
    facts = facts_of(
        """
        import gym
        import gymnasium as gm
        import gym.spaces
        from gym.wrappers import TimeLimit as TL
        (gym.make, gm.make, gym.spaces.Box, TL)
        """
    )
    expressions = facts.tree.body[-1].value.elts  # type: ignore[attr-defined]
    assert [facts.qualified_names(e) for e in expressions] == [
        {"gym.make"},
        {"gymnasium.make"},
        {"gym.spaces.Box"},
        {"gym.wrappers.TimeLimit"},
    ]
    assert facts.imported_as("gymnasium") == "gm"


def test_function_locals_shadow_module_names_and_class_bodies_do_not_enclose() -> None:
    facts = facts_of(
        """
        env = 1
        class Agent:
            env = 2
            def act(self):
                return env
        def local():
            env = 3
            return env
        """
    )
    method_read, local_read = name_reads(facts, "env")
    assert [b.lineno for b in facts.bindings_of(method_read)] == [2]  # the module's, not the class body's
    assert [b.lineno for b in facts.bindings_of(local_read)] == [8]


def test_defaults_are_read_in_the_enclosing_scope() -> None:
    facts = facts_of(
        """
        import gym
        env = gym.make("CartPole-v1")
        def run(env=env):
            return env
        """
    )
    default, body_read = name_reads(facts, "env")
    assert isinstance(facts.bindings_of(default)[0], ast.Name)  # the module-level assignment
    assert isinstance(facts.bindings_of(body_read)[0], ast.arg)


def test_indexes_of_calls_classes_and_functions() -> None:
    facts = facts_of(
        """
        def make_env():
            return 1
        class Box:
            pass
        make_env()
        x.step(1)
        y.step(2)
        """
    )
    assert len(facts.calls_by_name["make_env"]) == 1
    assert len(facts.attribute_calls["step"]) == 2
    assert set(facts.classes) == {"Box"} and set(facts.functions) == {"make_env"}


def test_statement_of_and_enclosing() -> None:
    facts = facts_of(
        """
        class Env:
            def step(self, a):
                return self.inner.step(a)
        """
    )
    call = facts.attribute_calls["step"][0]
    assert isinstance(facts.statement_of(call), ast.Return)
    assert facts.enclosing_class(call).name == "Env"  # type: ignore[union-attr]
    assert facts.is_method(facts.enclosing_function(call))  # type: ignore[arg-type]


def test_columns_count_characters_not_bytes() -> None:
    facts = facts_of('naïve = 1; env.reset()\n')
    call = facts.attribute_calls["reset"][0]
    assert call.col_offset == 12 and facts.column(call) == 11


def test_small_helpers() -> None:
    facts = facts_of(
        """
        def f(a, b=1):
            def g():
                return 2
            return a
        f(1, b=2)
        super().step.x
        """
    )
    function = facts.functions["f"]
    assert len(own_returns(function)) == 1  # the nested def's return is its own
    call = facts.calls_by_name["f"][0]
    assert ast.unparse(call_argument(call, 0, "a")) == "1"  # type: ignore[arg-type]
    assert ast.unparse(call_argument(call, 1, "b")) == "2"  # type: ignore[arg-type]
    assert full_name(facts.tree.body[-1].value) == "super.step.x"  # type: ignore[attr-defined]


# -- receivers -------------------------------------------------------------------------------


def receiver_kind(code: str, name: str = "env") -> EnvKind:
    facts = facts_of(code)
    return Receivers(facts).kind_of(name_reads(facts, name)[-1])


@pytest.mark.parametrize(
    ("code", "kind"),
    [
        ("import gym\nenv = gym.make('X')\nenv", EnvKind.GYM_ENV),
        ("import gymnasium as g\nenv = g.vector.SyncVectorEnv([])\nenv", EnvKind.GYM_VEC),
        ("from stable_baselines3.common.vec_env import DummyVecEnv\nenv = DummyVecEnv([])\nenv", EnvKind.SB3_VEC),
        ("from pettingzoo.classic import rps_v2\nenv = rps_v2.env()\nenv", EnvKind.PZ_AEC),
        ("import torch\nenv = torch.optim.Adam([])\nenv", EnvKind.NOT_ENV),
        ("env = something()\nenv", EnvKind.UNKNOWN),
        ("import gym\ndef make():\n    return gym.make('X')\nenv = make()\nenv", EnvKind.GYM_ENV),
        ("import gym\nenvs = [gym.make('X') for _ in range(3)]\nfor env in envs:\n    env", EnvKind.GYM_ENV),
        ("import gym\ndef run(env):\n    env\nrun(gym.make('X'))", EnvKind.GYM_ENV),
        ("import gym\nclass E(gym.Env):\n    pass\nenv = E()\nenv", EnvKind.GYM_ENV),
    ],
    ids=["make", "vector", "sb3", "pettingzoo", "optimiser", "unknown", "factory", "list", "param", "local-class"],
)
def test_receiver_kinds(code: str, kind: EnvKind) -> None:
    assert receiver_kind(code) is kind


def test_a_long_rebinding_chain_is_linear_and_cannot_overflow() -> None:
    # The classic Atari preprocessing stack, a thousand times over: no RecursionError,
    # and each binding is classified once.
    lines = ["import gym", "from gym import wrappers", "env = gym.make('Pong-v4')"]
    lines += ["env = wrappers.TimeLimit(env, 100)"] * 1000
    lines += ["env"]
    facts = facts_of("\n".join(lines))
    receivers = Receivers(facts)
    assert receivers.kind_of(name_reads(facts, "env")[-1]) is EnvKind.GYM_ENV
    assert len(receivers._cache) < 5000


def count_classifications(receivers: Receivers) -> list[ast.AST]:
    """Every expression ``receivers`` classifies from now on (its cached answers aside):
    the work a question costs, counted instead of timed."""
    classify = receivers._classify
    asked: list[ast.AST] = []

    def counted(expr: ast.AST) -> EnvKind:
        asked.append(expr)
        return classify(expr)

    receivers._classify = counted  # type: ignore[method-assign]
    return asked


def test_a_def_passing_its_parameter_on_at_many_calls_asks_each_frontier_once() -> None:
    # ``parse(text, params)`` calling itself at eight places with ``params`` (a recursive
    # descent parser): each call's argument is asked while others are open, and its
    # "unknown", cut short, is not kept. Asked again under the same open questions it is
    # reused, so the work follows the sets of open calls (2**8), not their orders (8!:
    # about a hundred thousand classifications, half a minute).
    lines = ["import gym", "def parse(text, params):", "    if not text:", "        return params.reset()"]
    lines += [f"    if text[0] == {i}:\n        return parse(text[1:], params)" for i in range(8)]
    lines += ["parse('ab', gym.make('CartPole-v1'))"]
    facts = facts_of("\n".join(lines))
    receivers = Receivers(facts)
    asked = count_classifications(receivers)
    assert receivers.kind_of(name_reads(facts, "params")[0]) is EnvKind.UNKNOWN
    assert len(asked) < 2000


def test_a_def_rebinding_its_parameter_under_many_ifs_walks_each_set_of_bindings_once() -> None:
    # ``wrap_deepmind``: ``env = Wrapper(env)`` eight times, under ``if``s. Every read of
    # ``env`` reads all eight bindings; a walk from one rebinding depends on the set already
    # on its path, not the order (8!: over two hundred thousand walks), so it is kept per set.
    lines = ["import gym", "from gym import wrappers", "def wrap(env, flags):"]
    for i in range(8):
        lines += [f"    if flags[{i}]:", "        env = wrappers.TimeLimit(env, 100)"]
    lines += ["    return env"]
    facts = facts_of("\n".join(lines))
    receivers = Receivers(facts)
    hands_on = receivers._hands_on_param
    walked: list[ast.AST] = []

    def counted(value: ast.expr, *rest: object) -> bool:
        walked.append(value)
        return hands_on(value, *rest)  # type: ignore[arg-type]

    receivers._hands_on_param = counted  # type: ignore[method-assign]
    assert receivers.wraps_argument(facts.functions["wrap"]) is True
    assert len(walked) < 5000


def test_classes_building_one_another_from_a_held_attribute_decide_it_once_per_class() -> None:
    # A planner's subgoals: ``Subgoal.__init__`` stores ``self.bot``, and each subclass (no
    # ``__init__`` of its own) builds the others with ``self.bot``. What ``self.bot`` holds in
    # one subclass is what its constructions pass, each a ``self.bot`` of another subclass:
    # asked per construction site, that is every order of the classes (8 subclasses: over
    # a minute); decided once per class and attribute, a few hundred classifications.
    lines = ["import gym", "class Subgoal:", "    def __init__(self, bot):", "        self.bot = bot"]
    for i in range(8):
        lines += [f"class Goal{i}(Subgoal):", "    def plan(self):"]
        lines += [f"        Goal{j}(self.bot)" for j in range(8) if j != i]
        lines += ["        return self.bot.step(0)"]
    facts = facts_of("\n".join(lines))
    receivers = Receivers(facts)
    asked = count_classifications(receivers)
    read = next(a for a in facts.attributes["bot"] if a.lineno == len(lines) and isinstance(a.ctx, ast.Load))
    assert receivers.kind_of(read) is EnvKind.UNKNOWN
    assert len(asked) < 3000


def test_a_question_through_dozens_of_mutually_recursive_methods_is_given_up_within_its_budget() -> None:
    # A compiler: ``_compile(expr, info)`` dispatches to a ``_compile_<op>(self, expr,
    # info)`` per operator, each compiling its operands with ``self._compile(arg, info)``.
    # What ``info`` holds is asked along every order of the methods (2**k open sets even
    # when kept per set); past the budget the question is "unknown", and the questions
    # open then are kept so, so the next read does not pay again.
    ops = [f"op{i}" for i in range(16)]
    lines = ["import gym", "class Compiler:", "    def _compile(self, expr, info):"]
    lines += [f"        if expr.kind == {op!r}:\n            return self._compile_{op}(expr, info)" for op in ops]
    lines += ["        return info.reset()"]
    for op in ops:
        lines += [f"    def _compile_{op}(self, expr, info):"]
        lines += [f"        a{j} = self._compile(expr.args[{j}], info)" for j in range(2)]
        lines += ["        return info.step(a0)"]
    lines += ["Compiler()._compile(None, gym.make('CartPole-v1'))"]
    facts = facts_of("\n".join(lines))
    receivers = Receivers(facts)
    asked = count_classifications(receivers)
    reads = name_reads(facts, "info")
    kinds = [receivers.kind_of(read) for read in reads]
    assert set(kinds) <= {EnvKind.UNKNOWN, EnvKind.GYM_ENV}
    assert len(asked) < 2 * WORK_BUDGET


@pytest.mark.parametrize(
    ("code", "handles"),
    [
        ("import gym\nenv = gym.make('CartPole-v1')\n", True),
        ("from gym import make\n", True),
        ("import gymnasium as gym\nclass W(gym.ObservationWrapper):\n    pass\n", True),
        ("import gym\ndef f(env):\n    return gym.wrappers.TimeLimit(env, 10)\n", True),
        ("from gym.envs.registration import register\n", True),
        ("def f():\n    import gym\n    return gym.vector.SyncVectorEnv([])\n", True),
        ("from gym.envs.classic_control import CartPoleEnv\n", True),
        ("import gym\n", False),
        ("from gym import spaces, error\nfrom gym.utils import seeding\n", False),
        ("import gym\nprint(gym.__version__)\ngym.logger.set_level(40)\n", False),
        ("def view():\n    from gym.envs.classic_control import rendering\n    return rendering.SimpleImageViewer()\n", False),
        ("import gym\nimport gym.wrappers.monitoring.video_recorder as vr\n", False),
    ],
)
def test_handles_gym_envs(code: str, handles: bool) -> None:
    from gymmigrate.facts.gym_use import handles_gym_envs

    assert handles_gym_envs(facts_of(code)) is handles


@pytest.mark.parametrize(
    ("body", "slot"),
    [
        ("return getattr(self.env, name)", "env"),
        ("return getattr(self._inner, name, None)", "_inner"),
        ("return self.env.get_wrapper_attr(name)", "env"),  # what GM604 writes: a second run agrees
        ("return getattr(self.env, 'seed')", None),  # not the looked-up name
        ("return getattr(other.env, name)", None),
        ("if name == 'x':\n        return getattr(self.a, name)\n    return getattr(self.b, name)", None),
        ("if name.startswith('_'):\n        raise AttributeError(name)\n    return getattr(self.env, name)", "env"),
    ],
)
def test_lookup_forwarded_to(body: str, slot: str | None) -> None:
    function = ast.parse(f"def __getattr__(self, name):\n    {body}\n").body[0]
    assert lookup_forwarded_to(function) == slot


@pytest.mark.parametrize(
    ("body", "expected"),
    [
        ("if all(done): pass", PerAgent()),
        ("for agent, d in zip(obs, done): pass", PerAgent()),
        ("x = done[0] if isinstance(done, (list, tuple)) else done", PerAgent("(list, tuple)")),
        ("if t > 9: done = len(obs) * [True]", PerAgent()),
        ('x = done["__all__"]', PerAgent(by_name=True)),
        ("if done: pass", None),
        ("x = all(done) if done.any() else 0", None),  # an array
        ("x = [done] if isinstance(done, bool) else done[0]", None),  # one flag or an array
        ("if isinstance(info, list): done = done[0]", None),  # a VecEnv's branch, not agents
    ],
)
def test_per_agent_done(body: str, expected) -> None:
    function = ast.parse(f"def step(obs, done, info, t):\n    {body}\n").body[0]
    assert per_agent_done(function, "done") == expected


@pytest.mark.parametrize(
    ("body", "may", "always"),
    [
        pytest.param("a()\nb()", True, True, id="straight line"),
        pytest.param("b()\na()", False, False, id="later in the text"),
        pytest.param("a()\nfor _ in n:\n    if c:\n        b()", True, True, id="in a later block"),
        pytest.param("if c:\n    a()\nb()", True, False, id="a on one path"),
        pytest.param("if c:\n    a()\nelse:\n    b()", False, False, id="two arms of an if"),
        pytest.param("if c:\n    return a()\nb()", False, False, id="a returns"),
        pytest.param("if c:\n    a()\n    raise E\nb()", False, False, id="a raises"),
        pytest.param("try:\n    x()\nexcept E:\n    a()\nexcept F:\n    b()", False, False, id="two handlers"),
        pytest.param("x = y if c else a()\nb()", True, False, id="a in a conditional value"),
        pytest.param("while c:\n    b()\n    a()", True, False, id="a loop comes round"),
        pytest.param("while c:\n    b()\n    a()\n    break", False, False, id="a loop that breaks"),
        pytest.param("while c:\n    b()\n    for _ in n:\n        a()\n        break", True, False, id="an inner break"),
    ],
)
def test_may_run_before_and_always_before(body: str, may: bool, always: bool) -> None:
    source = "def f():\n" + textwrap.indent(body, "    ") + "\n"
    facts = ModuleFacts(ast.parse(source), source)
    function = facts.functions["f"]
    calls = {c.func.id: c for c in ast.walk(function) if isinstance(c, ast.Call) and isinstance(c.func, ast.Name)}
    flow = Flow(facts)
    assert flow.may_run_before(calls["a"], calls["b"], function) is may
    assert flow.always_before(calls["a"], calls["b"]) is always


def test_a_loop_runs_a_call_again_before_itself() -> None:
    source = "def f():\n    while c:\n        a()\n        if d:\n            return\n    b()\n"
    facts = ModuleFacts(ast.parse(source), source)
    function = facts.functions["f"]
    call = next(c for c in ast.walk(function) if isinstance(c, ast.Call) and getattr(c.func, "id", "") == "a")
    assert Flow(facts).may_run_before(call, call, function)
    assert not Flow(facts).always_before(call, call)
