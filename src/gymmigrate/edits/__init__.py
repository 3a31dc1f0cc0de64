"""Edits: rules record them against ``ast`` nodes (``plan``); one traversal applies them (``apply``)."""
