"""Spaces whose constructors, values and comparisons changed in Gymnasium 1.x (``drift.py``,
loaded by the pipeline when a file may need it)."""
