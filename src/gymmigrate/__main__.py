"""Allow ``python -m gymmigrate``.

``python -m`` puts the current folder first on ``sys.path``, and that folder is usually
the project being migrated: a ``typer.py``, ``rich/`` or ``libcst/`` of its own would
be imported, and run, in place of gymmigrate's dependencies. gymmigrate never needs
modules from the current folder, so that entry goes before anything else is imported.
"""

import os
import sys

if sys.path and not getattr(sys.flags, "safe_path", False) and sys.path[0] in ("", os.getcwd()):
    del sys.path[0]

from gymmigrate.cli import main  # noqa: E402  (after the sys.path fix above, on purpose)

if __name__ == "__main__":
    main()
