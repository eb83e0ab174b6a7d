"""Elastic bodies kept across mesh positions and study cases.

A mesh position turns every gear rigidly about its own axis, so a body assembled in its own
frame has the same stiffness at every position: one factorization per (mesh, degree,
material, supports) serves them all. Bearing springs act on rigid unknowns outside the body
(:mod:`solvers.contact`), so cases that differ only in bearing stiffness share the bodies
too. ``BodyStore(reuse=False)`` builds every body afresh (the reference the reuse is tested
against).
"""

from __future__ import annotations

from collections.abc import Callable, Hashable


class BodyStore:
    """Set-up :class:`solvers.elastic_body.ElasticBody` objects by key, and the loaded
    meshes they stand on (:attr:`mesh_memo` for :func:`meshing.scene_bodies.load_body_meshes`)."""

    def __init__(self, reuse: bool = True):
        self.reuse = reuse
        self._bodies: dict[Hashable, object] = {}
        self._meshes: dict = {}
        self.built = 0
        self.reused = 0

    @property
    def mesh_memo(self) -> dict | None:
        """The memo of loaded meshes (None without reuse: every mesh is loaded again)."""
        return self._meshes if self.reuse else None

    def keep(self, key: Hashable, make: Callable[[], object]):
        """The object stored under ``key``, made by ``make()`` the first time (every time
        without reuse)."""
        if self.reuse and key in self._bodies:
            self.reused += 1
            return self._bodies[key]
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
