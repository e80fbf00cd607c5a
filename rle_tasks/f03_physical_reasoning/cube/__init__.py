"""Task ``03-pocket-cube``: the physical pocket cube (model, move model, state reading, distances,
scoring), the two-arm scene and metered environment, the verifier and the TaskSpec. See README.md.
"""
