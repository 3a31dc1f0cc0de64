"""Wrapper subclasses: ``reset`` and ``step`` overrides keep Gymnasium's contract (GM601-GM603), record their
constructor arguments (GM617) and stop reading state gym-era bases kept (GM618).

Gymnasium 0.26 changed ``Wrapper.reset`` to return ``(obs, info)`` and ``Wrapper.step``
to return ``(obs, reward, terminated, truncated, info)``; every wrapper that overrides
them must return the new shapes, or the next wrapper up (``TimeLimit`` from
``gym.make`` first) fails with "not enough values to unpack".

The reset family (ORDER 50) and the step family (ORDER 55) rewrite the *calls* inside the
overrides (``obs, info = self.env.reset(**kwargs)``, ``obs, reward, terminated, truncated,
info = self.env.step(action)`` plus ``done = terminated or truncated`` when ``done`` is
read later) and say so in ``notes`` (``reset_info_names``, ``step_unpacks``: ``rules/notes.py``). This
family (ORDER 60), deciding on the same original source, fixes what the override itself
returns:

* GM601 (ASSIST) ``reset`` returns ``(obs, info)``: ``return self._process(obs)`` ->
  ``return self._process(obs), info`` with the info of the inner reset (``{}`` when the
  override has none, e.g. baselines' FireResetEnv, which resets and then steps).
  Pass-throughs (``return self.env.reset(**kwargs)``) stay. A ``def reset(self)`` gets
  Gymnasium's ``*, seed=None, options=None`` keywords, because outer wrappers always pass them.
* GM602 (AUTO, ASSIST when the override changes ``done`` itself) ``step`` returns five
  values: ``return obs, reward, done, info`` -> ``return obs, reward, terminated,
  truncated, info``, with the names of the five-target unpack; the inserted ``done = ...``
  line is dropped when nothing reads ``done`` any more.
* GM603 (FLAG) ``__init__`` that never calls ``super().__init__(env)``: Gymnasium's
  ``Wrapper.__init__`` sets up ``env`` and the space/metadata properties.

* GM617 (AUTO) a wrapper whose ``__init__`` takes arguments besides the env records them
  with ``RecordConstructorArgs`` (its own family, ``constructor_args``), so Gymnasium 1.x
  can recreate it from ``env.spec``.
* GM618 (FLAG) a subclass of gym's ``RecordEpisodeStatistics``/``NormalizeReward``/
  ``NormalizeObservation`` that reads ``self.num_envs``, ``self.t0``... which the 1.x
  single-env rewrites of those wrappers no longer set; (ASSIST) a ``RecordEpisodeStatistics``
  subclass whose ``step`` computes the statistics itself gets gym 0.26's ``__init__`` and
  ``reset`` state back (``episode_state``).

GM607 (``ActionWrapper.reverse_action``) is deliberately not a rule: a user definition
is harmless (Gymnasium just never calls it), so a finding would only add review noise.

A legacy call that those families leave alone (they never do for ``self.env`` or
``super()`` in a Gym wrapper) leaves the returns to fix by hand: four-value returns are
reported. Sources: Gymnasium ``core.py`` (``Wrapper.reset``/``step``/``__init__``);
migration guide "Step API" and "Reset".

Wrapper *usage* (attribute forwarding, renamed and removed wrappers, Monitor...) lives in
the ``wrapper_usage`` package, which ``rules/__init__.py`` imports so that its families register.

Modules: ``common`` (catalog entries, syntax helpers), ``step`` (GM602's decision, with
``step_inner``: what the override does with its inner step, ``step_ends``: the end
conditions it adds, and ``step_returns``: the returns built), ``reset`` (GM601),
``episode_state`` (GM618's restoration), ``family`` (the ``RuleFamily``: finds wrapper
classes, GM603, GM618).
"""

from gymmigrate.rules.wrappers.common import RULES
from gymmigrate.rules.wrappers.family import WrapperClasses

__all__ = ["RULES", "WrapperClasses"]
