"""Task ``03-balance-coins``: find the heavy cube among nine with a two-pan balance (README.md)."""
