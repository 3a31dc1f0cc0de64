"""Shape torture: every odd expression kind in every slot the rules inspect.

Small legacy programs are generated here, programmatically (no hypothesis): each
template is a legacy Gym program with one slot (the ``done`` of a wrapper's step return,
a reset result, step targets, make/render/seed arguments...), and each expression kind
(attribute, call, conditional, subscript, starred, walrus, lambda, await, yield,
comprehension, f-string...) is put into it. A rule may rewrite or report what it sees,
but never raise: no program may come back with an internal error, and what comes back
parses and is stable.
"""

from __future__ import annotations

import ast

import pytest

from gymmigrate.engine import transform_source
from gymmigrate.source_text import TransformError

# Expression kinds, each valid in an ordinary expression position.
EXPRESSIONS = {
    "name": "x",
    "attribute": "self.meta.done",
    "call": "all(done)",
    "nested_call": "f(g(x), *h)",
    "ifexp": "a if c else b",
    "subscript": "d[0]",
    "slice": "d[1:]",
    "subscript_tuple": "d[0, 0]",
    "subscript_tuple_mixed": "d[(0), 1:]",
    "walrus": "(d := f())",
    "lambda": "(lambda: 0)",
    "await": "(await g())",
    "yield": "(yield)",
    "constant": "None",
    "fstring": 'f"{x}-v0"',
    "binop": "a + b",
    "boolop": "a or b",
    "not": "not d",
    "compare": "d == 1",
    "listcomp": "[y for y in ys]",
    "genexp": "(y for y in ys)",
    "dict": "{'k': v}",
    "tuple": "(a, b)",
    "list": "[a, b]",
    "starred_call": "f(*a, **k)",
    "method_chain": "self.env.unwrapped.get()",
}

ASYNC_KINDS = frozenset({"await", "name", "call", "walrus", "yield"})

# Assignment targets, each valid on the left of ``=``.
TARGETS = {
    "name": "x",
    "attribute": "self.x",
    "subscript": "d[0]",
    "starred": "*rest",
    "nested": "(a, b)",
    "list": "[a, b]",
}

WRAPPER = "import gym\n\n\nclass W(gym.Wrapper):\n{body}"

# Templates with {E}: an expression slot; {T}: a target slot. Each is one legacy program.
EXPRESSION_TEMPLATES = {
    "wrapper_step_done": WRAPPER.format(
        body="    {D}def step(self, action):\n"
        "        obs, reward, done, info = self.env.step(action)\n"
        "        return obs, reward, {E}, info\n"
    ),
    "wrapper_step_done_read": WRAPPER.format(
        body="    {D}def step(self, action):\n"
        "        obs, reward, done, info = self.env.step(action)\n"
        "        if done:\n            self.episodes += 1\n"
        "        return obs, reward, {E}, info\n"
    ),
    "wrapper_step_done_five": WRAPPER.format(
        body="    {D}def step(self, action):\n"
        "        obs, reward, terminated, truncated, info = self.env.step(action)\n"
        "        done = terminated or truncated\n"
        "        return obs, reward, {E}, info\n"
    ),
    "wrapper_reset_process": WRAPPER.format(
        body="    {D}def reset(self):\n        return self.process(self.env.reset(), {E})\n"
        "    def process(self, o, x=None):\n        return o\n"
    ),
    "wrapper_reset_assigned": WRAPPER.format(
        body="    {D}def reset(self):\n        obs = self.process(self.env.reset(), {E})\n        return obs\n"
    ),
    "env_holds_env": "import gym\n\n\nclass E(gym.Env):\n    def __init__(self):\n        self.env = gym.make('CartPole-v1')\n\n"
    "    {D}def reset(self):\n        return self.env.reset({E})\n\n"
    "    {D}def seed(self, seed=None):\n        self.env.seed({E})\n\n"
    "    {D}def step(self, action):\n        obs, reward, done, info = self.env.step({E})\n        return obs, reward, done, info\n",
    "elif_chain": "import gym\n\n{D}def main():\n    env = gym.make('CartPole-v1')\n    obs = env.reset()\n"
    "    if env.spec.id == 'a':\n        pass\n    elif {E}:\n        obs, reward, done, info = env.step(env.action_space.sample())\n"
    "    elif env.unwrapped.state is None:\n        env.seed(0)\n    else:\n        env.render(mode='human')\n",
    "time_limit_info": "import gym\n\n{D}def main():\n    env = gym.make('CartPole-v1')\n    obs = env.reset()\n"
    "    obs, reward, done, info = env.step(0)\n    timeout = info.get('TimeLimit.truncated', {E})\n"
    "    if done and not info[{E}]:\n        target = reward\n    return done and not timeout\n",
    "vector_infos": "import gym\n\n{D}def main():\n    envs = gym.vector.make('CartPole-v1', num_envs=2)\n    obs = envs.reset()\n"
    "    obs, rewards, dones, infos = envs.step(envs.action_space.sample())\n"
    "    for i, d in enumerate({E}):\n        last = infos[i]['terminal_observation'] if d else {E}\n",
    "env_step_limit": "import gym\n\n\nclass E(gym.Env):\n    {D}def step(self, action):\n        self.t += 1\n"
    "        done = self.t >= ({E}) or ({E})\n        return self.obs, 0.0, done, {{}}\n",
    "wrapper_step_done_no_unpack": WRAPPER.format(
        body="    {D}def step(self, action):\n        return self.obs, self.r, {E}, {{}}\n"
    ),
    "wrapper_step_action": WRAPPER.format(
        body="    {D}def step(self, action):\n        return self.env.step({E})\n"
    ),
    "wrapper_step_whole": WRAPPER.format(body="    {D}def step(self, action):\n        return {E}\n"),
    "wrapper_reset_wrapped": WRAPPER.format(
        body="    {D}def reset(self, **kwargs):\n        return self.process(self.env.reset(**kwargs), {E})\n"
    ),
    "wrapper_reset_result": WRAPPER.format(
        body="    {D}def reset(self):\n        obs = self.env.reset()\n        return {E}\n"
    ),
    "wrapper_reset_arg": WRAPPER.format(body="    {D}def reset(self):\n        return self.env.reset({E})\n"),
    "wrapper_observation": WRAPPER.format(
        body="    {D}def reset(self):\n        return self.observation({E})\n"
        "    def observation(self, o):\n        return o\n"
    ),
    "env_step_return": "import gym\n\n\nclass E(gym.Env):\n"
    "    {D}def step(self, action):\n        return self.obs, 1.0, {E}, {{}}\n"
    "    {D}def reset(self):\n        return {E}\n",
    "env_seed_method": "import gym\nfrom gym.utils import seeding\n\n\nclass E(gym.Env):\n"
    "    {D}def seed(self, seed=None):\n        self.np_random, seed = seeding.np_random({E})\n        return [seed]\n",
    "env_render_method": "import gym\n\n\nclass E(gym.Env):\n"
    "    metadata = {{'render.modes': {E}}}\n\n"
    "    {D}def render(self, mode={E}):\n        return {E}\n",
    "make_arg": "import gym\n\n{D}def main():\n    env = gym.make({E})\n    env.seed({E})\n    obs = env.reset()\n",
    "make_kwarg": "import gym\n\n{D}def main():\n    env = gym.make('CartPole-v1', render_mode={E}, max_episode_steps={E})\n",
    "render_arg": "import gym\n\n{D}def main():\n    env = gym.make('CartPole-v1')\n    env.render({E})\n    env.render(mode={E})\n",
    "seed_arg": "import gym\n\n{D}def main():\n    env = gym.make('CartPole-v1')\n    env.seed({E})\n    env.action_space.seed({E})\n",
    "reset_arg": "import gym\n\n{D}def main():\n    env = gym.make('CartPole-v1')\n    obs = env.reset({E})\n",
    "step_arg_loop": "import gym\n\n{D}def main():\n    env = gym.make('CartPole-v1')\n    obs = env.reset()\n"
    "    done = False\n    while not done:\n        obs, reward, done, info = env.step({E})\n        if {E}:\n            break\n",
    "done_condition": "import gym\n\n{D}def main():\n    env = gym.make('CartPole-v1')\n    obs = env.reset()\n"
    "    obs, reward, done, info = env.step(0)\n    if {E} or done:\n        obs = env.reset()\n"
    "    done = {E}\n    return done\n",
    "step_value": "import gym\n\n{D}def main():\n    env = gym.make('CartPole-v1')\n    env.reset()\n"
    "    result = env.step(0)\n    done = result[2] or {E}\n    x = ({E}).step(0)\n",
    "vector": "import gym\nfrom stable_baselines3.common.vec_env import DummyVecEnv\n\n{D}def main():\n"
    "    envs = gym.vector.make({E}, num_envs=2)\n    venv = DummyVecEnv([lambda: gym.make({E})])\n"
    "    obs = venv.reset()\n    obs, rewards, dones, infos = venv.step({E})\n",
    "wrappers_usage": "import gym\nfrom gym.wrappers import Monitor, TimeLimit\n\n{D}def main():\n"
    "    env = Monitor(gym.make('CartPole-v1'), {E}, force={E})\n    env = TimeLimit({E}, max_episode_steps={E})\n",
    "spaces": "import gym\nfrom gym import spaces\n\n{D}def main():\n"
    "    s = spaces.Box({E}, {E}, shape={E}, dtype={E})\n    t = gym.spaces.Discrete({E})\n    u = spaces.Tuple({E})\n",
    "registration": "import gym\nfrom gym.envs.registration import register\n\n"
    "register(id={E}, entry_point={E}, max_episode_steps={E}, kwargs={E})\n",
    "rng": "import gym\n\n{D}def main(env):\n    x = env.np_random.randint({E})\n    y = env.np_random.random_integers(0, {E})\n",
    "pettingzoo": "from pettingzoo.butterfly import pistonball_v6\n\n{D}def main():\n"
    "    env = pistonball_v6.env()\n    env.reset()\n    env.seed({E})\n"
    "    for agent in env.agent_iter():\n        obs, reward, done, info = env.last()\n"
    "        env.step(None if done else {E})\n",
}

TARGET_TEMPLATES = {
    "wrapper_step_targets": WRAPPER.format(
        body="    def step(self, action):\n        {T}, reward, done, info = self.env.step(action)\n"
        "        return obs, reward, done, info\n"
    ),
    "wrapper_step_done_target": WRAPPER.format(
        body="    def step(self, action):\n        obs, reward, {T}, info = self.env.step(action)\n"
        "        return obs, reward, done, info\n"
    ),
    "wrapper_reset_target": WRAPPER.format(
        body="    def reset(self):\n        {T} = self.env.reset()\n        return obs\n"
    ),
    "loop_step_targets": "import gym\n\nenv = gym.make('CartPole-v1')\nobs = env.reset()\n"
    "for _ in range(3):\n    obs, reward, {T}, info = env.step(0)\n    {T} = env.step(0)\n",
    "loop_reset_target": "import gym\n\nenv = gym.make('CartPole-v1')\n{T} = env.reset()\nwhile True:\n"
    "    {T}, r, done, _ = env.step(0)\n    if done:\n        {T} = env.reset()\n",
    "pettingzoo_last_targets": "from pettingzoo.butterfly import pistonball_v6\n\nenv = pistonball_v6.env()\nenv.reset()\n"
    "for agent in env.agent_iter():\n    obs, reward, {T}, info = env.last()\n    {T} = env.last()\n    env.step(None)\n",
    "pettingzoo_parallel_targets": "from pettingzoo.butterfly import pistonball_v6\n\nenv = pistonball_v6.parallel_env()\n"
    "obs = env.reset()\nobs, rewards, {T}, infos = env.step({a: 0 for a in env.agents})\n{T} = env.step({})\n",
    "vector_targets": "import gym\n\nenvs = gym.vector.make('CartPole-v1', num_envs=2)\nobs = envs.reset()\n"
    "obs, rewards, {T}, infos = envs.step(envs.action_space.sample())\n",
    "for_target": "import gym\n\nenv = gym.make('CartPole-v1')\nfor {T} in [env.step(0)]:\n    pass\n"
    "with env.step(0) as {T}:\n    pass\n",
    "aug_and_ann": "import gym\n\nenv = gym.make('CartPole-v1')\nobs: object = env.reset()\n"
    "total = 0\ntotal += env.step(0)[1]\n{T} = env.seed(0)\n",
}

# Whole programs around statements the templates cannot express with one slot.
STATEMENT_PROGRAMS = {
    "match": "import gym\n\nenv = gym.make('CartPole-v1')\nobs = env.reset()\n"
    "match env.step(0):\n    case (o, r, d, i):\n        done = d\n    case _:\n        pass\n",
    "async_loop": "import gym\n\n\nasync def main():\n    env = gym.make('CartPole-v1')\n    obs = env.reset()\n"
    "    async for obs, reward, done, info in steps(env):\n        pass\n"
    "    async with ctx() as env2:\n        obs, reward, done, info = env2.step(0)\n",
    "walrus_step": "import gym\n\nenv = gym.make('CartPole-v1')\nobs = env.reset()\n"
    "while not (res := env.step(0))[2]:\n    pass\nif (obs := env.reset()) is not None:\n    pass\n",
    "starred_step": "import gym\n\nenv = gym.make('CartPole-v1')\nobs = env.reset()\n"
    "obs, *rest = env.step(0)\n*head, done, info = env.step(0)\nobs, reward, done, info = *env.step(0),\n",
    "wrapper_step_starred_return": "import gym\n\n\nclass W(gym.Wrapper):\n"
    "    def step(self, action):\n        result = self.env.step(action)\n        return (*result,)\n\n"
    "    def reset(self, **kwargs):\n        return (yield self.env.reset(**kwargs))\n",
    "wrapper_lambda_methods": "import gym\n\n\nclass W(gym.Wrapper):\n    step = lambda self, a: self.env.step(a)\n"
    "    reset = lambda self: self.env.reset()\n    seed = property(lambda self: 0)\n",
    "env_class_odd": "import gym\n\n\nclass E(gym.Env, metaclass=M, **kw):\n    metadata = dict(modes=['human'])\n"
    "    reward_range = (-float('inf'), float('inf'))\n    def step(self, *args, **kwargs):\n        return super().step(*args)\n"
    "    async def reset(self):\n        return await self.r()\n    def seed(self, *a):\n        return [a]\n"
    "    def render(self, *a, **k):\n        pass\n",
    "decorated_and_global": "import gym\n\n\n@decorate(gym.make('CartPole-v1'))\nclass W(gym.ObservationWrapper):\n"
    "    def observation(self, o):\n        global env\n        nonlocal_ = [o for o in self.env.reset()]\n        return o\n",
    "try_star": "import gym\n\nenv = gym.make('CartPole-v1')\ntry:\n    obs, r, done, info = env.step(0)\n"
    "except* ValueError:\n    done = True\n",
    "type_alias": "import gym\n\ntype Step = tuple[object, float, bool, dict]\n\n"
    "def f[T](env: gym.Env) -> Step:\n    return env.step(0)\n",
}


def _programs() -> list[tuple[str, str]]:
    programs: list[tuple[str, str]] = []
    for slot, template in EXPRESSION_TEMPLATES.items():
        for kind, expr in EXPRESSIONS.items():
            # ``async def`` around the slot for the kinds that differ there (await is only
            # valid in it); every other kind once, in a plain ``def``.
            for prefix in ("", "async ") if kind in ASYNC_KINDS else ("",):
                if kind == "await" and not prefix:
                    continue
                code = template.replace("{D}", prefix).replace("{E}", expr).replace("{{", "{").replace("}}", "}")
                programs.append((f"{slot}-{kind}{'-async' if prefix else ''}", code))
    for slot, template in TARGET_TEMPLATES.items():
        for kind, target in TARGETS.items():
            programs.append((f"{slot}-{kind}", template.replace("{T}", target)))
    programs.extend(STATEMENT_PROGRAMS.items())
    valid = []
    for name, code in programs:
        try:
            ast.parse(code)
        except SyntaxError:
            continue  # a kind that this slot's grammar does not take (e.g. a starred target alone)
        valid.append((name, code))
    return valid


PROGRAMS = _programs()


def test_the_torture_covers_every_slot_and_kind() -> None:
    names = {name for name, _ in PROGRAMS}
    for slot in EXPRESSION_TEMPLATES:
        for kind in EXPRESSIONS:
            assert any(n.startswith(f"{slot}-{kind}") for n in names), f"{slot}-{kind} generated nothing that parses"
    assert len(PROGRAMS) > 800


@pytest.mark.parametrize(("name", "code"), PROGRAMS, ids=[name for name, _ in PROGRAMS])
def test_no_internal_error(name: str, code: str) -> None:
    try:
        result = transform_source(code.encode(), f"{name}.py")
    except TransformError as exc:
        assert "internal error" not in str(exc), f"{name}:\n{code}\n{exc}"
        assert "not stable" not in str(exc), f"{name}:\n{code}\n{exc}"
        return
    ast.parse(result.rewritten)
    again = transform_source(result.rewritten, f"{name}.py")
    assert again.rewritten == result.rewritten, f"{name}: a second run changed it"
