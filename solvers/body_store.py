"""Elastic bodies kept across mesh positions and study cases.

A mesh position turns every gear rigidly about its own axis, so a body assembled in its own
frame has the same stiffness at every position: one factorization per (mesh, degree,
Poisson ratio, supports) serves them all. Bearing springs act on rigid unknowns outside the
body (:mod:`solvers.contact`), so cases that differ only in bearing stiffness share the
bodies too, and so do gear sets of another Young's modulus (K is linear in E:
:mod:`solvers.modulus_scaling`). ``BodyStore(reuse=False)`` builds every body afresh (the
reference the reuse is tested against).

Memory: a factorization is the largest object of a run (a level-1 system scene holds about
9 GB of them), so the store keeps at most as many objects as the previous position used:
when a case brings new bodies (other meshes), each new one replaces the least recently
used object the current position does not need, instead of piling up beside it.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Hashable


class BodyStore:
    """Set-up :class:`solvers.elastic_body.ElasticBody` objects by key, and the loaded
    meshes they stand on (:attr:`mesh_memo` for :func:`meshing.scene_bodies.load_body_meshes`)."""

    def __init__(self, reuse: bool = True):
        self.reuse = reuse
        self._bodies: OrderedDict[Hashable, object] = OrderedDict()  # least recent first
        self._meshes: dict = {}
        self._previous: set[Hashable] = set()
        self._current: set[Hashable] = set()
        self.built = 0
        self.reused = 0
        self.evicted = 0

    def __len__(self) -> int:
        """The number of objects held."""
        return len(self._bodies)

    def begin_position(self) -> None:
        """Start a new mesh position: the objects the last one used set the store's size."""
        if self._current:
            self._previous = self._current
        self._current = set()

    def _evict_for_new(self) -> None:
        limit = max(len(self._previous), 1)
        while len(self._bodies) >= limit:
            old = next((k for k in self._bodies if k not in self._current), None)
            if old is None:
                return
            del self._bodies[old]
            self.evicted += 1

    def objects(self) -> list:
        """The objects held, least recently used first."""
        return list(self._bodies.values())

    @property
    def mesh_memo(self) -> dict | None:
        """The memo of loaded meshes (None without reuse: every mesh is loaded again)."""
        return self._meshes if self.reuse else None

    def keep(self, key: Hashable, make: Callable[[], object]):
        """The object stored under ``key``, made by ``make()`` the first time (every time
        without reuse)."""
        self._current.add(key)
        if self.reuse and key in self._bodies:
            self.reused += 1
            self._bodies.move_to_end(key)
            return self._bodies[key]
        if self.reuse:
            self._evict_for_new()
        obj = make()
        self.built += 1
        if self.reuse:
            self._bodies[key] = obj
        return obj

    def body(self, key: Hashable, make: Callable[[], object]):
        """The set-up body stored under ``key``, made by ``make()`` and set up (assembled,
        factorized) the first time."""

        def made():
            b = make()
            b.setup()
            return b

        return self.keep(key, made)
