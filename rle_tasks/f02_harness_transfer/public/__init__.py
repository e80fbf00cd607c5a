"""Modules of family 02 that run beside submitted code (they import only the standard library)."""
