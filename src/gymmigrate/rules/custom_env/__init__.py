"""Custom ``Env`` subclasses (GM404, GM405, GM501-GM504, GM507-GM509, GM511).

* ``metadata.py``      GM404 metadata keys (and a missing ``render_fps``)
* ``reward_range.py``  GM507 reads of the removed ``reward_range``
* ``env_class.py``     the family that migrates each env class's methods, deciding with
  ``seed.py`` (GM503), ``reset.py`` (GM501, GM502; a reset that returns nothing on some
  path in ``reset_none.py``), ``step.py`` (GM504; the
  step limits in a done in ``step_limits.py``, a done from another step in
  ``step_delegates.py``),
  ``render.py`` (GM405), ``observations.py`` (GM508, GM509) and ``spaces.py`` (GM511), with ``hooks.py`` (a
  hook ``step``/``reset`` returns migrates with its overrides, or none does); ``rebuild.py`` and
  ``cst_edits.py`` carry the decisions out on the class's LibCST node.
"""

from gymmigrate.rules.custom_env import env_class, metadata, reward_range  # noqa: F401  (register the families)
