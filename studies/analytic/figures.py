"""Figures of the analytical study (matplotlib, Agg backend: no display needed).

* ``fig6_misalignment.png``: singh2007 Fig. 6, LOA moment of the double pinion over the
  single pinion value against the included triangle angle (theta for sun-SP, phi for
  RP-ring), case 2 pressure angles, worst points and the case 2-B geometry marked.
* ``pust_stability.png``: pust2016, lowest eigenvalue W1^2 of the floating sun against the
  sun support stiffness k3, from the stated parameters and from the identified sun mass,
  with the printed Table 1 points.
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from gears.analytic import parametric, printed
from gears.analytic import radial_stiffness as rs


def fig6_misalignment(tables: dict, path: Path) -> Path:
    """LOA moment ratio (double / single pinion) vs included angle for both meshes."""
    meshes = tables["parametric"]["case2"]
    angles = np.linspace(0.0, 180.0, 721)
    fig, ax = plt.subplots(figsize=(7.0, 4.5))
    styles = {
        "sun_SP": ("M$_{SP-SUN}$ LOA vs $\\theta$", parametric.m_sp_sun_loa, "C0"),
        "RP_ring": ("|M$_{RP-RING}$| LOA vs $\\phi$", parametric.m_rp_ring_loa, "C3"),
    }
    for mesh, (label, curve, colour) in styles.items():
        m = meshes[mesh]
        a = math.radians(m["pressure_angle"])
        single = parametric.single_equivalent(a, 1.0)
        ratio = curve(np.radians(angles), a, 1.0) / single
        ax.plot(angles, ratio, color=colour, label=f"{label} (a = {m['pressure_angle']:.2f}°)")
        ax.plot(m["worst_angle"], m["worst_ratio"], "o", color=colour)
        ax.annotate(
            f"worst {m['worst_ratio']:.2f} at {m['worst_angle']:.1f}°",
            (m["worst_angle"], m["worst_ratio"]),
            textcoords="offset points",
            xytext=(6, 6),
            fontsize=8,
        )
        ax.plot(m["operating_angle"], m["operating_ratio"], "s", color=colour, mfc="none")
        ax.annotate(
            f"case 2-B {m['operating_ratio']:.2f} at {m['operating_angle']:.1f}°",
            (m["operating_angle"], m["operating_ratio"]),
            textcoords="offset points",
            xytext=(10, -16) if mesh == "sun_SP" else (-60, -30),
            fontsize=8,
        )
    ax.axhline(1.0, color="0.5", lw=0.8, ls="--", label="single pinion")
    ax.set_xlim(0, 180)
    ax.set_xticks(np.arange(0, 181, 30))
    ax.set_xlabel("included angle at the pinion centre (deg)")
    ax.set_ylabel("LOA moment / single pinion value")
    ax.set_ylim(-0.05, 2.1)
    ax.set_title("singh2007 Fig. 6: double pinion LOA moment / single pinion value")
    ax.grid(True, lw=0.4)
    ax.legend(fontsize=8, loc="lower center")
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def pust_stability(tables: dict, path: Path) -> Path:
    """W1^2 vs sun support stiffness: stated parameters, identified m3, printed points."""
    p = tables["pust"]
    st = p["stated"]
    m3_id = p["identified"]["m3"]
    k3 = np.linspace(0.0, 25_000.0, 251)
    fig, ax = plt.subplots(figsize=(7.0, 4.5))
    for m3, label, style in (
        (st["m3"], f"stated parameters (m3 = {st['m3']:g} kg)", "C0-"),
        (m3_id, f"identified m3 = {m3_id:g} kg, rest as stated", "C1--"),
    ):
        w1 = [rs.floating_sun_eigenvalues(st["m2"], m3, st["k_c"], k, st["k_r"])[0] for k in k3]
        ax.plot(k3 / 1e3, w1, style, label=label)
    ax.plot(
        [r["k3"] / 1e3 for r in printed.PUST_TABLE1],
        [r["omega1_sq"] for r in printed.PUST_TABLE1],
        "kx",
        ms=8,
        label="pust2016 Table 1 (printed)",
    )
    ax.axhline(0.0, color="0.5", lw=0.8)
    ax.axvline(p["threshold_k3"] / 1e3, color="0.5", lw=0.8, ls=":")
    ax.annotate(
        f"W1² = 0 at k3 = k_r (k_c + k_r) / k_c = {p['threshold_k3']:.0f} N/m",
        (p["threshold_k3"] / 1e3, 0.0),
        textcoords="offset points",
        xytext=(6, -30),
        fontsize=8,
    )
    ax.set_xlabel("sun support stiffness k3 (kN/m)")
    ax.set_ylabel("lowest eigenvalue W1² ((rad/s)²)")
    ax.set_title("Floating sun, one planet branch (pust2016): W1² < 0 is unstable")
    ax.grid(True, lw=0.4)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path
