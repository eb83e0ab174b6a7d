"""Planet phasing from the all-planet quasi-static FE (parker2000): harmonics of the net sun
force and torque over one mesh cycle, against the rules of :mod:`gears.analytic.phasing`.

Positions k = 0 .. M-1 step the sun through one tooth pitch, roll_k = k p / M (p = 2 pi /
Z_sun), the carrier held. Harmonic l of a sampled signal x_k (the DFT, exact for l < M / 2
when x has no harmonic above M - l)::

    c_l = (1 / M) sum_k x_k exp(-2 pi i l k / M),   A_l = |c_l| + |c_-l|

A_l is the peak value of the l-th harmonic: 2 |c_l| for a scalar, the semi-major axis of the
ellipse the l-th harmonic of a force vector (F_x + i F_y) draws.

Two views of each mesh, per planet i (sun mesh s, ring mesh r; F_bt the transverse normal
force, t_i the transverse unit normal, sun -> planet):

* the FE as solved: the sun torque is a load and the sun's centre is held, so the net sun
  torque is the applied torque at every position (no torque harmonic; the rotational
  response is the static transmission error, TE = r_b,sun theta_sun) and the net sun force
  F_net = -sum_i F_bt,i t_i is the reaction of the sun's support. The mesh forces change only
  as the planets share the load: in phase (3 planets, Zs = 27) they share it equally at
  every position and each mesh force is constant.
* the mesh-force excitation: the force each mesh would carry at its mean deflection,
  F~_i(t) = k_i(t) mean(delta_i), with k_i = F_bt,i / delta_i the mesh's secant stiffness
  (bore to bore, :func:`studies.radial_stiffness.fe.mesh_approach`). This is the
  parametric excitation a dynamic model is driven by (parker2000's mesh forces, without the
  response); its net force -sum_i F~_i t_i and net torque r_b,sun sum_i F~_i are what
  parker2000's rules are about, each mesh contributing its own FE waveform.

For each harmonic the report gives the rule (k = mod(l Zs, N) for equally spaced planets,
the parity of l Zs for opposed pairs), the phasor sums of the planet angles ((S- + S+) / 2N
for the force, T / N for the torque: what A_l(net) / sum_i A_l(mesh i) is when every mesh has
the same waveform, 0 = cancelled, 1 = all in phase), and the FE's reinforcement ratio
A_l(net) / sum_i A_l(mesh i) beside them. A harmonic counts as vanished when its FE amplitude
is below ``VANISH_TOL`` of that scale (the excitation), ``SOLVED_TOL`` of the mean mesh force
(the solved net force) or ``TE_TOL`` of the mean TE (the solved TE).

Aliasing: bin l of M samples holds the harmonics l, M - l, M + l, ... For N planets in phase
(k = 0 for every l) every harmonic vanishes from the force, so the zeros are alias-proof; for
opposed pairs l and M +- l have the same parity when M is even, so the rule's zeros are too.
The sizes of the non-zero bins are not: a stiffness that steps between single and double
tooth contact has harmonics far above M / 2, which fold into the bins with the phasor sums of
their own harmonic numbers.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from gears.analytic import phasing
from postprocess.run_scalars import level_text
from studies.radial_stiffness.fe import mesh_approach

#: a harmonic has vanished below this fraction of its scale: the excitation's net amplitude
#: against the sum of the single-mesh amplitudes; the solved net force against the single
#: mesh's mean force. Level-0 meshes are not the same tooth to tooth (each body is meshed
#: once, not by rotation), which leaves about 1e-3 of the mesh force between planets that
#: symmetry makes equal; the rules' non-zero harmonics are above 1e-1 of their scale.
VANISH_TOL = 0.02
SOLVED_TOL = 2e-3  # of the mean mesh force, for the net force as solved
TE_TOL = 1e-3  # of the mean TE, for the TE harmonics as solved


def position_record(position: dict, gearset) -> dict:
    """What the phasing analysis needs from one solved all-planet position (JSON-ready)."""
    sun = gearset.gears[gearset.power_path[0]]
    rig = position["rigid"]
    theta = rig[f"{gearset.power_path[0]}_rotation"]
    planets = []
    for b in position["branches"]:
        row = {"pinion": b["pinion"], "angle_deg": b["angle_deg"]}
        for key, mesh in (("sun", b["mesh_S"]), ("ring", b["mesh_R"])):
            m = position["meshes"][mesh]
            n = np.asarray(m["normal"], float)
            nt = float(np.linalg.norm(n[:2]))
            row[key] = {
                "mesh": mesh,
                "normal_force_N": m["normal_force_N"],
                "transverse_force_N": m["normal_force_N"] * nt,
                "direction": (n[:2] / nt).tolist(),
                "approach_mm": mesh_approach(position, mesh),
                "active_points": m["active_points"],
            }
        Q = np.asarray(position["pinions"][b["pinion"]]["frame"], float)
        row["bearing_force_N"] = (Q.T @ np.asarray(b["pinion_force_N"], float))[:2].tolist()
        planets.append(row)
    coast = position.get("coast") or {}
    return {
        "roll": position["roll"],
        "coast_force_N": float(sum(c["normal_force_N"] for c in coast.values())),
        "te_um": theta * sun.base_radius * 1e3,
        "sun_contact_torque_Nm": position["sun_contact_torque_Nm"],
        "ring_support_torque_Nm": position["ring_support_torque_Nm"],
        "planets": planets,
        "dofs": position["dofs"],
        "wall_s": position["timings"]["wall"],
    }


def harmonics(x) -> np.ndarray:
    """A_l, l = 0 .. M // 2 (module docstring); ``x`` (M,) real, (M, 2) a vector (x, y) or
    (M,) complex. A_0 is the mean (its size for a vector)."""
    x = np.asarray(x)
    if x.ndim == 2:
        x = x[:, 0] + 1j * x[:, 1]
    m = len(x)
    c = np.fft.fft(x) / m
    out = np.empty(m // 2 + 1)
    out[0] = abs(c[0])
    for ell in range(1, m // 2 + 1):
        out[ell] = abs(c[ell]) + (abs(c[-ell]) if 2 * ell != m else 0.0)
    return out


def signals(records: list[dict], r_b_sun: float) -> dict:
    """Time series (one value per position) of the solved FE and the mesh-force excitation."""
    n = len(records[0]["planets"])
    out: dict = {"te_um": np.array([r["te_um"] for r in records])}
    out["sun_torque_Nm"] = np.array([r["sun_contact_torque_Nm"] for r in records])
    for key in ("sun", "ring"):
        f = np.array([[p[key]["transverse_force_N"] for p in r["planets"]] for r in records])
        t = np.array([[p[key]["direction"] for p in r["planets"]] for r in records])
        dlt = np.array([[p[key]["approach_mm"] for p in r["planets"]] for r in records])
        k = f / dlt
        exc = k * dlt.mean(axis=0)[None, :]
        sgn = -1.0 if key == "sun" else 1.0  # force on the sun (driver) / on the ring (driven)
        out[f"{key}_mesh_force_N"] = f
        out[f"{key}_mesh_stiffness_N_per_um"] = k * 1e-3
        out[f"{key}_excitation_N"] = exc
        out[f"{key}_net_force_N"] = sgn * np.einsum("ki,kij->kj", f, t)
        out[f"{key}_net_excitation_N"] = sgn * np.einsum("ki,kij->kj", exc, t)
    out["sun_excitation_torque_Nm"] = out["sun_excitation_N"].sum(axis=1) * r_b_sun * 1e-3
    bear = np.array([[p["bearing_force_N"] for p in r["planets"]] for r in records])
    out["carrier_net_force_N"] = bear.sum(axis=1)
    out["planets"] = n
    return out


def analyse(records: list[dict], zs: int, psi_deg, r_b_sun: float, l_max: int) -> dict:
    """Harmonic tables l = 1 .. l_max of the solved FE and of the excitation, with the
    rules and phasor sums of the planet angles (module docstring)."""
    s = signals(records, r_b_sun)
    n = s["planets"]
    psi = np.radians(np.asarray(psi_deg, float))
    rules = phasing.harmonic_table(zs, psi, l_max)
    mean_force = float(s["sun_mesh_force_N"].mean())
    mean_te = float(s["te_um"].mean())
    h = {
        key: harmonics(s[key])
        for key in (
            "te_um",
            "sun_torque_Nm",
            "sun_net_force_N",
            "ring_net_force_N",
            "carrier_net_force_N",
            "sun_net_excitation_N",
            "ring_net_excitation_N",
            "sun_excitation_torque_Nm",
        )
    }
    mesh_h = np.array([harmonics(s["sun_mesh_force_N"][:, i]) for i in range(n)])
    exc_h = np.array([harmonics(s["sun_excitation_N"][:, i]) for i in range(n)])
    exc_scale_t = r_b_sun * 1e-3
    rows = []
    for rule in rules:
        ell = rule["l"]
        single = float(exc_h[:, ell].sum())  # all planets in phase, force (N)
        row = {
            "l": ell,
            "rule": rule.get("rule"),
            "k": rule.get("k"),
            "rule_force": rule.get("rule_force", rule["force_nonzero"]),
            "rule_torque": rule.get("rule_torque", rule["torque_nonzero"]),
            "phasor_force": (rule["force_minus"] + rule["force_plus"]) / (2 * n),
            "phasor_torque": rule["torque"] / n,
            "solved": {
                "net_force_N": float(h["sun_net_force_N"][ell]),
                "mesh_force_N": mesh_h[:, ell].tolist(),
                "ring_net_force_N": float(h["ring_net_force_N"][ell]),
                "carrier_net_force_N": float(h["carrier_net_force_N"][ell]),
                "torque_Nm": float(h["sun_torque_Nm"][ell]),
                "te_um": float(h["te_um"][ell]),
            },
            "excitation": {
                "mesh_N": exc_h[:, ell].tolist(),
                "net_force_N": float(h["sun_net_excitation_N"][ell]),
                "ring_net_force_N": float(h["ring_net_excitation_N"][ell]),
                "torque_Nm": float(h["sun_excitation_torque_Nm"][ell]),
                "force_ratio": float(h["sun_net_excitation_N"][ell]) / single,
                "torque_ratio": float(h["sun_excitation_torque_Nm"][ell]) / (single * exc_scale_t),
            },
        }
        ex = row["excitation"]
        row["fe_force"] = ex["force_ratio"] > VANISH_TOL
        row["fe_torque"] = ex["torque_ratio"] > VANISH_TOL
        row["fe_solved_force"] = row["solved"]["net_force_N"] > SOLVED_TOL * mean_force
        row["fe_solved_te"] = row["solved"]["te_um"] > TE_TOL * mean_te
        row["agrees"] = (row["fe_force"] == row["rule_force"]) and (
            row["fe_torque"] == row["rule_torque"]
        )
        row["solved_agrees"] = (row["fe_solved_force"] == row["rule_force"]) and (
            row["fe_solved_te"] == row["rule_torque"]
        )
        rows.append(row)
    return {
        "planets": n,
        "r_b_sun_mm": r_b_sun,
        "planet_angles_deg": [float(a) for a in psi_deg],
        "mean_mesh_force_N": mean_force,
        "mean_te_um": float(s["te_um"].mean()),
        "mean_sun_torque_Nm": float(s["sun_torque_Nm"].mean()),
        "sun_torque_spread_Nm": float(np.ptp(s["sun_torque_Nm"])),
        "net_force_mean_N": float(h["sun_net_force_N"][0]),
        "mesh_force_ripple_rel": float(np.ptp(s["sun_mesh_force_N"], axis=0).max() / mean_force),
        "planet_stiffness_spread_rel": float(
            (
                np.ptp(s["sun_mesh_stiffness_N_per_um"], axis=1)
                / s["sun_mesh_stiffness_N_per_um"].mean(axis=1)
            ).max()
        ),
        "mesh_stiffness_ripple_rel": float(
            (
                np.ptp(s["sun_mesh_stiffness_N_per_um"], axis=0)
                / s["sun_mesh_stiffness_N_per_um"].mean(axis=0)
            ).max()
        ),
        "coast_force_max_N": max(
            (r["coast_force_N"] for r in records if "coast_force_N" in r), default=None
        ),
        "equilibrium_rel": float(
            np.abs(s["sun_net_force_N"] + s["ring_net_force_N"] + s["carrier_net_force_N"]).max()
            / mean_force
        ),
        "harmonics": rows,
        "all_agree": all(r["agrees"] and r["solved_agrees"] for r in rows),
        "series": {k: np.asarray(v).tolist() for k, v in s.items() if k != "planets"},
    }


# --- figures and report ---------------------------------------------------------------------


def figure_histories(result: dict, name: str, path: Path) -> Path:
    """Per planet: the sun-mesh force as solved and the mesh-force excitation, and the TE."""
    s = result["series"]
    f = np.asarray(s["sun_mesh_force_N"])
    e = np.asarray(s["sun_excitation_N"])
    m = f.shape[0]
    x = np.arange(m + 1) / m  # one cycle, closed
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.0))
    for i in range(f.shape[1]):
        lab = f"planet {i + 1} ({result['planet_angles_deg'][i]:.2f}°)"
        dev = (f[:, i] / f.mean() - 1) * 100
        axes[0].plot(x, np.r_[dev, dev[0]], "o-", ms=3, label=lab)
        axes[1].plot(x, np.r_[e[:, i], e[0, i]], "o-", ms=3, label=lab)
    te = np.asarray(s["te_um"])
    axes[2].plot(x, np.r_[te, te[0]], "o-", ms=3, color="k")
    lim = max(0.5, 1.1 * float(np.abs(f / f.mean() - 1).max()) * 100)
    axes[0].set_ylim(-lim, lim)
    axes[0].set_title(f"sun-mesh force as solved (torque held), mean {f.mean():.0f} N", fontsize=10)
    axes[1].set_title("mesh-force excitation k_i(t) mean(delta_i)", fontsize=10)
    axes[2].set_title("static transmission error r_b,sun theta_sun", fontsize=10)
    axes[0].set_ylabel("deviation from the mean mesh force (%)")
    axes[1].set_ylabel("N")
    axes[2].set_ylabel("um")
    for ax in axes:
        ax.set_xlabel("sun position (mesh cycles)")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle(f"{name}: mesh-force histories over one mesh cycle", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def figure_harmonics(result: dict, name: str, path: Path) -> Path:
    """Net sun force and torque of the excitation per harmonic, against a single mesh; the
    rule's non-zero harmonics marked."""
    rows = result["harmonics"]
    ls = np.array([r["l"] for r in rows])
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.0))
    single = np.array([max(r["excitation"]["mesh_N"]) for r in rows])
    for ax, key, rule, unit, scale in (
        (axes[0], "net_force_N", "rule_force", "N", 1.0),
        (axes[1], "torque_Nm", "rule_torque", "N m", None),
    ):
        net = np.array([r["excitation"][key] for r in rows])
        ref = single if scale else single * result["r_b_sun_mm"] * 1e-3
        ax.bar(ls - 0.18, ref, 0.36, color="0.7", label="one mesh (largest planet)")
        ax.bar(ls + 0.18, np.maximum(net, 1e-30), 0.36, color="C0", label="net, all planets")
        ax.set_yscale("log")
        ax.set_xticks(ls, [f"{r['l']}\n{_yes(r[rule])}" for r in rows])
        ax.set_xlabel("mesh harmonic l (parker2000 rule: 0 or ≠0)")
        ax.set_ylabel(f"amplitude ({unit})")
        ax.legend(fontsize=7, loc="upper right", framealpha=0.9)
    axes[0].set_title("net sun force of the mesh-force excitation", fontsize=10)
    axes[1].set_title("net sun torque of the mesh-force excitation", fontsize=10)
    fig.suptitle(
        f"{name}: harmonics over one mesh cycle ({len(result['series']['te_um'])} positions)",
        fontsize=11,
    )
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def discussion(data: dict) -> list[str]:
    """The closing discussion, from the numbers of every case."""
    out = ["## What the FE shows", ""]
    ok = all(c["all_agree"] for c in data["cases"].values())
    out.append(
        (
            "Every harmonic of every case is zero or non-zero as parker2000's rules say, "
            if ok
            else "**Some harmonics disagree with parker2000's rules (see the tables)**, "
        )
        + "in the mesh-force excitation (net force and torque) and in the FE as solved (net "
        "force on the held sun and transmission error)."
    )
    for name, c in data["cases"].items():
        rows = c["harmonics"]
        zero = [r for r in rows if not r["rule_force"]]
        live = [r for r in rows if r["rule_force"]]
        single = max(max(r["excitation"]["mesh_N"]) for r in rows)
        text = f"{name} ({c['planets']} planets): "
        if not live:
            worst = max(r["solved"]["net_force_N"] for r in zero)
            worst_e = max(
                r["excitation"]["net_force_N"] / max(r["excitation"]["mesh_N"]) for r in zero
            )
            text += (
                "the planets are in phase (Zs psi_i a whole number of mesh cycles), so under a "
                "held torque they share it equally at every position (mesh forces within "
                f"{c['mesh_force_ripple_rel']:.2%}) and the net sun force vanishes at every "
                f"instant, not only harmonic by harmonic: at most {worst:.2f} N per harmonic "
                f"against a single mesh's excitation of up to {single:.0f} N and a mean mesh "
                f"force of {c['mean_mesh_force_N']:.0f} N. The excitation's net force cancels to "
                f"{worst_e:.1%} of a single mesh's harmonic: the floor of this model, set by the "
                "level-0 meshes (each body is meshed once and its teeth differ, so planets that "
                f"symmetry makes equal differ by up to {c['planet_stiffness_spread_rel']:.2%} in "
                "mesh stiffness at one position). Every harmonic "
                "reaches the rotation: the excitation torques of the planets add in phase and "
                "the TE carries every harmonic."
            )
        else:
            f0 = max(r["solved"]["net_force_N"] for r in zero)
            f1 = min(r["solved"]["net_force_N"] for r in live)
            t1 = max(r["solved"]["te_um"] for r in live)
            t0 = min(r["solved"]["te_um"] for r in zero)
            text += (
                "the opposed pairs are half a mesh cycle apart for odd l Zs, so the pairs' "
                "forces cancel at the even harmonics and their torques at the odd ones. As "
                f"solved, the mesh forces change by up to {c['mesh_force_ripple_rel']:.1%} as the "
                f"load moves between the pairs; the net sun force has odd harmonics of at least "
                f"{f1:.0f} N and even ones of at most {f0:.1f} N; the TE has even harmonics of "
                f"at least {t0:.3f} um and odd ones of at most {t1:.3f} um (the rotation is "
                "excited only by the even harmonics, the translation only by the odd)."
            )
        out += ["", text]
    inp4 = [i for i in data["case_inputs"].values() if i["planet_angles_given_deg"]]
    out += [
        "",
        "Left out and caveats: the analysis is quasi-static with the sun torque held, so the "
        "net sun torque is the applied torque at every position and carries no harmonic; the "
        "rotational channel of the rules shows in the TE and in the excitation torque. The "
        "excitation F~_i = k_i(t) mean(delta_i) is our stand-in for parker2000's dynamic mesh "
        "forces (the mesh stiffness from the bores' rigid motions, both gear bodies included); "
        "no dynamic response is modelled. The sizes of the non-zero ratios differ from the "
        "phasor sums because the single/double-contact steps alias into the bins (module "
        "docstring); the zeros do not. The sun's centre is held (not floating): a floating sun "
        "would turn the odd-harmonic net force of the four-planet set into sun orbit and "
        "change the load sharing.",
    ]
    if inp4:
        i = inp4[0]
        out.append("")
        out.append(
            "Four planets: the angles "
            + "/".join(f"{a:g}" for a in i["planet_angles_given_deg"])
            + " deg are not assemblable for Zs + Zr = 126 (the scene's assembly check refuses "
            "91.4: the ring would be out of phase with branch 2); the nearest "
            "assemblable angles, "
            + "/".join(f"{a:.2f}" for a in i["planet_angles_deg"])
            + f" deg (moved by at most {i['largest_snap_deg']:.3f} deg), are still opposed pairs."
            " Without given angles the scene places the same paired layout itself "
            "(gears.analytic.phasing.planet_layout)."
        )
    return out


def _yes(b: bool) -> str:
    return "≠0" if b else "0"


def case_section(name: str, res: dict, inp: dict) -> list[str]:
    rows = res["harmonics"]
    n = res["planets"]
    lines = [
        f"## {name}: {n} planets at {', '.join(f'{a:.3f}' for a in res['planet_angles_deg'])} deg",
        "",
        f"{inp['description']}. {inp['positions']} positions over one sun tooth pitch, level "
        f"{level_text(inp)}, {inp['dofs']} DOFs, {inp['wall_s']:.0f} s per position. Mean sun-mesh"
        f" transverse force {res['mean_mesh_force_N']:.1f} N, mean TE {res['mean_te_um']:.2f} "
        f"um; sun contact torque {res['mean_sun_torque_Nm']:.3f} N m at every position (spread "
        f"{res['sun_torque_spread_Nm']:.1e} N m: the applied load). Equilibrium sun + ring + "
        f"carrier net force: {res['equilibrium_rel']:.0e} of the mesh force."
        + (
            f" Largest force on the coast flanks: {res['coast_force_max_N']:.2g} N."
            if res.get("coast_force_max_N") is not None
            else ""
        ),
        "",
        f"As solved: the sun-mesh forces vary by at most {res['mesh_force_ripple_rel']:.2%} of "
        "their mean over the cycle (load sharing between the planets), the mesh stiffness by "
        f"{res['mesh_stiffness_ripple_rel']:.0%} (single and double tooth contact).",
        "",
        "| l | rule | l Zs | net force: phasor / FE ratio | net torque: phasor / FE ratio | "
        "rule force / torque | FE force / torque | agrees | solved net sun force (N) | "
        "solved mesh force (N, planets) | TE (um) | solved force / TE | agrees |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    zs = inp["zs"]
    for r in rows:
        ex, so = r["excitation"], r["solved"]
        rule = r["rule"] or "-"
        if r["k"] is not None:
            rule += f", k = {r['k']}"
        lines.append(
            f"| {r['l']} | {rule} | {r['l'] * zs} | {r['phasor_force']:.3f} / "
            f"{ex['force_ratio']:.1e} | {r['phasor_torque']:.3f} / {ex['torque_ratio']:.3f} | "
            f"{_yes(r['rule_force'])} / {_yes(r['rule_torque'])} | {_yes(r['fe_force'])} / "
            f"{_yes(r['fe_torque'])} | {'yes' if r['agrees'] else '**no**'} | "
            f"{so['net_force_N']:.2f} | {', '.join(f'{v:.2f}' for v in so['mesh_force_N'])} | "
            f"{so['te_um']:.3f} | {_yes(r['fe_solved_force'])} / {_yes(r['fe_solved_te'])} | "
            f"{'yes' if r['solved_agrees'] else '**no**'} |"
        )
    return lines


def report(data: dict) -> str:
    """The markdown report of the phasing study (``data``: phasing.json)."""
    inp = data["inputs"]
    lines = [
        "# Planet phasing from the all-planet FE (parker2000)",
        "",
        f"Gear set {inp['gearset']}: spur planetary Zs {inp['zs']}, Zp {inp['zp']}, Zr "
        f"{inp['zr']}, module {inp['module']:g} mm, pressure angle {inp['pressure_angle']:g} deg,"
        f" face width {inp['face_width']:g} mm, sun torque {inp['torque_Nm']:g} N m (the "
        "reference gives only the tooth numbers; the rest is ours, see the gear-set file). "
        "Scene all_planets: every planet on its bearing to a rigid pin, full sun and ring, the "
        "sun's centre held and its rotation free under the torque, the ring held at its rim.",
        "",
        "How to read the tables (details in `studies/phasing/fe.py`). *FE ratio*: the net "
        "amplitude of the mesh-force excitation F~_i = k_i(t) mean(delta_i) over the sum of "
        "the single-mesh amplitudes (1: all planets in phase, 0: cancelled), beside the phasor "
        "sum of the planet angles (parker2000 with one waveform for all meshes). A harmonic is "
        f"non-zero (≠0) in the FE when that ratio exceeds {data['vanish_tol']:g}. The last "
        "three columns are the FE as solved: the net force on the held sun, each planet's "
        "sun-mesh force and the transmission error, per harmonic (peak values).",
        "",
    ]
    for name, res in data["cases"].items():
        lines += case_section(name, res, data["case_inputs"][name])
        lines += [
            "",
            f"![{name} histories]({name}_histories.png)",
            "",
            f"![{name} harmonics]({name}_harmonics.png)",
            "",
        ]
    lines += data.get("discussion", [])
    return "\n".join(lines)
