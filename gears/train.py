"""Names along a gear train: one key per gear and mesh it takes part in.

A gear in one mesh is named by itself (``sun``, ``ring``); a gear in two meshes (a pinion)
carries load on different teeth at each and is named per mate, ``<gear>_<mate>_side``
(``pinion_sun_side``, ``pinion_ring_side``; ``SP_sun_side``, ``SP_RP_side``, ...). Root
stresses (FE and ISO 6336-3) are reported under these keys."""

from __future__ import annotations

from collections.abc import Sequence


def mesh_side_keys(meshes: Sequence[tuple[str, str]]) -> list[tuple[str, str, str, int]]:
    """``(key, gear, mate, i)`` for gear i (1: driver, 2: driven) of every mesh
    ``(driver, driven)``, in mesh order."""
    count: dict[str, int] = {}
    for a, b in meshes:
        count[a] = count.get(a, 0) + 1
        count[b] = count.get(b, 0) + 1
    out = []
    for a, b in meshes:
        for gear, mate, i in ((a, b, 1), (b, a, 2)):
            key = gear if count[gear] == 1 else f"{gear}_{mate}_side"
            out.append((key, gear, mate, i))
    return out
