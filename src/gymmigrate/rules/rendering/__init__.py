"""Rendering at call sites: the render mode moves from ``render()`` to ``make()`` (GM401-GM403, GM406, GM407).

Gym 0.26 made the render mode a property of the env instance: ``gym.make(id,
render_mode=...)`` fixes it and ``env.render()`` takes no arguments (Gymnasium 1.x:
``TypeError: ... render() got an unexpected keyword argument 'mode'``). So each rule
here edits two places: the ``render`` call and the ``gym.make`` that created that env,
found through ``gymmigrate.facts.creation``.

* GM401 ``env.render(mode="rgb_array")`` -> ``render_mode="rgb_array"`` at the make and
  ``env.render()``. One env rendered in two modes, a make that already has another
  mode, or an env whose make cannot be found: reported, not rewritten (the fix is two
  envs, e.g. a training env and an eval env).
* GM402 bare ``env.render()`` (legacy default ``"human"``) -> ``render_mode="human"`` at
  the make. The call stays: "human" envs now draw inside ``step()``/``reset()``, so the
  call is redundant, and the review item says so; but an env class of the run that draws
  in ``render()`` alone (``ProjectView.draws_only_in_render``) still draws only there, and
  the note says the call is what draws.
* GM403 gym 0.25's ``"single_rgb_array"`` -> ``"rgb_array"``; in a file written for 0.25
  a ``"rgb_array"`` render returned a list of frames, and is reported.
* GM406 ``env.render(close=True)`` -> ``env.close()``.
* GM407 ``RecordVideo``, ``gymnasium.utils.play.play`` and SB3 ``VecVideoRecorder`` need
  ``render_mode="rgb_array"`` on the make that feeds them; so does a legacy ``Monitor``
  that records videos, which the wrapper family replaces by ``RecordVideo`` (GM611) in
  the same run.
  Bare legacy renders of the same make do not block it: the recorder raises without a
  frame mode, a bare ``render()`` is Gymnasium's API in any mode, and once migrated nothing
  says it meant "human" (a second run would add the mode), so the make gets "rgb_array"
  and each bare render is asked about (GM402: it returns a frame now). A recorder that
  never runs as the code stands (a switch bound once to False) leaves the make to the
  renders that run.

Receivers go through ``facts.decisions.decide``: Stable-Baselines3 VecEnvs keep
``vec_env.render("human")`` (SB105, their 2.x API) and PettingZoo envs are left alone.
A make that already has ``render_mode`` is not given another (idempotence).

One make, one ``render_mode``, whichever family adds it: ``notes.render_modes_added``
is a dict ``{id(ast.Call): mode}`` of the creation calls given a ``render_mode`` in this
run. A family that adds one (the wrapper family may, where ``Monitor`` becomes
``RecordVideo``) records it there; this family (``after = ("WrapperRenames",)``)
treats a noted make as already having that mode, adds none of its own, and records
every make it gives a mode.
Sources: gym 0.25/0.26 release notes ("Env.Render", "Render modes"); Gymnasium
``core.py::Env.render``, ``wrappers/rendering.py::RecordVideo``, ``utils/play.py``.

Where each part lives:

* ``family.py``: ``Rendering``, the family (``may_fire``, ``decide``).
* ``sites.py``: the render calls (GM401, GM402 sites; GM406 ``render(close=True)``).
* ``recorders.py``: GM407, RecordVideo, ``play``, ``VecVideoRecorder``, a recording
  ``Monitor``, and the frames of SB3 VecEnvs.
* ``planning.py``: the sites planned make by make, each site's finding.
* ``env_uses.py``: where the env a make builds is stepped, drawn and passed.
* ``untraced.py``: renders of envs made out of the file's reach (another module, a
  Gym-only stack).
* ``makes.py``: the edits of make calls (``render_mode=``, its quotes, ``make``
  aliases, GM403 at a make).
* ``common.py``: catalog entries, modes, ``RenderSite`` and the shared state.

The syntax of render calls is ``rules/render_calls.py``; when a conditional render
runs, ``rules/render_schedule.py``.
"""

from gymmigrate.rules.rendering.common import RULES
from gymmigrate.rules.rendering.family import Rendering

__all__ = ["RULES", "Rendering"]
