"""Probe-pose selection: greedy D-optimal design on the gravity regressor.

Each probe pose q contributes the information ``Y(q)^T Y(q)`` about the base parameters. Greedy
D-optimality adds, one at a time, the candidate that maximises ``log det(A + Y_c^T Y_c)``, i.e.
``log det(I + Y_c A^-1 Y_c^T)`` (matrix determinant lemma), starting from the poses already measured.
"""

from __future__ import annotations

import numpy as np

__all__ = ["greedy_d_optimal", "information_logdet"]


def information_logdet(regressors: np.ndarray, eps: float = 1e-9) -> float:
    """log det(sum_i Y_i^T Y_i + eps I) of a set of regressors, shape (N, n, p)."""
    regressors = np.asarray(regressors, float)
    p = regressors.shape[-1]
    a = np.einsum("nip,niq->pq", regressors, regressors) + eps * np.eye(p)
    return float(np.linalg.slogdet(a)[1])


def greedy_d_optimal(
    candidates: np.ndarray, k: int, initial: np.ndarray | None = None, eps: float = 1e-6
) -> np.ndarray:
    """Pick ``k`` candidate indices greedily maximising the information determinant.

    Args:
        candidates: Candidate regressors, shape (M, n, p).
        k: Number of poses to pick (distinct).
        initial: Regressors already measured (e.g. the home pose), shape (r, n, p).
        eps: Regularisation of the information matrix (scale of the parameters' prior precision).

    Returns:
        Indices into ``candidates``, in the order chosen.
    """
    candidates = np.asarray(candidates, float)
    m, _, p = candidates.shape
    if k > m:
        raise ValueError(f"cannot pick {k} poses from {m} candidates")
    a = eps * np.eye(p)
    if initial is not None:
        init = np.asarray(initial, float)
        a = a + np.einsum("nip,niq->pq", init, init)
    chosen: list[int] = []
    free = np.ones(m, bool)
    for _ in range(k):
        a_inv = np.linalg.inv(a)
        # gain_c = log det(I + Y_c A^-1 Y_c^T) for every candidate at once
        s = np.einsum("cip,pq,cjq->cij", candidates, a_inv, candidates)
        s += np.eye(s.shape[1])
        gain = np.linalg.slogdet(s)[1]
        gain[~free] = -np.inf
        best = int(np.argmax(gain))
        chosen.append(best)
        free[best] = False
        a = a + candidates[best].T @ candidates[best]
    return np.array(chosen)
