"""The reference study's published figures, each once: every ``STUDY_*`` constant.

The study: Joynt, Nistor, Palermo & Stolle, 1:40 shipping-container debris carried by
a dam-break bore in a flume against a column (the Stolle et al. 2019 set-up). Each figure names
its section or table; the other modules (analytical and orchestrator) import them from here.
Figures the study does not print but that follow from its printed ones by arithmetic alone are
here too, with the arithmetic. Units: m, s, kg, N, N s, N/m.
"""

from __future__ import annotations

__all__ = [
    "STUDY_ARRIVALS",
    "STUDY_CONTAINER_SIZE_M",
    "STUDY_CONTAINER_WALL_M",
    "STUDY_DEBRIS_MASS_KG",
    "STUDY_DEBRIS_STIFFNESS_N_M",
    "STUDY_FIG7_RATIOS",
    "STUDY_IMPACT_COUNT",
    "STUDY_IMPACT_HEIGHTS_M",
    "STUDY_IMPACT_VELOCITY_M_S",
    "STUDY_MEAN_HEIGHT_M",
    "STUDY_STRUCTURE_STIFFNESS_N_M",
    "STUDY_TABLE1",
    "STUDY_TABLE1_FORCE_KD_N",
    "STUDY_TABLE1_FORCE_KS_N",
    "STUDY_TABLE1_MDOF",
    "STUDY_TABLE1_SDOF",
    "STUDY_TABLE1_UNDER",
    "STUDY_TABLE1_VELOCITY_M_S",
    "STUDY_TABLE2",
    "STUDY_TABLE2_MDOF",
    "STUDY_VELOCITY_M_S",
]

# ------------------------------------------------------------------------------ the flume

STUDY_ARRIVALS = {2.40: ("WG2", 0.91, 0.88), 3.20: ("WG3", 1.39, 1.20)}
"""The bore's arrival (its 4.1.2) by gauge position x (m): (gauge, experiment s, the study's
LS-DYNA model s)."""

STUDY_STRUCTURE_STIFFNESS_N_M = 4.685e5
"""Column stiffness k_s, N/m (study Sec. 3.2.1; bounds 4.653e5-4.701e5)."""

# ------------------------------------------------------------------------------ the debris

STUDY_DEBRIS_MASS_KG = 0.236
"""Mass of the 1:40 container debris, kg (study Sec. 3.1)."""

STUDY_CONTAINER_SIZE_M = (0.15, 0.06, 0.06)
"""The 1:40 20-ft container: length, width, height."""

STUDY_CONTAINER_WALL_M = 0.005
"""Its polyethylene wall thickness."""

STUDY_IMPACT_COUNT = 22
"""The study's impacts behind Table 2 (its section 3.1: 22 single-debris experiments
at 0.40 m inundation kept)."""

STUDY_IMPACT_HEIGHTS_M = (0.16, 0.50, 0.40)
"""Lowest, highest and mean impact height on the column (the water surface at its face): the study's
MDOF fit, load points from WG4 at the face (its load height "determined from the water surface
elevation at the face of the structure", m above the column's base)."""

STUDY_MEAN_HEIGHT_M = STUDY_IMPACT_HEIGHTS_M[2]
"""The mean load height, m."""

STUDY_IMPACT_VELOCITY_M_S = (1.60, 0.13)
"""Mean and standard deviation of the 22 impact velocities, backed out of Table 2's ASCE rows
(impulse = 2 C_o m u: 0.49 +- 0.04 N s with C_o = 0.65, m = 0.236 kg)."""

STUDY_VELOCITY_M_S = (1.59, 0.13)
"""Impact velocities implied by Table 2's ASCE rows read through the force (F = 0.65 u sqrt(k_s m)), m/s."""

# ------------------------------------------------------------------------------ Table 1

STUDY_TABLE1 = {
    "ASCE 7-22, k_d": (822.34, 0.0006, 0.46),
    "ASCE 7-22, k_s": (322.83, 0.0014, 0.46),
    "SDOF fit": (471.49, 0.0030, 0.91),
    "MDOF fit": (236.93, 0.0047, 0.71),
}
"""Table 1 (its Fig. 4b event, u = 1.50 m/s): magnitude N, duration s, impulse N s."""

STUDY_TABLE1_VELOCITY_M_S = 1.50
"""Measured impact velocity of the study's Figure 4 / Table 1 event, m/s (as printed)."""

STUDY_TABLE1_FORCE_KS_N = STUDY_TABLE1["ASCE 7-22, k_s"][0]
"""The study's Table 1, 'ASCE 7-22 using k_s' magnitude, N."""

STUDY_TABLE1_FORCE_KD_N = STUDY_TABLE1["ASCE 7-22, k_d"][0]
"""The study's Table 1, 'ASCE 7-22 using k_d' magnitude, N."""

STUDY_TABLE1_SDOF = STUDY_TABLE1["SDOF fit"][:2]
"""Table 1's SDOF pulse (magnitude N, duration s)."""

STUDY_TABLE1_MDOF = STUDY_TABLE1["MDOF fit"][:2]
"""Table 1's MDOF pulse (magnitude N, duration s)."""

STUDY_TABLE1_UNDER = {"sdof": 0.40, "mdof": 0.087}
"""Its Fig. 4 comparison on that event: its SDOF fit's response under the measured peak by 40 %,
its MDOF fit's by 8.7 % (section 3.3)."""

STUDY_DEBRIS_STIFFNESS_N_M = STUDY_STRUCTURE_STIFFNESS_N_M * (STUDY_TABLE1_FORCE_KD_N / STUDY_TABLE1_FORCE_KS_N) ** 2
"""Debris stiffness k_d the study used, N/m (about 3.040e6), backed out from its Table 1.

The study takes k_d and k_s from Stolle et al. (2019) without printing k_d. Both Table 1 ASCE
rows use the same u, m_d, I_tsu and C_o, so their magnitudes are in the ratio
``F(k_d)/F(k_s) = sqrt(k_d/k_s)`` whatever u and m_d are: 822.34 / 322.83 = 2.5473, hence
``k_d = k_s * 2.5473^2 = 6.4887 k_s = 3.040e6 N/m``. The Table 2 means give the same ratio
(875.25 / 343.60 = 2.5473).

Note: with u = 1.50 m/s exactly, the k_s row comes out 324.2 N, 0.43 % above the printed
322.83 N: the printed row corresponds to u = 1.4936 m/s (the velocity was presumably rounded to
1.50 in the text). Durations (0.0014 s, 0.0006 s) and impulses (0.46 N s) agree to the printed
digits either way.
"""

# ------------------------------------------------------------------------------ Table 2, Fig. 7

STUDY_TABLE2 = {
    "asce_kd": {"magnitude_N": (875.25, 70.22), "duration_s": (0.0006, 0.0000), "impulse_Ns": (0.49, 0.04)},
    "asce_ks": {"magnitude_N": (343.60, 27.57), "duration_s": (0.0014, 0.0000), "impulse_Ns": (0.49, 0.04)},
    "sdof": {"magnitude_N": (333.96, 106.94), "duration_s": (0.0026, 0.0010), "impulse_Ns": (0.57, 0.32)},
    "mdof": {"magnitude_N": (171.07, 62.91), "duration_s": (0.0047, 0.0005), "impulse_Ns": (0.52, 0.22)},
}
"""Table 2 (mean, std) for each method: magnitude N, duration s, impulse N s."""

STUDY_TABLE2_MDOF = {"peak_force_N": STUDY_TABLE2["mdof"]["magnitude_N"], "duration_s": STUDY_TABLE2["mdof"]["duration_s"],
                    "impulse_Ns": STUDY_TABLE2["mdof"]["impulse_Ns"]}
"""Table 2's MDOF row: (mean, standard deviation) over its 22 impacts."""

STUDY_FIG7_RATIOS = {
    "sdof": (1.2, 2.1, 1.8),
    "mdof": (0.8, 1.1, 0.9),
    "asce_ks": (1.2, 4.4, 2.5),
    "asce_kd": (1.5, 5.8, None),
}
"""Fig. 7: peak modelled / peak measured base shear, (min, max, mean). For ASCE with k_d the study
prints "an average of 1.3 and ranges from 1.5 to 5.8": the mean cannot lie below the minimum, so
that mean is a typo in the study; only the range is kept."""
