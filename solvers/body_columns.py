"""A body's FE compliance between its contact points, kept in the body's own frame.

The contact compliance of eq. (5) of :mod:`solvers.contact` is a sum over bodies of

    S_b[i, j] = g_i^T K_b^{-1} g_j   (surface rows),   D_b[i, j] = d_i^T K_b^{-1} g_j,      (1)

g_i the gap-operator row of FE point i on body b (the patch-averaged normal displacement,
:mod:`solvers.gap_operator`) and d_i its row at the matching depth below it. Both depend on
the body alone: its mesh, degree, material, supports, held reference DOFs and linear solver
(the key of the :class:`solvers.body_store.BodyStore` that keeps it), and the rows' geometry
in the body's own frame. So a point's entries serve every problem that places the same row
on the same body, whatever the bearing, torque, penalty, other bodies or case: another case
of the gear set at the same mesh position, a sweep, a rerun in the same process.

:class:`BodyColumns` holds them. A *node* is one row geometry (the spreading points in the
body frame, their weights, the signed body-frame normal, and the depth row's point where the
problem has one), identified by those numbers rounded to :data:`KEY_QUANTUM` (a near miss
is computed again, never confused with another point). A column j is *known at* the rows
of a problem when every (row node, j) entry was formed: only then is it read instead of
solved, so an entry is always the solve it stands for. Entries are stored as the body's own
solve (a :class:`solvers.modulus_scaling.ScaledBody` divides them by its scale when read).

Memory: a column keeps its entries at the rows it was formed for; past
:data:`MAX_ENTRIES` entries the oldest columns are dropped (formed again when met again,
never wrong).
"""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

#: rounding of the node geometry (mm for points, 1 for normals and weights) in its key
KEY_QUANTUM = 1e-9
#: entries (S and D pairs) a body keeps at most, 16 bytes each: 160 MB at 1e7 (about 35
#: level-1 positions of a pinion's two meshes)
MAX_ENTRIES = 10_000_000


def node_keys(spread: np.ndarray, weights: np.ndarray, normal: np.ndarray, depth=None):
    """Byte keys of rows: ``spread`` (m, q, gdim) body-frame spreading points of each row,
    ``weights`` (m, q) their signed weights, ``normal`` (m, gdim) the body-frame normal and
    ``depth`` (m, gdim) the depth row's body-frame point (or None)."""
    parts = [spread.reshape(len(spread), -1), weights.reshape(len(spread), -1), normal]
    if depth is not None:
        parts.append(depth)
    q = np.rint(np.hstack(parts) / KEY_QUANTUM).astype(np.int64)
    return [r.tobytes() for r in q]


class BodyColumns:
    """The entries (1) of one body's columns, each at the row nodes it was formed for
    (replicated on every rank: every rank makes the same calls, so the same decisions)."""

    def __init__(self):
        self.index: dict[bytes, int] = {}
        self._cols: OrderedDict[int, tuple] = OrderedDict()  # node -> (rows, S, D), oldest first
        self.entries = 0

    def __len__(self) -> int:
        """The number of columns held."""
        return len(self._cols)

    def nodes(self, keys: list[bytes]) -> np.ndarray:
        """The node index of each key (new keys get new nodes)."""
        for k in keys:
            if k not in self.index:
                self.index[k] = len(self.index)
        return np.array([self.index[k] for k in keys], dtype=np.int64)

    def coverage(self, rows: np.ndarray, cols: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(held (len(cols),), missing (len(rows), len(cols))): whether column node j has
        entries, and which row nodes of ``rows`` it has none at."""
        held = np.zeros(len(cols), dtype=bool)
        missing = np.ones((len(rows), len(cols)), dtype=bool)
        for i, j in enumerate(cols):
            entry = self._cols.get(int(j))
            if entry is not None:
                r = entry[0]
                k = np.minimum(np.searchsorted(r, rows), len(r) - 1)
                held[i] = True
                missing[:, i] = r[k] != rows
        return held, missing

    def known_columns(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """(len(cols),) whether column node j was formed at every row node of ``rows``."""
        held, missing = self.coverage(rows, cols)
        return held & ~missing.any(axis=0)

    def read(self, rows: np.ndarray, cols: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(S[rows, cols], D[rows, cols]) of known columns (:meth:`known_columns`)."""
        S = np.empty((len(rows), len(cols)))
        D = np.empty((len(rows), len(cols)))
        for i, j in enumerate(cols):
            r, s, d = self._cols[int(j)]
            self._cols.move_to_end(int(j))
            k = np.searchsorted(r, rows)
            S[:, i], D[:, i] = s[k], d[k]
        return S, D

    def write(self, rows: np.ndarray, cols: np.ndarray, S: np.ndarray, D=None) -> None:
        """Keep the formed entries S[rows, cols] (and D: zero where the problem has no depth
        rows), replacing what a column held."""
        D = np.zeros_like(S) if D is None else D
        for i, j in enumerate(cols):
            old = self._cols.pop(int(j), None)
            if old is not None:
                self.entries -= len(old[0])
            self._put(int(j), np.asarray(rows, dtype=np.int64), S[:, i], D[:, i])

    def extend(self, col: int, rows: np.ndarray, S: np.ndarray, D=None) -> None:
        """Add entries of column node ``col`` at row nodes ``rows`` it had none at."""
        r, s, d = self._cols.pop(int(col))
        self.entries -= len(r)
        D = np.zeros_like(S) if D is None else D
        self._put(int(col), np.r_[r, rows], np.r_[s, S], np.r_[d, D])

    def _put(self, col: int, rows: np.ndarray, S: np.ndarray, D: np.ndarray) -> None:
        order = np.argsort(rows, kind="stable")
        self._cols[col] = (rows[order], np.array(S)[order], np.array(D)[order])
        self.entries += len(rows)

    def trim(self, keep: int = 0) -> None:
        """Drop the oldest columns past :data:`MAX_ENTRIES` entries, keeping the ``keep``
        most recently used."""
        while self.entries > MAX_ENTRIES and len(self._cols) > keep:
            _, (r_old, _, _) = self._cols.popitem(last=False)
            self.entries -= len(r_old)


def body_columns(body) -> BodyColumns:
    """The :class:`BodyColumns` of ``body`` (a view's: the body it stands on), made on first
    use and living as long as the body."""
    base = getattr(body, "_body", body)
    if getattr(base, "columns", None) is None:
        base.columns = BodyColumns()
    return base.columns


__all__ = ["KEY_QUANTUM", "MAX_ENTRIES", "BodyColumns", "body_columns", "node_keys"]
