"""The motors and loads of the drive studies.

Values are per phase, star-equivalent, peak-valued (the convention of motulator and of the FOC
equations): ``psi_f`` is the peak phase flux linkage of the magnets, so the phase back-EMF peak is
``psi_f * n_p * w_m`` and the line-to-line peak is ``sqrt(3)`` times that.

Every value marked *assumed* could not be checked against the manufacturer's datasheet on this
machine (no internet access): it is the value Microchip's published motor-control firmware
parameter files use for that part, or follows from such values as stated. ``docs/drive.md`` shows
how the results move when they change.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

__all__ = ["HURST_DMA0204024B101", "HURST_REWOUND_X5", "MOTORS", "Load", "Motor"]


@dataclass(frozen=True)
class Motor:
    """A surface or interior PMSM with a stiff shaft.

    ``n_p`` pole pairs; ``R_s`` (ohm), ``L_d``, ``L_q`` (H), ``psi_f`` (Vs, peak phase flux);
    ``J`` (kg m^2) the rotor's inertia; ``B`` (Nm s/rad) viscous friction; ``tau_rated`` (Nm) and
    ``speed_rated`` (rpm) the rated point; ``u_dc`` (V) the nominal DC bus. ``notes`` says where
    each value comes from.
    """

    name: str
    n_p: int
    R_s: float
    L_d: float
    L_q: float
    psi_f: float
    J: float
    B: float
    tau_rated: float
    speed_rated: float
    u_dc: float
    notes: dict = field(default_factory=dict, compare=False)

    def __post_init__(self):
        for name in ("R_s", "L_d", "L_q", "psi_f", "J", "tau_rated", "speed_rated", "u_dc"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and value > 0 and math.isfinite(value)):
                raise ValueError(f"Motor.{name} must be a positive number, not {value!r}")
        if not (isinstance(self.n_p, int) and self.n_p >= 1):
            raise ValueError(f"Motor.n_p must be a positive integer, not {self.n_p!r}")
        if self.B < 0:
            raise ValueError(f"Motor.B must be >= 0, not {self.B!r}")

    @property
    def k_t(self) -> float:
        """Torque per ampere of peak q-axis current (Nm/A): ``1.5 n_p psi_f``."""
        return 1.5 * self.n_p * self.psi_f

    @property
    def i_rated(self) -> float:
        """Peak phase current at rated torque with i_d = 0 (A)."""
        return self.tau_rated / self.k_t

    def modulation_index(self, rpm: float, torque: float = 0.0) -> float:
        """Steady-state phase-voltage peak over Vdc at ``rpm`` and ``torque`` with i_d = 0
        (linear up to ``1/sqrt(3)`` = 0.577 with SVPWM or MDFQM)."""
        w_e = self.n_p * rpm * 2 * math.pi / 60
        i_q = torque / self.k_t
        u_d = -w_e * self.L_q * i_q
        u_q = self.R_s * i_q + w_e * self.psi_f
        return math.hypot(u_d, u_q) / self.u_dc

    def rewound(self, turns: float, name: str) -> Motor:
        """The same frame with ``turns`` times the winding turns in the same copper area: flux
        linkage x turns, R and L x turns^2, rated torque, speed and inertia unchanged."""
        k = float(turns)
        return replace(self, name=name, R_s=self.R_s * k * k, L_d=self.L_d * k * k,
                       L_q=self.L_q * k * k, psi_f=self.psi_f * k,
                       notes={**self.notes, "rewound": f"{name}: the Hurst frame with {k:g}x "
                              "the turns (psi_f x k, R and L x k^2)"})


_KE_LL_PER_KRPM = 7.24  # V peak line-to-line per 1000 rpm


HURST_DMA0204024B101 = Motor(
    name="Hurst DMA0204024B101 (Microchip AC300022, 24 V)",
    n_p=5,
    R_s=0.285,
    L_d=0.32e-3,
    L_q=0.32e-3,
    psi_f=_KE_LL_PER_KRPM / math.sqrt(3) / (1000 * 2 * math.pi / 60) / 5,
    J=17.7e-6,
    B=0.0,
    tau_rated=0.2,
    speed_rated=3000.0,
    u_dc=24.0,
    notes={
        "part": "Hurst (Nidec) DMA0204024B101, sold by Microchip as AC300022 for the dsPICDEM "
                "MCLV boards; datasheet revision not checked (no internet): every value assumed",
        "n_p": "5 pole pairs (Microchip firmware parameter files)",
        "R_s": "0.285 ohm per phase = 0.57 ohm line-to-line / 2 (Microchip files)",
        "L": "0.32 mH per phase = 0.64 mH line-to-line at 1 kHz / 2 (Microchip files); "
             "surface magnets, L_d = L_q assumed",
        "psi_f": f"from K_e = {_KE_LL_PER_KRPM} V peak line-to-line per krpm (Microchip files "
                 "quote 6.2-7.3)",
        "J": "17.7e-6 kg m^2 (as quoted from the datasheet by a third party)",
        "tau_rated": "0.2 Nm assumed (3.4 A rms bus current rating x K_t, rounded)",
        "speed_rated": "3000 rpm assumed (the firmware's top speed is 3500 rpm)",
        "B": "0: friction is in the load",
    },
)

#: The second motor: the Hurst frame with 5x the turns, so that 100-400 rpm at 0-100 % of rated
#: torque spans a modulation index of about 0.09-0.55 on the same 24 V bus (the paper's Table 3
#: range), where the Hurst motor itself stays below 0.14.
HURST_REWOUND_X5 = HURST_DMA0204024B101.rewound(5.0, "Hurst frame rewound with 5x turns (24 V)")

MOTORS = {"hurst": HURST_DMA0204024B101, "hurst_x5": HURST_REWOUND_X5,
          # the back-EMF constant is the assumption the switching counts depend on most: the
          # report repeats the paper's sweep with these two to show how far
          "hurst_x4": HURST_DMA0204024B101.rewound(4.0, "Hurst frame rewound with 4x turns"),
          "hurst_x6": HURST_DMA0204024B101.rewound(6.0, "Hurst frame rewound with 6x turns")}


@dataclass(frozen=True)
class Load:
    """Load torque on the shaft: ``tau_const + k_speed * w_m`` (Nm, ``w_m`` in rad/s) plus the
    load machine's inertia ``J`` (kg m^2).

    ``k_speed`` models the paper's load, a second PMSM feeding three resistors: its torque is
    proportional to speed. :meth:`generator` builds it from that machine's constants.
    """

    tau_const: float = 0.0
    k_speed: float = 0.0
    J: float = 0.0

    def torque(self, w_m: float) -> float:
        return self.tau_const + self.k_speed * w_m

    @staticmethod
    def generator(machine: Motor, r_load: float, J: float | None = None) -> Load:
        """A PMSM ``machine`` driven as a generator into a star of ``r_load`` ohm resistors:
        current ``n_p psi_f w / (R_s + r_load)`` (inductance neglected: the electrical time
        constant is far below the speed changes), torque ``1.5 n_p psi_f`` times that."""
        k = 1.5 * (machine.n_p * machine.psi_f) ** 2 / (machine.R_s + r_load)
        return Load(0.0, k, machine.J if J is None else J)
