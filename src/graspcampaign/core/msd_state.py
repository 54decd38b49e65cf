"""State vector of the MSD shell body: its layout, validation, and views of positions and velocities.

State layout
------------
``X`` is a flat float64 vector of length ``6 n`` that interleaves position and velocity per node
(the paper's ordering, §2.2)::

    X.reshape(n, 6) == [[x_0, y_0, z_0, vx_0, vy_0, vz_0],
                        [x_1, y_1, z_1, vx_1, vy_1, vz_1], ...]

so ``X[6 i : 6 i + 3]`` is the position of node ``i`` in W [m] and ``X[6 i + 3 : 6 i + 6]`` its
velocity [m/s]. :func:`positions_from_state`, :func:`velocities_from_state` return views,
:func:`state_from_positions` builds a state.

Shape letters: ``n`` nodes, ``s`` recorded samples.

References
----------
Eq. 5 (§2.2).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "check_state",
    "positions_from_state",
    "state_from_positions",
    "velocities_from_state",
]


# ----------------------------------------------------------------------------------------------
# State helpers
# ----------------------------------------------------------------------------------------------


def check_state(state, n_nodes: int) -> np.ndarray:
    """Validate a state vector and return it as float64 of shape (6 n,).

    Raises
    ------
    ValueError
        If the shape is not ``(6 n,)`` or an entry is not finite.
    """
    state = np.asarray(state, dtype=np.float64)
    if state.shape != (6 * n_nodes,):
        raise ValueError(f"state must have shape ({6 * n_nodes},) for n = {n_nodes}, got {state.shape}")
    if not np.all(np.isfinite(state)):
        raise ValueError("state contains non-finite values")
    return state


def positions_from_state(state) -> np.ndarray:
    """Return the (n, 3) node positions [m] of a (6 n,) or (s, 6 n) state (a view)."""
    state = np.asarray(state)
    return state.reshape(*state.shape[:-1], -1, 6)[..., :3]


def velocities_from_state(state) -> np.ndarray:
    """Return the (n, 3) node velocities [m/s] of a (6 n,) or (s, 6 n) state (a view)."""
    state = np.asarray(state)
    return state.reshape(*state.shape[:-1], -1, 6)[..., 3:]


def state_from_positions(positions, velocities=None) -> np.ndarray:
    """Stack (n, 3) positions [m] and velocities [m/s] (default zero) into a (6 n,) state."""
    positions = np.asarray(positions, dtype=np.float64)
    if positions.ndim != 2 or positions.shape[1] != 3:
        raise ValueError(f"positions must have shape (n, 3), got {positions.shape}")
    state = np.zeros((positions.shape[0], 6))
    state[:, :3] = positions
    if velocities is not None:
        velocities = np.asarray(velocities, dtype=np.float64)
        if velocities.shape != positions.shape:
            raise ValueError(
                f"velocities must have shape {positions.shape}, got {velocities.shape}"
            )
        state[:, 3:] = velocities
    return state.ravel()
