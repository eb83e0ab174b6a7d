"""The one table of physical-group names used by every mesh of the pipeline.

A name is ``"<body>"`` for the volume of a body and ``"<body>/<region>"`` for a surface:

========================================  =================================================
``<body>``                                the body's volume (one per body)
``<body>/tooth<NN>/flank_pos``            involute flank on the +theta side of tooth NN
``<body>/tooth<NN>/flank_neg``            involute flank on the -theta side of tooth NN
``<body>/tooth<NN>/fillet_pos``           root fillet (trochoid, plus half the root land
                                          when there is one) below ``flank_pos``
``<body>/tooth<NN>/fillet_neg``           the same below ``flank_neg``
``<body>/tooth<NN>/tip``                  tip land of tooth NN
``<body>/bore``                           bore of an external gear (sun, pinions)
``<body>/rim``                            outer cylinder of an internal gear (ring)
``<body>/end_zpos``, ``<body>/end_zneg``  transverse end faces at z = +b/2, -b/2
``<body>/cut_pos``, ``<body>/cut_neg``    sector cut faces at the +theta / -theta end
``carrier/pin<K>``                        cylindrical surface of pin K (carries the bearing)
``carrier/plate_zpos``, ``plate_zneg``    outer faces of the carrier plates
``carrier/hub_zpos``, ``hub_zneg``        inner (hub) cylinders of the carrier plates
``carrier/other``                         every other carrier surface
``<body>/other``                          every other surface of a gear (not expected)
========================================  =================================================

Tooth ``NN`` is the global tooth index of the full gear (tooth 0 is symmetric about the
body's +x axis at mid face width, tooth k is turned by 2 pi k / z), so a sector keeps the
names its teeth have in the full gear. ``pos``/``neg`` are geometric sides in the body
frame; which of them is the drive or the coast flank of a mesh is decided by the scene
(:mod:`meshing.scenes`), never here.

Integer tags are assigned when a model is built and are looked up by name (the ``names``
dict of :class:`meshing.to_dolfinx.MeshBundle`); no integer tag is fixed anywhere.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

SEP = "/"

# Surface kinds per tooth.
FLANK_POS = "flank_pos"
FLANK_NEG = "flank_neg"
FILLET_POS = "fillet_pos"
FILLET_NEG = "fillet_neg"
TIP = "tip"
TOOTH_KINDS = (FLANK_POS, FLANK_NEG, FILLET_POS, FILLET_NEG, TIP)
FLANKS = {"pos": FLANK_POS, "neg": FLANK_NEG}
FILLETS = {"pos": FILLET_POS, "neg": FILLET_NEG}

# Surface kinds per body.
BORE = "bore"
RIM = "rim"
END_ZPOS = "end_zpos"
END_ZNEG = "end_zneg"
CUT_POS = "cut_pos"
CUT_NEG = "cut_neg"
OTHER = "other"
BODY_KINDS = (BORE, RIM, END_ZPOS, END_ZNEG, CUT_POS, CUT_NEG, OTHER)

# Carrier.
CARRIER = "carrier"
PLATE_ZPOS = "plate_zpos"
PLATE_ZNEG = "plate_zneg"
HUB_ZPOS = "hub_zpos"
HUB_ZNEG = "hub_zneg"
CARRIER_KINDS = (PLATE_ZPOS, PLATE_ZNEG, HUB_ZPOS, HUB_ZNEG, OTHER)

_BODY_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
_TOOTH_RE = re.compile(r"^(?P<body>[A-Za-z][A-Za-z0-9_]*)/tooth(?P<idx>\d+)/(?P<kind>[a-z_]+)$")


def check_body_name(body: str) -> str:
    """Return ``body`` if it is a valid body name (letter first, then letters, digits, _)."""
    if not isinstance(body, str) or not _BODY_RE.match(body):
        raise ValueError(
            f"body name {body!r}: must start with a letter and contain only letters, "
            "digits and '_' (it is the first part of every tag name)"
        )
    return body


def volume(body: str) -> str:
    """Name of the volume group of ``body``."""
    return check_body_name(body)


def tooth(body: str, index: int, kind: str) -> str:
    """Name of surface ``kind`` (one of :data:`TOOTH_KINDS`) of tooth ``index`` of ``body``."""
    if kind not in TOOTH_KINDS:
        raise ValueError(f"tooth surface kind {kind!r}: must be one of {TOOTH_KINDS}")
    if int(index) != index or index < 0:
        raise ValueError(f"tooth index {index!r}: must be an integer >= 0")
    return f"{check_body_name(body)}{SEP}tooth{int(index):02d}{SEP}{kind}"


def flank(body: str, index: int, side: str) -> str:
    """Name of the involute flank on side ``"pos"``/``"neg"`` of tooth ``index``."""
    return tooth(body, index, FLANKS[side])


def fillet(body: str, index: int, side: str) -> str:
    """Name of the root fillet below the flank on side ``"pos"``/``"neg"``."""
    return tooth(body, index, FILLETS[side])


def surface(body: str, kind: str) -> str:
    """Name of a body-level surface (bore, rim, ends, sector cuts, other)."""
    if kind not in BODY_KINDS:
        raise ValueError(f"body surface kind {kind!r}: must be one of {BODY_KINDS}")
    return f"{check_body_name(body)}{SEP}{kind}"


def pin(index: int) -> str:
    """Name of the cylindrical surface of carrier pin ``index``."""
    return f"{CARRIER}{SEP}pin{int(index)}"


def carrier_surface(kind: str) -> str:
    """Name of a carrier surface, one of :data:`CARRIER_KINDS`."""
    if kind not in CARRIER_KINDS:
        raise ValueError(f"carrier surface kind {kind!r}: must be one of {CARRIER_KINDS}")
    return f"{CARRIER}{SEP}{kind}"


@dataclass(frozen=True)
class ParsedName:
    body: str
    tooth: int | None  # None for body-level names
    kind: str | None  # None for a volume name


def parse(name: str) -> ParsedName:
    """Split a tag name into body, tooth index and kind."""
    m = _TOOTH_RE.match(name)
    if m:
        return ParsedName(m["body"], int(m["idx"]), m["kind"])
    parts = name.split(SEP)
    if len(parts) == 1:
        return ParsedName(check_body_name(parts[0]), None, None)
    if len(parts) == 2:
        return ParsedName(check_body_name(parts[0]), None, parts[1])
    raise ValueError(f"not a tag name: {name!r}")
