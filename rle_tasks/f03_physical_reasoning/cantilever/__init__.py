"""Task ``03-cantilever``: the longest stable overhang of four blocks beyond the table edge (README.md)."""
