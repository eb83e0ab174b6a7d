"""The one-page report checks the paper's conclusions on the paper's own study cases only
(postprocess.paper_cases): before, every one-branch single-pinion run under results/ was
pooled into them, a user's case file or an edited copy of a paper case too."""

import copy
import json

from cases.study_case import load_study_case, study_inputs
from postprocess.paper_cases import paper_case_difference


def _summary(name: str) -> dict:
    inputs = json.loads(json.dumps(study_inputs(load_study_case(name))))
    return {"case": name, "inputs": inputs}


def test_a_run_of_a_shipped_paper_case_counts_at_any_level():
    s = _summary("1-GB")
    s["inputs"]["study_case"]["model"]["level"] = 0  # a coarser run is still the paper's case
    s["inputs"]["study_case"]["numerics"]["zone_gap_limit_um"] = 200.0
    assert paper_case_difference(s) is None
    assert paper_case_difference(_summary("2B-GB")) is None


def test_an_edited_paper_case_or_another_gear_set_is_named_with_the_reason():
    s = _summary("1-GA")
    edited = copy.deepcopy(s)
    edited["inputs"]["study_case"]["bearing"]["tilting_stiffness"] = 1.0e7
    assert paper_case_difference(edited) == "its bearing differ(s) from cases/1-GA.toml"
    torque = copy.deepcopy(s)
    torque["inputs"]["gearset"]["input_torque"] *= 2
    torque["inputs"]["study_case"]["material"]["gear_modulus_factor"] = 0.5
    assert paper_case_difference(torque) == "its gear set, material differ(s) from cases/1-GA.toml"
    assert paper_case_difference(dict(s, case="my_single")) == "not one of the shipped study cases"
    parker = _summary("parker2000-3")
    assert (
        paper_case_difference(parker) == "cases/parker2000-3.toml is not on the paper's gear sets"
    )
    assert paper_case_difference({"inputs": {}}) == "no case name"
