"""A gear set that cannot be built says what to change (issue 57: "involute/fillet
interference" named the mesh but no way forward). Case 1's sun and pinion at other helix
angles and centre distances, the trials a new user makes."""

import pytest

from gears.pair import GearPair
from gears.spec import GearSpec, GeometryError


def pair(beta: float, a: float) -> GearPair:
    common = dict(normal_module=1.59, normal_pressure_angle=20.0, helix_angle=beta)
    sun = GearSpec("sun", 35, hand="right", face_width=32.35, **common)
    pinion = GearSpec("pinion", 26, hand="left", face_width=29.0, **common)
    return GearPair(sun, pinion, a)


def test_a_shift_the_centre_distance_cannot_give_names_the_way_to_the_standard_one():
    # 30 deg: a0 = 1.59 * 61 / (2 cos 30) = 55.997 mm; 51.945 asks for x = -1.84 (undercut)
    with pytest.raises(
        GeometryError,
        match=r"a larger centre_distance, towards the standard "
        r"55.997 mm",
    ):
        pair(30.0, 51.945)
    with pytest.raises(GeometryError, match=r"pointed tooth.*a smaller centre_distance"):
        pair(30.0, 59.2)


def test_no_tip_clearance_says_by_how_much_to_shorten_the_tip():
    # 35 deg, a = 56 mm: the sun's tip circle passes the pinion's root circle
    with pytest.raises(GeometryError) as err:
        pair(35.0, 56.0)
    msg = str(err.value)
    assert "no tip clearance" in msg and "lower sun.addendum_coef (by " in msg
    said = float(msg.split("lower sun.addendum_coef (by ")[1].split()[0])
    cut = float(msg.split("cuts pinion root circle by ")[1].split()[0])
    assert said >= cut / 1.59 and said - cut / 1.59 < 1e-3  # h_a* lowers the tip by m_n each
    # and following it clears the tip (the pair may still fail another check, not this one)
    common = dict(normal_module=1.59, normal_pressure_angle=20.0, helix_angle=35.0)
    sun = GearSpec("sun", 35, hand="right", face_width=32.35, addendum_coef=1 - said, **common)
    pinion = GearSpec("pinion", 26, hand="left", face_width=29.0, **common)
    try:
        GearPair(sun, pinion, 56.0)
    except GeometryError as exc:
        assert "sun tip circle cuts" not in str(exc), exc
