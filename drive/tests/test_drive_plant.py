"""The plant against closed forms and against motulator (Aalto University's motor-drive
simulator) on the same motor, load and switching sequence; a deliberately wrong plant (phase
order swapped, back-EMF sign flipped) fails the same checks."""

import cmath
import functools
import math
from dataclasses import replace

import numpy as np
import pytest

from mdfqm_drive.motors import HURST_DMA0204024B101, HURST_REWOUND_X5, Load
from mdfqm_drive.plant import DcBus, Plant, ShootThroughError
from wrongplants import FlippedEmf, SwappedPhases

SALIENT = replace(HURST_REWOUND_X5, name="salient variant", L_q=1.6 * HURST_REWOUND_X5.L_d)


PLANTS = {"plant": Plant, "swapped phases": SwappedPhases, "flipped back-EMF": FlippedEmf}


# -------------------------------------------------------------------------------------------
# closed forms
# -------------------------------------------------------------------------------------------

def locked_rotor_error(cls) -> float:
    """Relative error of phase b's current against ``(2/3) Vdc / R (1 - e^(-t R / L))`` with leg
    b up, a and c down, the rotor locked at angle 0.4 rad, over 20 unequal steps; and of the
    torque that current makes on the rotor, ``1.5 n_p psi Im(i_ab e^(-j theta))``, ``i_ab`` along
    phase b's axis (``e^(j 2 pi / 3)``)."""
    m = HURST_DMA0204024B101
    theta = 0.4
    plant = cls(m, theta=theta)
    plant.speed_locked = True
    worst = 0.0
    t = 0.0
    for dt in np.linspace(1e-5, 2e-4, 20):
        plant.advance(dt, 0b010, 0b101)
        t += dt
        expect = (2 / 3) * m.u_dc / m.R_s * (1 - math.exp(-t * m.R_s / m.L_d))
        i_a, i_b, i_c = plant.phase_currents()
        tau = 1.5 * m.n_p * m.psi_f * (expect * cmath.exp(1j * (2 * math.pi / 3 - theta))).imag
        worst = max(worst, abs(i_b - expect) / expect, abs(i_a + expect / 2) / expect,
                    abs(i_c + expect / 2) / expect, abs(plant.torque() - tau) / expect)
    return worst


def short_circuit_error(cls, motor) -> float:
    """Relative error of the steady short-circuit current at a locked speed (the three lower
    switches on) against ``i_d = -w^2 L_q psi / D``, ``i_q = -w R psi / D``,
    ``D = R^2 + w^2 L_d L_q``, and of its braking torque."""
    w_m = 300 * 2 * math.pi / 60
    plant = cls(motor, w_m=w_m)
    plant.speed_locked = True
    plant.i_q = 1e-3  # any start: the transient decays
    for _ in range(4000):
        plant.advance(5e-5, 0b000, 0b111)
    w = motor.n_p * w_m
    d = motor.R_s ** 2 + w * w * motor.L_d * motor.L_q
    i_d = -w * w * motor.L_q * motor.psi_f / d
    i_q = -w * motor.R_s * motor.psi_f / d
    scale = math.hypot(i_d, i_q)
    tau = 1.5 * motor.n_p * (motor.psi_f * i_q + (motor.L_d - motor.L_q) * i_d * i_q)
    return max(abs(plant.i_d - i_d) / scale, abs(plant.i_q - i_q) / scale,
               abs(plant.torque() - tau) / abs(tau))


def coast_down_error(cls) -> float:
    """Every gate off at 200 rpm, no current (back-EMF below the bus): the shaft decelerates
    under the constant load torque alone, ``w(t) = w0 - tau_L t / J``."""
    m = HURST_DMA0204024B101
    load = Load(tau_const=0.01, J=m.J)
    w0 = 200 * 2 * math.pi / 60
    plant = cls(m, load, w_m=w0)
    for _ in range(100):
        plant.advance(1e-3, 0, 0)
    expect = w0 - 0.01 * 0.1 / (2 * m.J)
    return abs(plant.w_m - expect) / w0 + abs(plant.i_d) + abs(plant.i_q)


@pytest.mark.parametrize("name", list(PLANTS))
def test_closed_forms(name):
    cls = PLANTS[name]
    errors = {
        "locked rotor": locked_rotor_error(cls),
        "short circuit, surface": short_circuit_error(cls, HURST_REWOUND_X5),
        "short circuit, salient": short_circuit_error(cls, SALIENT),
        "coast down": coast_down_error(cls),
    }
    if cls is Plant:
        assert max(errors.values()) < 1e-9, errors
    else:
        assert max(errors.values()) > 1e-2, f"the wrong plant '{name}' passed: {errors}"


def test_shoot_through_and_bad_input_are_refused():
    plant = Plant(HURST_DMA0204024B101)
    with pytest.raises(ShootThroughError, match="legs 010"):
        plant.advance(1e-6, 0b011, 0b110)
    with pytest.raises(ValueError, match="dt"):
        plant.advance(-1.0, 0, 0)
    with pytest.raises(ValueError, match="R_s"):
        replace(HURST_DMA0204024B101, R_s=0.0)
    fast = Plant(HURST_REWOUND_X5, w_m=2000 * 2 * math.pi / 60)
    with pytest.raises(NotImplementedError, match="back-EMF"):
        fast.advance(1e-3, 0, 0)


def test_bus_charges_from_braking_when_the_source_cannot_take_current_back():
    """A diode-fed bus: the spinning motor short-circuited by the three lower switches, then
    every gate off (its current through the diodes into the bus: a boost) raises the bus above
    the source; a regenerative source holds it near the source's voltage."""
    m = HURST_REWOUND_X5
    peaks = {}
    for regenerative in (True, False):
        bus = DcBus(24.0, C=100e-6, r_source=0.05, regenerative=regenerative)
        plant = Plant(m, bus=bus, w_m=400 * 2 * math.pi / 60)
        plant.speed_locked = True
        peak = 0.0
        for _ in range(2000):
            plant.advance(20e-6, 0b000, 0b111)   # short: the current builds up
            plant.advance(20e-6, 0b000, 0b000)   # into the bus through the diodes
            peak = max(peak, plant.u_dc)
        peaks[regenerative] = peak
    assert peaks[True] < 24.5
    assert peaks[False] > 26.0


# -------------------------------------------------------------------------------------------
# against motulator
# -------------------------------------------------------------------------------------------

def switching_sequence(seed: int, steps: int):
    """A reproducible random sequence of ``(duration, upper, lower)`` with dead-time blanking:
    every leg change passes through 2 us with both of its switches off."""
    rng = np.random.default_rng(seed)
    seq = []
    up = 0b000
    for _ in range(steps):
        new = int(rng.integers(0, 8))
        changed = up ^ new
        if changed:
            seq.append((2e-6, up & ~changed, (~up & 7) & ~changed))
        seq.append((float(rng.uniform(5e-6, 60e-6)), new, ~new & 7))
        up = new
    return seq


@functools.cache
def motulator_run(motor, load, seq, w_m0, theta0):
    """The same motor, load and gate sequence through motulator's drive model (a constant
    bus; its blanking rule is the plant's)."""
    import motulator.drive.model as mm
    from motulator.common.model._simulation import Simulation, SolverCfg

    par = mm.SynchronousMachinePars(n_p=motor.n_p, R_s=motor.R_s, L_d=motor.L_d, L_q=motor.L_q,
                                 psi_f=motor.psi_f)
    machine = mm.SynchronousMachine(par)
    machine.state.theta_m = complex(theta0)
    mech = mm.MechanicalSystem(J=motor.J + load.J, B_L=motor.B + load.k_speed)
    mech.state.w_M = complex(w_m0)
    mech.set_external_load_torque(load.tau_const)
    conv = mm.VoltageSourceConverter(u_dc=motor.u_dc)
    drive = mm.Drive(machine, mech, conv, pwm=True)
    durations = np.array([d for d, _, _ in seq])

    def modulate(_sampling_period, _duty_ratios):
        q = np.array([[(up >> i) & 1 for i in range(3)] for _, up, _ in seq])
        b = np.array([[1 - ((up >> i) & 1) - ((lo >> i) & 1) for i in range(3)]
                      for _, up, lo in seq])
        return durations, q, b

    drive.modulate = modulate

    class OneShot:
        t = 0.0

        def get_enable(self):
            return True

        def __call__(self, mdl):
            return float(durations.sum()), np.zeros(3)

        def post_process(self):
            return None

    sim = Simulation(drive, OneShot(), show_progress=False,
                     cfg=SolverCfg(rtol=1e-9, atol=1e-9, max_step=2e-6))
    sim.simulate(t_stop=float(durations.sum()) * 0.999)
    return drive


@pytest.mark.parametrize("name", list(PLANTS))
def test_against_motulator(name):
    """Currents within 0.1 % of their peak and the speed within 0.01 % after 12 ms of random
    switching with dead times, for a surface and a salient motor (seen: 0.02 % and 0.0004 %).
    The tolerance: motulator integrates with RK45 at rtol 1e-9 and steps of 2 us at most; the
    plant is exact between edges at the interval's mid-point speed, which leaves the second-order
    error of the speed's change within an interval (an interval up to 60 us, the speed changing
    by up to 2 % within one here)."""
    cls = PLANTS[name]
    worst = {}
    for motor in (HURST_REWOUND_X5, SALIENT):
        load = Load(tau_const=0.05, k_speed=1e-3, J=motor.J)
        seq = tuple(switching_sequence(7, 400))
        w_m0, theta0 = 250 * 2 * math.pi / 60, 0.3
        ref = motulator_run(motor, load, seq, w_m0, theta0)
        plant = cls(motor, load, w_m=w_m0, theta=theta0)
        for dt, up, lo in seq[:-1]:
            plant.advance(dt, up, lo)
        # motulator stops at its last switching instant before t_stop: compare there
        remaining = ref.t0 - plant.t
        plant.advance(remaining, seq[-1][1], seq[-1][2])
        i_ref = complex(ref.machine.out.i_s_ab)
        peak = max(abs(i_ref), 1e-3)
        worst[motor.name] = (abs(plant.i_ab() - i_ref) / peak,
                             abs(plant.w_m - ref.mechanics.out.w_M) / w_m0)
    ok = all(i < 1e-3 and w < 1e-4 for i, w in worst.values())
    if cls is Plant:
        assert ok, worst
    else:
        assert not ok, f"the wrong plant '{name}' matched motulator: {worst}"


def test_cmath_conventions_match_motulator():
    """Space vector and phase order: the plant's ``phase_currents`` inverts motulator's
    ``abc2complex``."""
    from motulator.common.utils import abc2complex

    plant = Plant(HURST_DMA0204024B101, theta=1.1)
    plant.i_d, plant.i_q = 0.7, -1.3
    assert cmath.isclose(complex(abc2complex(np.array(plant.phase_currents()))), plant.i_ab(),
                         abs_tol=1e-12)
