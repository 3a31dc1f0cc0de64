"""Step and ``done`` semantics at call sites (GM301-GM304, GM703).

Since gym 0.26 ``step`` returns five values, ``(obs, reward, terminated, truncated,
info)``: ``terminated`` means the MDP reached a terminal state, ``truncated`` that the
episode was cut (usually by ``TimeLimit``). The legacy ``done`` was their ``or``
(Gymnasium release notes 0.26, "Step termination / truncation"; migration guide,
"Environment step").

* ``unpack``: GM301 / GM703 split the done flag of ``obs, r, done, info = env.step(a)``
  (vector envs with ``np.logical_or``), GM302 moves value reads of ``done`` to
  ``terminated``; the reads of ``done`` it plans are judged in ``next_state`` (what the
  step's next state is, which reads mask bootstrapping from it), ``read_uses`` (what else
  a read is for, where the code shows it), ``read_stores`` (where a read stores the flag),
  ``bookkeeping`` (reads that only keep an episode's books), ``read_settled`` (what the
  code around a read settles by its shape) and ``read_reports`` (the GM302 findings; with
  ``read_untraced``, for a step left unrewritten, and ``read_attributes``, for a ``done``
  stored in ``self``).
* ``time_limit``: GM303 ``info["TimeLimit.truncated"]`` -> ``truncated and not terminated``.
* ``results``: GM304 step results that are not unpacked.
* ``family``: the ``RuleFamily`` that finds the call sites and dispatches them;
  ``common``: catalog entries, flag names and the receiver decision they share.

The data flow (which reads a binding reaches) is ``gymmigrate.facts.flow``; what a read
of ``done`` is for is ``gymmigrate.facts.done_uses``.
"""

from gymmigrate.rules.step_done.common import RULES, TIME_LIMIT_KEY, StepNames
from gymmigrate.rules.step_done.family import StepDone

__all__ = ["RULES", "TIME_LIMIT_KEY", "StepDone", "StepNames"]
