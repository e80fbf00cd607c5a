"""Task ``03-hidden-com``: three sealed boxes, name each one's ballast quadrant (README.md)."""
