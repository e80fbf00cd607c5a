"""A harness whose manual points at a function that does not exist."""
