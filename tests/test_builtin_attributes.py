"""GM604's table of attributes Gymnasium's built-in envs lost (``builtin_attributes.py``)
agrees with the installed Gymnasium: for every id gym 0.21 registered, the class Gymnasium
1.4 makes for it (after GM803's version bump) is the class the table names, and it has
none of the attributes the table lists as gone (no ``self.x`` store, method or class
attribute in the class or its Gymnasium bases). Read from source: Box2D and MuJoCo need
not be installed."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import gymnasium
import pytest

from gymmigrate.rules.env_ids import migration_for
from gymmigrate.rules.wrapper_usage.builtin_attributes import (
    ATARI_GONE,
    ATARI_REPLACED,
    GONE,
    class_of_id,
)

# gym 0.21's built-in ids (``gym/envs/__init__.py``) whose classes Gymnasium still has.
LEGACY_IDS = (
    "CartPole-v0", "CartPole-v1", "MountainCar-v0", "MountainCarContinuous-v0", "Pendulum-v1", "Acrobot-v1",
    "LunarLander-v2", "LunarLanderContinuous-v2", "BipedalWalker-v3", "BipedalWalkerHardcore-v3", "CarRacing-v0",
    "FrozenLake-v1", "FrozenLake8x8-v1", "CliffWalking-v0", "Taxi-v3",
    "Reacher-v2", "Pusher-v2", "InvertedPendulum-v2", "InvertedDoublePendulum-v2", "HalfCheetah-v3", "Hopper-v3",
    "Swimmer-v3", "Walker2d-v3", "Ant-v3", "Humanoid-v3", "HumanoidStandup-v2",
)  # fmt: skip
_ROOT = Path(gymnasium.__file__).parent


def _module_tree(module: str) -> ast.Module:
    root, *parts = module.split(".")
    assert root == "gymnasium", module
    path = _ROOT.joinpath(*parts)
    path = path / "__init__.py" if path.is_dir() else path.with_suffix(".py")
    return ast.parse(path.read_text(encoding="utf-8"))


def _class_attributes(module: str, name: str, seen: set[str]) -> set[str]:
    """What the class and its bases define, following ``from gymnasium... import`` bases."""
    if f"{module}:{name}" in seen:
        return set()
    seen.add(f"{module}:{name}")
    tree = _module_tree(module)
    imported = {
        alias.asname or alias.name: (node.module, alias.name)
        for node in ast.walk(tree)
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("gymnasium")
        for alias in node.names
    }
    classdef = next((n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == name), None)
    if classdef is None:  # re-exported (``from gymnasium.core import Env`` in the package)
        return _class_attributes(*imported[name], seen)
    found: set[str] = set()
    for node in ast.walk(classdef):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node in classdef.body:
            found.add(node.name)
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store) and isinstance(node.value, ast.Name) and node.value.id == "self":
            found.add(node.attr)
        elif isinstance(node, (ast.Assign, ast.AnnAssign)) and node in classdef.body:
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            found.update(t.id for t in targets if isinstance(t, ast.Name))
    for base in classdef.bases:
        base = base.value if isinstance(base, ast.Subscript) else base
        if isinstance(base, ast.Name) and base.id in imported:
            found |= _class_attributes(*imported[base.id], seen)
        elif isinstance(base, ast.Name) and any(isinstance(n, ast.ClassDef) and n.name == base.id for n in tree.body):
            found |= _class_attributes(module, base.id, seen)
        elif isinstance(base, ast.Attribute) and base.attr == "Env":
            found |= _class_attributes("gymnasium.core", "Env", seen)
    return found


@pytest.mark.parametrize("legacy_id", LEGACY_IDS)
def test_gone_attributes_are_gone_from_the_class_gymnasium_makes(legacy_id: str) -> None:
    migration = migration_for(legacy_id)
    new_id = migration.new_id if migration is not None else legacy_id
    entry_point = gymnasium.spec(new_id).entry_point
    assert isinstance(entry_point, str), f"{new_id} is a stub"
    module, name = entry_point.split(":")
    assert class_of_id(legacy_id) == name, f"{legacy_id} makes {name} on Gymnasium"
    defined = _class_attributes(module, name, set())
    assert "reset" in defined and "np_random" in defined, "the bases were not followed"
    assert not defined & set(GONE[name]), f"{name} still has {sorted(defined & set(GONE[name]))}"


def test_every_class_of_the_table_is_made_by_an_id() -> None:
    made = {class_of_id(legacy_id) for legacy_id in LEGACY_IDS}
    # The two classes gym 0.21 also exported by name, which Gymnasium folds into a keyword.
    assert set(GONE) - made == {"LunarLanderContinuous", "BipedalWalkerHardcore"}


def test_atari_table_against_ale_py() -> None:
    """Every method the Atari table rewrites or reports is gone from ale-py's AtariEnv, and
    what replaces it is there, with the keywords the table adds."""
    ale_py = pytest.importorskip("ale_py")
    atari_env = ale_py.env.AtariEnv
    for name in (*ATARI_REPLACED, *ATARI_GONE):
        assert not hasattr(atari_env, name), name
    interface = ale_py.ALEInterface
    for name, (path, keywords, _) in ATARI_REPLACED.items():
        owner = interface if path[0] == "ale" else atari_env
        method = getattr(owner, path[-1])
        if keywords:
            assert {k for k, _ in keywords} <= set(inspect.signature(method).parameters), name
