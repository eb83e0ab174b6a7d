"""Physical plausibility of a study's results: numbers no gear could carry get a warning in
``summary.json`` (``warnings``) and on stderr instead of being reported silently.

The model is linear elastic with small displacements: its root stress grows in proportion
to the load and its Hertz stress with the square root, whatever the load, so a torque in
the wrong unit or a slip of the exponent (1e9 N m instead of 1e3) still gives numbers, e.g.
a contact stress of 5e6 MPa. The bounds below mark where the linear elastic model of a steel
gear is far outside its range; they are not design limits.

* Hertz contact stress 5000 MPa, on the mean over the loaded grid points of a mesh (the load
  level along the contact lines). Case-hardened gear steels have an endurance limit
  sigma_Hlim of 1300-1650 MPa (ISO 6336-5) and a static limit about 1.6 times that (life
  factor Z_NT), about 2600 MPa; subsurface yield in line contact starts at
  p_max = 1.67 sigma_y (Tresca), 3300 MPa even for a 2000 MPa case. Above 5000 MPa the flank
  has yielded deep under the surface. The bound is not applied to the peak, which sits at
  the unrelieved line ends (tip and face corners) where the line-contact formula overstates
  the stress: the paper's own flexible-bearing case 1-GC reaches a 5800 MPa peak there at
  level 0 with a mean of 2650 MPa. A gear material stiffer than steel (``material.
  gear_modulus_factor``, e.g. 1-GB-R) is checked at the steel-equivalent stress: Hertz
  stress at equal line load scales with sqrt(E*), so the value is divided by
  sqrt(E_gear / E_steel) (1-GB-R: 8400 MPa, 2650 MPa steel-equivalent).
* Root (fillet) stress 3000 MPa, on the largest value over the positions. The tooth-root
  endurance limit of case-hardened steels is sigma_FE = 850-1050 MPa (ISO 6336-5) and the
  static limit about 2.5 times that (Y_NT), 2100-2600 MPa, near the tensile strength of the
  case: above 3000 MPa the tooth has broken. 1-GC reaches 1700 MPa at level 0. Root stress
  at equal loads does not depend on E, so the bound is the same for any gear material.
* The zone model's body correction: where the FE's correction of a tooth pair is indefinite
  it is projected onto the positive semidefinite matrices (:mod:`solvers.contact` eq. (6)),
  and each solve measures what that moved (``timings.correction_clip_effect``). Above 0.1 %
  of the contact forces or of a pinion's motion the match of the half-space near field to
  the FE is not converged at that mesh: a model error the convergence ± does not hold.

The inputs are checked too (:func:`input_warnings`, said before the solve; the run goes on):

* A Poisson ratio above :data:`LOCKING_POISSON` on linear elements (``degree = 1``): P1
  tetrahedra lock in volume change as nu nears 0.5, so the bodies are too stiff.
* A line grid's penalty factor below :data:`PENALTY_FACTOR_USUAL`: the penalty springs'
  compliance, about 1/factor of the bodies', enters the answer.
* The length a bearing's two stiffnesses imply, L = sqrt(12 k_tilt / k_r) (a uniform row of
  springs of length L has k_tilt = k_r L^2 / 12), outside 2-200 mm: the paper's bearings give
  21 mm. One of the two is then most likely in another unit (N m/rad instead of N mm/rad).
* The torque, through each mesh's nominal contact stress sigma_H0 (ISO 6336-2 method B at
  the pitch point, every K factor 1, steel flanks: :func:`gears.contact_stress.
  iso6336_pitch_contact_stress`) outside 100-2600 MPa. 2600 MPa is the static limit of a
  case-hardened flank (sigma_Hlim 1650 MPa times the static life factor Z_NT 1.6, ISO
  6336-2/-5), which even the nominal stress without the K factors passes only with a torque
  in the wrong unit; the paper's sets reach 1900 MPa (2B-GA's SP-RP mesh), the phasing
  set 540 MPa. Below 100 MPa the mesh is all but unloaded (a hundredth of a design load):
  often N m given as kN m.
* A flank modification amount above 100 um (the validator allows 500): industrial
  micro-geometry is 5-60 um (lead crown C_b, tip relief C_a about 0.01-0.02 m_n, Niemann
  and Winter, Maschinenelemente II); a larger amount is most likely a slip of the
  unit or a different tooth form, not a modification.
"""

from __future__ import annotations

import math

from gears.contact_stress import iso6336_pitch_contact_stress
from gears.material import STEEL
from postprocess.mesh_stress import driver_torques

CONTACT_STRESS_LIMIT_MPA = 5000.0
ROOT_STRESS_LIMIT_MPA = 3000.0
#: the Poisson ratio above which P1 bodies lock (1-GB at level 0, P1 against P2: My_pin
#: 1.7 % apart at 0.3, 2.4 % at 0.45, 4.3 % at 0.49; ZS 0.29 / 0.40 / 0.72 mm)
LOCKING_POISSON = 0.45
#: the least penalty factor a line grid is run at unwarned (1-GB at level 0, line grid:
#: My_pin 224.1 N m at factor 1 against 213.3 at 1e6; it converges like 1 / factor)
PENALTY_FACTOR_USUAL = 10.0
#: the share of the results the PSD projection of the body correction may move unwarned
#: (issue 54: a guarded fallback warns above 0.1 %)
CLIP_EFFECT_LIMIT = 1e-3
BEARING_LENGTH_MM = (2.0, 200.0)  # sqrt(12 k_tilt / k_r)
NOMINAL_CONTACT_STRESS_MPA = (100.0, 2600.0)  # sigma_H0 of a mesh, K factors 1
MODIFICATION_USUAL_UM = 100.0


def input_warnings(study) -> list[str]:
    """Warnings for inputs outside the range seen in practice (module docstring): the
    length the bearing's two stiffnesses imply, the torque, the flank modifications, a
    Poisson ratio linear elements lock at and a line grid's soft penalty."""
    return (
        _bearing_warnings(study)
        + _torque_warnings(study)
        + _modification_warnings(study)
        + _locking_warnings(study)
        + _penalty_warnings(study)
    )


def _penalty_warnings(study) -> list[str]:
    num = study.numerics
    if num.contact_model != "line" or num.penalty_factor >= PENALTY_FACTOR_USUAL:
        return []
    return [
        f"{study.name}: numerics.penalty_factor = {num.penalty_factor:g} on the line grid: its "
        "penalty springs add a compliance of about 1/factor of the bodies' to every contact, "
        f"which moves the moments and centroids by per cents; use {PENALTY_FACTOR_USUAL:g} "
        "or more (the default is 100)"
    ]


def _locking_warnings(study) -> list[str]:
    nu = study.material.poisson_ratio
    if study.numerics.degree != 1 or nu <= LOCKING_POISSON:
        return []
    return [
        f"{study.name}: material.poisson_ratio = {nu:g} with numerics.degree = 1: linear "
        "tetrahedra lock as the Poisson ratio nears 0.5 (the bodies too stiff in volume "
        "change), which moves the moments and centroids beyond the convergence study's ±; "
        f"above {LOCKING_POISSON:g} set degree = 2"
    ]


def _torque_warnings(study) -> list[str]:
    gs = study.gearset
    torques = driver_torques(gs)
    lo, hi = NOMINAL_CONTACT_STRESS_MPA
    out = []
    for m in gs.meshes:
        pair = gs.pair(m.gear1, m.gear2)
        sigma = iso6336_pitch_contact_stress(pair, torques[(m.gear1, m.gear2)])["sigma_H0"]
        if not lo <= sigma <= hi:
            out.append(
                f"{study.name}: input_torque = {gs.input_torque:g} N m in the gear set gives the "
                f"{m.gear1}-{m.gear2} mesh a nominal contact stress sigma_H0 = {sigma:.0f} MPa "
                f"(ISO 6336-2, K factors 1), outside the usual {lo:g}-{hi:g} MPa of steel "
                "gears: is the torque in N m on the sun, all branches together?"
            )
    return out


def _modification_warnings(study) -> list[str]:
    out = []
    for gear, mods in sorted(study.gearset.modifications.items()):
        for f in ("lead_crown_um", "lead_slope_um", "tip_relief_um", "end_relief_um"):
            v = getattr(mods, f)
            if abs(v) > MODIFICATION_USUAL_UM:
                out.append(
                    f"{study.name}: [gears.{gear}.modifications] {f} = {v:g} um is above the "
                    f"{MODIFICATION_USUAL_UM:g} um of usual flank micro-geometry (5-60 um): "
                    "is it in um?"
                )
    return out


def _bearing_warnings(study) -> list[str]:
    out: list[str] = []
    b = study.bearing
    where = f"{study.name}: [bearing]"
    length = math.sqrt(12.0 * b.tilting_stiffness / b.radial_stiffness)
    lo, hi = BEARING_LENGTH_MM
    if not lo <= length <= hi:
        out.append(
            f"{where} tilting_stiffness = {b.tilting_stiffness:.4g} N mm/rad and "
            f"radial_stiffness = {b.radial_stiffness:.4g} N/mm imply a bearing "
            f"{length:.3g} mm long (sqrt(12 k_tilt / k_r); usually {lo:g}-{hi:g} mm, the "
            "paper's 21 mm): is one of them in another unit (N mm/rad, N/mm)?"
        )
    return out


def steel_equivalent_factor(study) -> float:
    """sqrt(E_steel / E_gear): turns the Hertz stress of the study's gear material into the
    stress the same line load gives on steel flanks (1 for steel)."""
    return math.sqrt(STEEL.youngs_modulus / study.material.gear_youngs_modulus)


def _severity(v: float) -> float:
    return math.inf if math.isnan(v) else v


def _worst(records: list[dict], key: str) -> dict[str, tuple[float, int]]:
    """Per entry of ``rec[key]`` (a mesh or a fillet): the largest value over the positions
    and its position index (a value that is not a number counts as the largest)."""
    worst: dict[str, tuple[float, int]] = {}
    for k, rec in enumerate(records):
        for name, v in (rec.get(key) or {}).items():
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                continue
            if name not in worst or _severity(float(v)) > _severity(worst[name][0]):
                worst[name] = (float(v), k)
    return worst


def plausibility_warnings(study, summary: dict) -> list[str]:
    """Warnings for ``summary`` (:func:`postprocess.summary.summarise`): contact and root
    stresses beyond their bounds, and top-level quantities that are not finite numbers."""
    out: list[str] = []
    records = summary.get("positions") or []
    factor = steel_equivalent_factor(study)
    for mesh, (p, k) in _worst(records, "contact_stress_mean_loaded").items():
        if not math.isfinite(p) or p * factor > CONTACT_STRESS_LIMIT_MPA:
            steel = f" ({p * factor:.4g} MPa steel-equivalent)" if factor != 1.0 else ""
            out.append(
                f"{study.name}: Hertz contact stress {p:.4g} MPa{steel} (mean over the loaded "
                f"points of the {mesh} mesh, position {k + 1}) is beyond "
                f"{CONTACT_STRESS_LIMIT_MPA:.0f} MPa, far above what a steel flank carries: "
                "the linear elastic model is outside its range; check input_torque (N m on "
                "the sun, all branches) in the gear set"
            )
    for key, (s, k) in _worst(records, "bending_stress").items():
        if not math.isfinite(s) or s > ROOT_STRESS_LIMIT_MPA:
            out.append(
                f"{study.name}: root stress {s:.4g} MPa ({key}, position {k + 1}) is beyond "
                f"{ROOT_STRESS_LIMIT_MPA:.0f} MPa, above the strength of any gear steel: the "
                "linear elastic model is outside its range; check input_torque (N m on the "
                "sun, all branches) and the face widths in the gear set"
            )
    moved = summary.get("contact_correction_clip_effect")
    if moved is not None and moved > CLIP_EFFECT_LIMIT:
        out.append(
            f"{study.name}: the zone model's FE body correction was indefinite and its "
            f"projection (solvers/contact.py eq. (6)) moves the contact forces or the "
            f"pinions' motion by {moved:.2%} (the largest over the positions), above "
            f"{CLIP_EFFECT_LIMIT:.1%}: the near/far-field match is not converged at this "
            "mesh, and the results carry an error of about that share beyond their ±"
        )
    for key, value in summary.items():
        if isinstance(value, float) and not math.isfinite(value):
            out.append(f"{study.name}: {key} = {value} is not a finite number")
    return out
