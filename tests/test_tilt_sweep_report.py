"""The case-1 report's tilting-stiffness section reads the sweep `make case1-sweep` writes:
a row per value with each moment beside its closed form, the variants without results named,
and a line saying how to make it where it has not been run."""

from studies.files import write_json
from studies.paper.tilt_sweep import SWEEP, sweep_section
from studies.sweep import CLOSED_FORM, sweep_folder


def _variant(label, value, q=None):
    run = {"sizes": "L0P1", "positions": 1, "root_stress": None}
    return {"value": value, "label": label, "quantities": q, "run": run if q else None}


def test_the_section_reads_the_sweep_and_names_what_is_missing(tmp_path):
    report_dir = tmp_path / "case1"
    assert "`make case1-sweep`" in " ".join(sweep_section(tmp_path, report_dir))
    q = {"ZS": -3.3, "ZR": 3.87, "Mx_pin": 15.0, "My_pin": 213.8, "M_LOA_sun": 91.6}
    q |= {"M_LOA_ring": -71.8, "My_pin" + CLOSED_FORM: 218.8, "Mx_pin" + CLOSED_FORM: 7.8}
    q |= {"M_LOA_sun" + CLOSED_FORM: 86.8, "M_LOA_ring" + CLOSED_FORM: -80.4}
    variants = [_variant("8.8e7", 8.8e7, q), _variant("8.8e8", 8.8e8)]
    folder = sweep_folder(tmp_path, *SWEEP)
    folder.mkdir(parents=True)
    write_json(folder / "sweep.json", {"case": "1-GB", "field": SWEEP[1], "variants": variants})
    text = "\n".join(sweep_section(tmp_path, report_dir))
    assert "| 8.8e7 | -3.30 | +3.87 | 15.0 / 7.8 (+92%) | 213.8 / 218.8 (-2%) |" in text
    assert "No results for 8.8e8" in text and "Run: L0P1, 1 position(s)." in text
    assert "](../sweeps/1-GB/bearing.tilting_stiffness/sweep.png)" in text
