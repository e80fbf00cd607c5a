"""Shipped solutions of 06-pose-c-learned (pinned checksums and golden quick scores).

- ``reference``: ``reference_c/model.pt``, trained from scratch by
  ``nice -n 10 python -m rle_tasks.f06_pose_estimation.train --steps 1500 --seed 0`` (``learned.py``).
- ``baseline/nan_output``: a model returning NaN (interface gate: non-finite output).
- ``baseline/big_model``: 25 M tensor elements (refused by the element count before inference).
"""

from rle_tasks.core.solutions import SolutionSet
from rle_tasks.f06_pose_estimation.solutions import PACKAGE, model_solutions

PINS = {
    "reference": ("25d6d63796216781838e495559c7d3b586ce457dde756114bc973d72735a3e6c", 0.895774),
    "baseline/nan_output": ("fb14917ff26fe0d21ca7f0789794ddd1909639fbde4dd9b35de53572710066f8", 0.0),
    "baseline/big_model": ("e6cbb0b7637563c34c699f892cc0794b2b8c26bb382bf9df166a343c2be7d04d", 0.0),
}
SOLUTIONS = SolutionSet(package=PACKAGE, solutions=model_solutions(PINS))
