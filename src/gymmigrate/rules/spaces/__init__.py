"""Spaces whose constructors, values and comparisons changed in Gymnasium 1.x (``drift.py``)."""

from gymmigrate.rules.spaces import drift  # noqa: F401  (register the family)
