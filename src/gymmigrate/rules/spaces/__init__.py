"""Spaces whose constructors, values and comparisons changed in Gymnasium 1.x (``drift.py``,
the family, with ``values.py``, ``type_checks.py``, ``json_writes.py``, ``sizes.py`` and ``shape_writes.py``;
loaded by the pipeline when a file may need it)."""
