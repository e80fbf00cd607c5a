"""Task ``03-tower``: the tallest stable tower of twelve mixed pieces (README.md)."""
