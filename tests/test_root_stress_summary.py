"""The root stress of a summary is the maximum over the mesh cycle (postprocess.summary.
cycle_bending), and the report section prints it beside ISO (postprocess.stress_tables)."""

import pytest

from cases.study_case import load_study_case
from postprocess.mesh_stress import iso_root_stress_factors
from postprocess.stress_tables import contact_section, root_section
from postprocess.summary import cycle_bending
from solvers.root_submodel import most_loaded, read_for


def _pos(roll, sun, ring, tan, cell, set_keys=None, position=0):
    keys = {"sun": "sun", "ring": "ring"} if set_keys is None else set_keys
    names = list(keys)
    locs = {k: {"tooth": 3, "side": "pos", "z_mm": 1.5 * roll, "set_key": keys[k]} for k in names}
    bs = {
        names[0]: sun,
        names[1]: ring,
        "tangent": dict(zip(names, tan, strict=True)),
        "cell_max": dict(zip(names, cell, strict=True)),
        "locations": locs,
    }
    return {"position": position, "roll": roll, "bending_stress": {**bs, "method": "x"}}


def test_maximum_over_the_cycle_and_where():
    # positions 0, 2 and 3 of the cycle finished (1 failed): "position" is the cycle's index,
    # not the index among the finished ones
    recs = [
        _pos(0.0, 500.0, None, (480.0, None), (400.0, None), position=0),
        _pos(0.1, 520.0, 300.0, (470.0, 290.0), (410.0, 250.0), position=2),
        _pos(0.2, 510.0, 310.0, (490.0, 280.0), (390.0, 260.0), position=3),
    ]
    out = cycle_bending(recs)
    assert out["bending_stress"] == {"sun": 520.0, "ring": 310.0}  # not the mean
    assert out["bending_stress_tangent"] == {"sun": 490.0, "ring": 290.0}
    assert out["bending_stress_cell"] == {"sun": 410.0, "ring": 260.0}
    assert out["bending_stress_at"]["sun"]["position"] == 2
    want = {"position": 3, "roll": 0.2, "tooth": 3, "side": "pos", "z_mm": pytest.approx(0.3)}
    assert out["bending_stress_at"]["ring"] == want
    assert "bending_stress_set" not in out  # one branch: the keys are the gear set's
    assert cycle_bending([{"roll": 0.0}])["bending_stress"] is None


def test_planets_are_reduced_to_gear_set_keys():
    keys = {"sun_pinion1_side": "sun", "sun_pinion2_side": "sun"}
    recs = [_pos(0.0, 500.0, 530.0, (1, 1), (1, 1), keys)]
    assert cycle_bending(recs)["bending_stress_set"] == {"sun": 530.0}


def test_the_most_loaded_planet_is_read_and_stands_for_its_gear():
    """The system scene reads one planet mesh per gear and side at each position (the most
    loaded, solvers.root_submodel.most_loaded), the others None: the set's value is the
    largest over the positions of whichever planet was read, and names it."""
    keys = {"sun_pinion1_side": "sun", "sun_pinion2_side": "sun"}
    recs = [
        _pos(0.0, None, 530.0, (None, 510.0), (None, 1), keys),
        _pos(0.1, 545.0, None, (520.0, None), (1, None), keys),
    ]
    out = cycle_bending(recs)
    assert out["bending_stress_set"] == {"sun": 545.0}
    assert out["bending_stress_tangent_set"] == {"sun": 520.0}
    assert out["bending_stress_set_key"] == {"sun": "sun_pinion1_side"}
    assert out["bending_stress"] == {"sun_pinion1_side": 545.0, "sun_pinion2_side": 530.0}


def test_most_loaded_reads_one_key_per_gear_set_key():
    to_set = {
        "sun_pinion1_side": "sun",
        "sun_pinion2_side": "sun",
        "sun_pinion3_side": "sun",
        "ring_pinion1_side": "ring",
        "ring_pinion2_side": "ring",
    }
    load = {
        "sun_pinion1_side": 9.0,
        "sun_pinion2_side": 10.0,
        "sun_pinion3_side": 10.0,
        "ring_pinion1_side": 7.0,
        "ring_pinion2_side": 6.0,
    }
    read = most_loaded(to_set, load)
    assert read == {"sun_pinion2_side", "ring_pinion1_side"}  # a tie: the first one
    assert read_for("sun_pinion3_side", to_set, read) == "sun_pinion2_side"
    # one branch: every key is its own gear-set key, and every key is read
    assert most_loaded({"sun": "sun", "ring": "ring"}, {"sun": 1.0, "ring": 0.0}) == {"sun", "ring"}


def test_report_sections_print_fe_beside_iso():
    gs = load_study_case("1-GA").gearset
    iso = iso_root_stress_factors(gs)
    s = {
        "level": 1,
        "degree": 1,
        **cycle_bending([_pos(0.0, 600.0, 450.0, (580.0, 440.0), (500.0, 300.0))]),
        "bending_stress_iso6336": iso,
        "bending_stress_iso6336_nominal": {k: v["sigma_F0"] for k, v in iso.items()},
    }
    text = "\n".join(root_section({"1-GA": s}, ("sun", "ring"), ["1-GA"]))
    sun = iso["sun"]["sigma_F0"]
    assert f"| 1-GA | 1 / 1 | sun | 600 | 3, pos, +0.0 | - | 580 | 500 | {sun:.0f} (" in text
    assert f"| {600 / sun:.2f} | {580 / sun:.2f} |" in text
    assert "| | ring | 450 |" in text
    # where: Z = -z (scene), the axis of ZS / ZR; z = 1.5 mm at roll 1 prints Z = -1.5
    s1 = {**s, **cycle_bending([_pos(1.0, 600.0, 450.0, (580.0, 440.0), (500.0, 300.0))])}
    assert "| sun | 600 | 3, pos, -1.5 |" in "\n".join(
        root_section({"1-GA": s1}, ("sun",), ["1-GA"])
    )
    assert iso["ring"]["internal"] and not iso["sun"]["internal"]
    # a summary without the contact cycle prints no row, and old summaries do not fail
    assert len(contact_section({"1-GA": {}}, ("sun_pinion",), ["1-GA"])) > 5
    assert root_section({"old": {"bending_stress": {"sun": 1.0}}}, ("sun",), ["old"])
    # with a convergence study's uncertainty, the ± beside the FE values (issue 13)
    s["uncertainty"] = {"bending_stress.sun": 0.25, "bending_stress_tangent.sun": 0.1}
    text = "\n".join(root_section({"1-GA": s}, ("sun", "ring"), ["1-GA"]))
    assert "| sun | 600 ± 150 | 3, pos, +0.0 | - | 580 ± 58 | 500 |" in text
    assert "| | ring | 450 |" in text  # no uncertainty for it: no ±


def test_recovered_values_are_carried_over_the_cycle():
    """The recovered surface and ISO-line values (solvers.surface_recovery) are maxima over
    the positions like the nodal ones; a position from before them adds nothing, and runs
    with none give None per key."""
    recs = [
        _pos(0.0, 500.0, 300.0, (480.0, 290.0), (400.0, 250.0)),
        _pos(0.1, 520.0, 310.0, (470.0, 280.0), (410.0, 260.0)),
        _pos(0.2, 530.0, 305.0, (475.0, 285.0), (405.0, 255.0)),
    ]
    for r, (sun, ring) in zip(recs[:2], ((490.0, 295.0), (505.0, 290.0)), strict=True):
        locs = r["bending_stress"]["locations"]
        locs["sun"]["recovered"] = {
            "value": sun,
            "tangent": sun - 20.0,
            "tooth": 4,
            "side": "neg",
            "z_mm": 2.0 + r["roll"],
        }
        locs["ring"]["recovered"] = {
            "value": ring,
            "tangent": None,
            "tooth": 1,
            "side": "pos",
            "z_mm": -1.0,
        }
    out = cycle_bending(recs)
    assert out["bending_stress_recovered"] == {"sun": 505.0, "ring": 295.0}
    assert out["bending_stress_tangent_recovered"] == {"sun": 485.0, "ring": None}
    # where the recovered maximum sits: its own tooth, side and z (not the nodal one's)
    at = out["bending_stress_recovered_at"]
    assert at["sun"] == {"position": 0, "roll": 0.1, "tooth": 4, "side": "neg", "z_mm": 2.1}
    assert at["ring"] == {"position": 0, "roll": 0.0, "tooth": 1, "side": "pos", "z_mm": -1.0}
    assert out["bending_stress_at"]["sun"]["tooth"] == 3
    old = cycle_bending(recs[2:])
    assert old["bending_stress_recovered"] == {"sun": None, "ring": None}
    assert "bending_stress_recovered_at" not in old


def test_report_prints_the_recovered_reading_beside_the_nodal_one():
    gs = load_study_case("1-GA").gearset
    iso = iso_root_stress_factors(gs)
    recs = [
        _pos(0.0, 600.0, 450.0, (580.0, 440.0), (500.0, 300.0)),
        _pos(1.0, 590.0, 455.0, (585.0, 445.0), (500.0, 300.0)),
    ]
    for r, v in zip(recs, (588.0, 594.0), strict=True):
        r["bending_stress"]["locations"]["sun"]["recovered"] = {
            "value": v,
            "tangent": v - 10.0,
            "tooth": 2,
            "side": "pos",
            "z_mm": 1.5 * r["roll"],
        }
    s = {
        "level": 1,
        "degree": 1,
        **cycle_bending(recs),
        "bending_stress_iso6336": iso,
        "bending_stress_iso6336_nominal": {k: v["sigma_F0"] for k, v in iso.items()},
        "uncertainty": {"bending_stress_recovered.sun": 0.02},
    }
    text = "\n".join(root_section({"1-GA": s}, ("sun", "ring"), ["1-GA"]))
    # the sun's recovered maximum (position 1, Z = -1.5) with its ±, its ratio to ISO's
    # sigma_F0, and the ratios to the nodal maxima 600 (surface) and 585 (line): 594 / 600,
    # 584 / 585
    sig = iso["sun"]["sigma_F0"]
    row = f"| 1-GA | sun | 594 ± 12 | 2, pos, -1.5 | 584 | {sig:.0f} | {594 / sig:.2f} | 0.99 |"
    assert row + " 1.00 |" in text
    # the reported reading first, the nodal maxima after it as a check
    reported, nodal = text.split("Reported: the recovered reading")[1].split("Nodal maxima")
    assert "| | ring |" not in reported and "| | ring |" in nodal  # no recovered ring value
    # summaries without the recovered reading print no such table
    old = {"level": 1, "degree": 1, **cycle_bending(recs[:1])}
    old["bending_stress_recovered"] = {"sun": None, "ring": None}
    plain = "\n".join(root_section({"x": old}, ("sun",), ["x"]))
    assert "recovered reading" not in plain and "Nodal maxima" not in plain


def test_recovered_values_are_reduced_to_gear_set_keys():
    keys = {"sun_pinion1_side": "sun", "sun_pinion2_side": "sun"}
    recs = [_pos(0.0, 500.0, 530.0, (1, 1), (1, 1), keys)]
    locs = recs[0]["bending_stress"]["locations"]
    locs["sun_pinion1_side"]["recovered"] = {"value": 520.0, "tangent": 470.0}
    locs["sun_pinion2_side"]["recovered"] = {"value": 510.0, "tangent": 480.0}
    out = cycle_bending(recs)
    assert out["bending_stress_recovered_set"] == {"sun": 520.0}
    assert out["bending_stress_recovered_set_key"] == {"sun": "sun_pinion1_side"}
    assert out["bending_stress_tangent_recovered_set"] == {"sun": 480.0}
    assert out["bending_stress_set_key"] == {"sun": "sun_pinion2_side"}  # the nodal one's


def test_a_value_kept_apart_beside_a_load_is_reported():
    """The largest fillet value within one element of a contact point force
    (solvers.root_stress near_load) is carried over the cycle and named in the report where
    it exceeds the reported maximum."""
    recs = [
        _pos(0.0, 500.0, 300.0, (480.0, 290.0), (400.0, 250.0)),
        _pos(0.1, 520.0, 310.0, (470.0, 280.0), (410.0, 260.0)),
    ]
    recs[0]["bending_stress"]["locations"]["sun"]["near_load"] = 900.0
    recs[1]["bending_stress"]["locations"]["sun"]["near_load"] = 100.0
    recs[1]["bending_stress"]["locations"]["ring"]["near_load"] = 200.0
    out = cycle_bending(recs)
    assert out["bending_stress_near_load"] == {"sun": 900.0, "ring": 200.0}
    s = {"level": 1, "degree": 1, **out, "bending_stress_method": "P2 submodel"}
    text = "\n".join(root_section({"1-GB-R": s}, ("sun", "ring"), ["1-GB-R"]))
    assert "reported maximum at 1-GB-R sun 900 (reported 520)." in text
    s["bending_stress_near_load"] = {"sun": 100.0, "ring": None}
    text = "\n".join(root_section({"x": s}, ("sun", "ring"), ["x"]))
    assert "reported maximum at no row of the table." in text
    del s["bending_stress_near_load"]  # a summary from before the rule: no claim either way
    assert "Beside a load" not in "\n".join(root_section({"x": s}, ("sun",), ["x"]))


def test_correction_note_reports_the_clipped_body_correction():
    """The case reports say how much of the zone model's FE body correction was clipped
    (eq. (6)), per run; runs without the entry (line grid, older summaries) say nothing."""
    from postprocess.stress_tables import correction_note

    runs = {
        "1-GA": {"contact_correction_clipped": 0.0612},
        "1-GB": {"contact_correction_clipped": None},
    }
    text = " ".join(correction_note(runs))
    assert "eigenvalue: 1-GA 0.06 (0: nothing" in text
    assert "What the clip moved" not in text  # a summary from before the measure: no claim
    runs["1-GA"]["contact_correction_clip_effect"] = 4.0e-6
    assert "warns above 0.1 %): 1-GA 4.0e-06." in " ".join(correction_note(runs))
    assert correction_note({"x": {}}) == []


def test_the_quoted_root_stress_is_one_reading_for_every_gear():
    """Reports quote the recovered reading where it covers every gear with a nodal maximum;
    a gear whose recovery is missing makes the whole summary quote the nodal maxima, so the
    maximum over the gears never drops a gear (the ring's 800 MPa here) unseen."""
    from postprocess.stress_tables import reported_root_stress

    s = {
        "bending_stress": {"sun": 600.0, "ring": 800.0, "locations": {}},
        "bending_stress_recovered": {"sun": 590.0, "ring": 780.0},
    }
    assert reported_root_stress(s) == ("bending_stress_recovered", {"sun": 590.0, "ring": 780.0})
    s["bending_stress_recovered"]["ring"] = None
    assert reported_root_stress(s) == ("bending_stress", {"sun": 600.0, "ring": 800.0})
    assert reported_root_stress({"bending_stress": None}) == ("bending_stress", {})
