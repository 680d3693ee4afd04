"""The linearised dynamics of a model about an equilibrium, ``E d(dz)/dt = A dz``, and its eigenvalues.

Apart from :mod:`._dynamics` (the seam: the :class:`~._dynamics.Dynamics` protocol and the choice of
dynamics for a model): this is the result both kinds of dynamics return, the ODE's and the mechanism's
(:mod:`._mechanism_dynamics`), so each imports it from here and neither imports the other.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["LinearDynamics", "NEUTRAL_RTOL"]

#: An eigenvalue's real part (or a sum of two eigenvalues) at most this times the largest ``|lambda|`` is rounding,
#: i.e. zero: the linearisation of an undamped conservative mechanism has its eigenvalues on the imaginary axis to
#: about 1e-15 of their size. The zero of ``n_unstable_dynamic`` and of the Hopf test function.
NEUTRAL_RTOL = 1e-9


@dataclass(frozen=True)
class LinearDynamics:
    """Small motions ``dz`` about an equilibrium: ``E d(dz)/dt = A dz``.

    Attributes
    ----------
    A:
        The state matrix (1/s in the rates' units), shape (n, n).
    E:
        The descriptor matrix, or None for the identity (an explicit ODE).
    names:
        The name of each state component (``z``'s order).
    """

    A: np.ndarray
    E: np.ndarray | None
    names: tuple[str, ...]

    def eigenvalues(self) -> np.ndarray:
        """The finite eigenvalues ``lambda`` (1/s) of ``A v = lambda E v``, largest real part first."""
        if self.E is None:
            lam = np.linalg.eigvals(self.A)
        else:
            import scipy.linalg

            alpha, beta = scipy.linalg.eig(self.A, self.E, right=False, homogeneous_eigvals=True)
            scale = np.maximum(np.abs(alpha), 1.0) * np.finfo(float).eps * max(1.0, np.linalg.norm(self.E, 1))
            finite = np.abs(beta) > scale
            lam = alpha[finite] / beta[finite]
        return lam[np.lexsort((-lam.imag, -lam.real))]
