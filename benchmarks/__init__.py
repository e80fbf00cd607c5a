"""Performance measurements (not run by ``make test``): one module per benchmark, each with ``main() -> int``."""
