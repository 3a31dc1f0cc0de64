"""Using wrappers: renamed, changed and removed wrappers, and attribute forwarding.

Two families, both deciding on the original source:

* ``renames.WrapperRenames`` (GM608-GM615): renamed wrappers in imports, paths
  and uses (GM608, GM612, GM614), changed signatures (GM609, ``arguments.py``;
  subclasses of TimeLimit, ``time_limit_subclasses.py``), removed wrappers (GM610),
  ``Monitor`` -> ``RecordVideo`` with its render mode (GM611, ``monitor.py``; what else
  uses gym's Monitor, ``monitor_consumers.py``), single-env wrappers on vector envs
  (GM613) and AtariPreprocessing's frame skip (GM615). ``wrapper_imports.py`` decides
  what the wrapper imports become and ``import_edits.py`` rewrites them, ``stacks.py``
  follows wrapper stacks down to the env they wrap, and ``legacy_imports.py`` tells
  which gym imports the imports rules leave alone in the same run.
* ``forwarding.WrapperForwarding`` (GM604-GM606): what legacy code read through
  ``Wrapper.__getattr__``. ``origins.py`` tells where an env comes from and which
  wrapper is outermost, ``bare_make.py`` which names hold a bare make result;
  ``make_layers.py`` decides ``.env`` chains and ``isinstance(env, TimeLimit)`` (GM606),
  ``self_forwarding.py`` ``self.x`` in a wrapper's own methods, ``getattr_hasattr.py``
  lookups by a name held in a value, ``monitor_attributes.py`` ``env.videos`` and
  ``env.monitor``, ``builtin_attributes.py`` what Gymnasium's built-in envs no longer
  have, ``atari_api.py`` the calls of gym's AtariEnv's methods ale-py's renamed; ``forwarding_edits.py`` builds the rewrites, and
  ``atari_limits.py`` answers the Atari time-limit questions of GM605, GM606 and GM609.

``tables.py`` holds what Gymnasium 1.x did to each wrapper, shared by both.
"""

from gymmigrate.rules.wrapper_usage import forwarding, renames  # noqa: F401  (imported to register the families)
