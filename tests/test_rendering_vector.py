"""Runtime checks for the rendering (GM401-GM407) and vector (GM701-GM708) rules.

The fixtures prove the text of each rewrite; these tests run the rewritten code on the
installed Gymnasium, because a rewrite that reads well and fails at run time (wrong
``make_vec`` mode, ``wrappers=`` not a list, a render mode the env does not draw in) is
the failure this project exists to prevent.
"""

from __future__ import annotations

import textwrap
import warnings
from pathlib import Path

import gymnasium
import numpy as np
import pytest

from gymmigrate.engine import transform_source


def migrate(source: str) -> tuple[str, list]:
    result = transform_source(textwrap.dedent(source).encode(), "legacy.py")
    return result.rewritten.decode(), result.findings


def run(code: str) -> dict:
    namespace: dict = {"__name__": "migrated"}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # env-checker chatter is not what these tests check
        exec(compile(code, "migrated.py", "exec"), namespace)
    return namespace


# -- acceptance: a legacy vector loop runs once migrated (needs GM701 + GM704 + GM703) -----------

LEGACY_VECTOR_LOOP = """
import gym
import numpy as np

envs = gym.vector.make("CartPole-v1", num_envs=4)
obs = envs.reset()
episodes = 0
for step in range(300):
    actions = envs.action_space.sample()
    obs, rewards, dones, infos = envs.step(actions)
    episodes += int(np.sum(dones))
envs.close()
"""


def test_legacy_vector_loop_runs_after_migration() -> None:
    code, findings = migrate(LEGACY_VECTOR_LOOP)
    assert 'gym.make_vec("CartPole-v1", num_envs=4, vectorization_mode="async")' in code
    assert {"GM701"} <= {f.rule for f in findings}
    namespace = run(code)
    assert namespace["obs"].shape == (4, 4)
    assert namespace["episodes"] > 0  # 300 random steps end several CartPole episodes
    assert isinstance(namespace["envs"], gymnasium.vector.AsyncVectorEnv)


def test_list_style_infos_loop_runs_with_dict_info_to_list() -> None:
    code, findings = migrate(
        """
        import gym

        envs = gym.vector.make("CartPole-v1", num_envs=3, asynchronous=False,
                               wrappers=gym.wrappers.RecordEpisodeStatistics)
        obs = envs.reset()
        returns = []
        for step in range(300):
            obs, rewards, dones, infos = envs.step(envs.action_space.sample())
            for info in infos:
                if "episode" in info:
                    returns.append(float(info["episode"]["r"]))
        envs.close()
        """
    )
    assert "DictInfoToList(" in code
    assert ("GM705", "assist") in {(f.rule, f.kind.value) for f in findings}
    namespace = run(code)
    assert namespace["returns"], "the per-env info dicts must still carry episode statistics"


def test_final_observation_reader_runs_with_same_step_autoreset() -> None:
    code, findings = migrate(
        """
        import gym
        import numpy as np

        envs = gym.vector.make("CartPole-v1", num_envs=2, asynchronous=False)
        obs, _ = envs.reset(seed=0)
        finals = []
        for step in range(300):
            next_obs, rewards, terminations, truncations, infos = envs.step(envs.action_space.sample())
            if "final_observation" in infos:
                for idx, ended in enumerate(infos["_final_observation"]):
                    if ended:
                        finals.append(infos["final_observation"][idx])
        envs.close()
        """
    )
    assert "vector_kwargs={\"autoreset_mode\": gym.vector.AutoresetMode.SAME_STEP}" in code
    assert '"final_obs"' in code and '"_final_obs"' in code
    namespace = run(code)
    assert namespace["finals"] and all(np.shape(f) == (4,) for f in namespace["finals"])


@pytest.mark.parametrize(
    ("legacy", "vector_class"),
    [
        pytest.param('gym.vector.make("CartPole-v1", 2)', gymnasium.vector.AsyncVectorEnv, id="positional-default-async"),
        pytest.param(
            'gym.vector.make("Pendulum-v1", 2, False, gym.wrappers.ClipAction)',
            gymnasium.vector.SyncVectorEnv,
            id="positional-sync-single-wrapper",
        ),
        pytest.param(
            'gym.vector.make("CartPole-v1", num_envs=2, shared_memory=False, daemon=True)',
            gymnasium.vector.AsyncVectorEnv,
            id="vector-class-kwargs",
        ),
        pytest.param(
            'gym.vector.make("CartPole-v1", num_envs=2, asynchronous=use_async, wrappers=[gym.wrappers.RecordEpisodeStatistics])',
            gymnasium.vector.SyncVectorEnv,
            id="mode-from-variable",
        ),
        pytest.param(
            'gym.vector.make("Pendulum-v1", num_envs=2, asynchronous=False, shared_memory=True, g=9.0)',
            gymnasium.vector.SyncVectorEnv,
            id="sync-drops-async-only-kwargs",
        ),
    ],
)
def test_every_make_vec_form_runs(legacy: str, vector_class: type) -> None:
    code, _ = migrate(f"import gym\n\nuse_async = False\nenvs = {legacy}\n")
    assert "gym.vector.make" not in code and "vectorization_mode=" in code
    namespace = run(code + "obs, infos = envs.reset(seed=0)\nenvs.step(envs.action_space.sample())\nenvs.close()\n")
    assert isinstance(namespace["envs"], vector_class)


# -- acceptance: a legacy render loop gives frames from env.render() ---------------------------

LEGACY_RENDER_LOOP = """
import gym

env = gym.make("CartPole-v1")
frames = []
for step in range(10):
    frames.append(env.render(mode="rgb_array"))
env.close()
"""


def test_legacy_render_loop_gives_frames_on_cartpole() -> None:
    pytest.importorskip("pygame", reason="CartPole draws its frames with pygame (gymnasium[classic-control])")
    code, findings = migrate(LEGACY_RENDER_LOOP)
    assert 'gym.make("CartPole-v1", render_mode="rgb_array")' in code
    assert "env.render()" in code
    assert ("GM401", "assist") in {(f.rule, f.kind.value) for f in findings}
    namespace = run(code.replace("frames = []", "frames = []\nenv.reset(seed=0)"))
    frames = namespace["frames"]
    assert len(frames) == 10
    assert all(isinstance(frame, np.ndarray) and frame.ndim == 3 and frame.shape[2] == 3 for frame in frames)


class _CanvasEnv(gymnasium.Env):
    """A tiny env that draws with numpy, so the render path is checked without pygame."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 4}

    def __init__(self, render_mode=None):
        self.render_mode = render_mode
        self.observation_space = gymnasium.spaces.Discrete(2)
        self.action_space = gymnasium.spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        return 0, {}

    def step(self, action):
        return 0, 0.0, False, False, {}

    def render(self):
        if self.render_mode == "rgb_array":
            return np.zeros((8, 8, 3), dtype=np.uint8)
        return None


def test_render_loop_with_wrapper_chain_gives_frames() -> None:
    gymnasium.register("gymmigrate-test/Canvas-v0", entry_point=_CanvasEnv, max_episode_steps=20)
    try:
        code, _ = migrate(
            """
            import gym

            env = gym.make("gymmigrate-test/Canvas-v0")
            env = gym.wrappers.TimeLimit(env, max_episode_steps=5)
            frames = [env.render("rgb_array") for _ in range(3)]
            env.render(close=True)
            """
        )
        assert 'render_mode="rgb_array"' in code and "env.close()" in code
        namespace = run(code.replace("frames =", "env.reset(seed=0)\nframes ="))
        assert all(isinstance(frame, np.ndarray) for frame in namespace["frames"])
    finally:
        gymnasium.registry.pop("gymmigrate-test/Canvas-v0", None)


def test_record_video_gets_an_rgb_array_env() -> None:
    code, findings = migrate(
        """
        import gym
        from gym.wrappers import RecordVideo

        env = gym.make("CartPole-v1")
        env = RecordVideo(env, "videos")
        """
    )
    assert 'gym.make("CartPole-v1", render_mode="rgb_array")' in code
    assert ("GM407", "assist") in {(f.rule, f.kind.value) for f in findings}


def test_sb3_vec_env_render_is_left_alone() -> None:
    source = textwrap.dedent(
        """
        import gym
        from stable_baselines3.common.env_util import make_vec_env

        vec_env = make_vec_env("CartPole-v1", n_envs=2)
        vec_env.render("human")
        vec_env.render(mode="rgb_array")
        """
    )
    code, findings = migrate(source)
    assert 'vec_env.render("human")' in code and 'vec_env.render(mode="rgb_array")' in code
    assert not any(f.rule.startswith("GM4") for f in findings)


# -- the blessed fixture outputs run, not only parse -------------------------------------------

FIXTURES = Path(__file__).resolve().parent.parent / "fixtures" / "rules"


@pytest.mark.parametrize(
    ("fixture", "needs"),
    [
        ("GM701/default_async.expected.py", None),
        ("GM701/sync_with_wrapper.expected.py", None),
        ("GM701/from_import.expected.py", None),
        ("GM705/list_of_infos.expected.py", None),
        ("GM706/noop_same_step.py", None),
        ("GM401/basic.expected.py", "pygame"),
        ("GM401/self_env_positional.expected.py", "pygame"),
        ("GM403/single_frame_mode.expected.py", "pygame"),
    ],
)
def test_fixture_output_runs(fixture: str, needs: str | None, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)  # some fixtures save what they recorded (frames.npy)
    if needs:
        pytest.importorskip(needs, reason=f"the env draws its frames with {needs}")
    code = (FIXTURES / fixture).read_text()
    # Frames need a reset first; the fixtures show the render rewrite, not a whole loop.
    code = code.replace("\nframes = []", "\nenv.reset(seed=0)\nframes = []").replace(
        "\nimage = env.render()", "\nenv.reset(seed=0)\nimage = env.render()"
    )
    namespace = run(code)
    if "Evaluator" in namespace:
        evaluator = namespace["Evaluator"]("CartPole-v1")
        evaluator.env.reset(seed=0)
        assert isinstance(evaluator.snapshot(), np.ndarray)
    if "image" in namespace:
        assert isinstance(namespace["image"], np.ndarray)
    for value in namespace.values():
        if isinstance(value, gymnasium.vector.VectorEnv):
            value.close()


def test_the_starred_spaces_gm702_reports_raise_and_the_env_fns_alone_run() -> None:
    """GM702's claim on ``constructor(*args)``: gym's (env_fns, observation_space,
    action_space) by position raise on Gymnasium 1.x; the env functions alone build."""
    env = gymnasium.make("CartPole-v1")
    args = [lambda: gymnasium.make("CartPole-v1")] * 2, env.observation_space, env.action_space
    with pytest.raises(ValueError, match="observation_mode"):
        gymnasium.vector.SyncVectorEnv(*args)
    envs = gymnasium.vector.SyncVectorEnv(args[0])
    assert envs.reset(seed=0)[0].shape == (2, 4)
    envs.close()
